"""Bloom (render.bloom): the glow keeps the image's total linear light, spreads light
around a bright emitter, and a scene without it (or with strength 0) renders the bytes and
the graph it did before."""
from __future__ import annotations

import numpy as np
import pytest

import scenerender
from scenerender.raytrace.render import bloomed
from scenerender.rendering.passes.bloom import bloom_weights
from scenerender.rendering.renderer import plan

EMITTER = """
render: {size: [160, 120], background: [0.02, 0.02, 0.03]}
camera: {position: [0, 1.5, 5], target: [0, 0.5, 0]}
lights:
  - {type: directional, direction: [-1, -2, -1], intensity: 0.8}
objects:
  - mesh: {primitive: plane, size: [10, 10]}
  - mesh: {primitive: sphere}
    position: [0, 0.6, 0]
    scale: 0.4
    material: {diffuse: [0.1, 0.1, 0.1], emissive: [1, 0.75, 0.4], emissive_strength: 8}
"""


def _frame(gl, overrides=(), **options):
    scene = scenerender.Scene.from_yaml(EMITTER, ".", list(overrides))
    with scenerender.Renderer(scene, gl=gl, **options) as renderer:
        return renderer.render(0)


def test_the_weights_are_a_normalised_gaussian():
    weights = bloom_weights(4.0, 100).astype(np.float64)
    assert len(weights) == 13  # 3 standard deviations either side
    assert weights[0] + 2 * weights[1:].sum() == pytest.approx(1.0, abs=1e-6)
    assert np.all(np.diff(weights) < 0)
    assert len(bloom_weights(50.0, 20)) == 21  # never past the image (the mirror reflects once)


@pytest.mark.parametrize("bloom", ["{strength: 0.3, radius: 0.05}", "{strength: 1, radius: 0.2}"])
def test_bloom_keeps_the_total_linear_light_within_half_a_percent(gl, bloom):
    """The sum of the linear image (EXR values) with bloom is the sum without, within
    0.5 % (the 16-bit float targets round each value), though pixels change a lot."""
    plain = _frame(gl, want_linear=True).linear.astype(np.float64)
    bloomed = _frame(gl, [f"render.bloom={bloom}"], want_linear=True).linear.astype(np.float64)
    assert np.abs(bloomed - plain).max() > 0.1  # light did move
    assert bloomed.sum() == pytest.approx(plain.sum(), rel=0.005)
    assert np.allclose(bloomed.sum(axis=(0, 1)), plain.sum(axis=(0, 1)), rtol=0.005)  # and per channel


def test_bloom_brightens_the_dark_around_a_bright_emitter(gl):
    plain = _frame(gl).pixels.astype(int)
    bloomed = _frame(gl, ["render.bloom={strength: 0.2, radius: 0.03}"]).pixels.astype(int)
    above = (slice(46, 52), slice(74, 86))  # the dark background just above the sphere (rows 54-61)
    assert bloomed[above].mean() > plain[above].mean() + 5


def test_no_bloom_and_strength_0_render_the_bytes_and_graph_of_a_scene_without_the_key(gl):
    plain = _frame(gl).pixels
    assert np.array_equal(_frame(gl, ["render.bloom={strength: 0}"]).pixels, plain)
    assert np.array_equal(_frame(gl, ["render.bloom=null"]).pixels, plain)
    names = plan_names([])
    assert names == plan_names(["render.bloom={strength: 0}"])
    assert "bloom_mix" in plan_names(["render.bloom={strength: 0.1}"])


def plan_names(overrides) -> list[str]:
    world = scenerender.Scene.from_yaml(EMITTER, ".", list(overrides)).world
    return plan(world, world.settings.size, world.settings.samples).compiled.pass_names


def test_the_reference_blooms_like_the_gpu(gl):
    """The reference's NumPy bloom of the GPU's own linear image is the GPU's bloomed
    image within 16-bit float rounding (0.2 % of the brightest value)."""
    plain = _frame(gl, want_linear=True).linear.astype(np.float64)
    bloomed_gpu = _frame(gl, ["render.bloom={strength: 0.3, radius: 0.05}"], want_linear=True).linear
    expected = bloomed(plain, 0.3, 0.05)
    assert np.abs(bloomed_gpu - expected).max() < 0.002 * plain.max()
