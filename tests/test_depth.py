"""The camera passes' depth convention (scenerender.gpu.depth): reversed-Z float depth where
the device has clip control, the 24-bit fixed-point fallback elsewhere."""
from __future__ import annotations

import numpy as np
import pytest

from scenerender.gpu.depth import ENV_REVERSED_Z, DepthConvention, depth_convention
from scenerender.world.camera import orthographic, perspective

SCENE = """
render: {size: [96, 64], samples: 4}
camera: {position: [0, 2.5, 4], target: [0, 0.3, 0], fov: 50}
lights:
  - {type: directional, direction: [-0.4, -1, -0.3], shadows: true}
  - {type: ambient, color: [0.1, 0.1, 0.1]}
objects:
  - mesh: {primitive: plane, size: 6}
  - mesh: {primitive: box, size: 0.8}
    position: [0.5, 0.4, 0]
    outline: {color: [1, 0.5, 0], width: 0.02}
  - mesh: {primitive: sphere, radius: 0.4}
    position: [-0.8, 0.4, 0.3]
    material: {diffuse: [0.2, 0.4, 0.9], opacity: 0.5}
"""


@pytest.mark.parametrize("projection", [perspective(50.0, 1.5, 0.01, 2e5), orthographic(4.0, 1.5, 0.5, 30.0)])
def test_reversed_projection_puts_near_at_one_and_far_at_zero(projection):
    near, far = (0.01, 2e5) if projection[3, 3] == 0.0 else (0.5, 30.0)
    reversed_projection = DepthConvention(True).camera_projection(projection)
    for distance, expected in ((near, 1.0), (far, 0.0)):
        clip = reversed_projection @ np.array([0.3, -0.2, -distance, 1.0])
        assert clip[2] / clip[3] == pytest.approx(expected, abs=1e-9)
    # x, y and w are untouched: the image is the same
    assert np.array_equal(reversed_projection[[0, 1, 3]], projection[[0, 1, 3]])


def test_device_here_has_reversed_z_and_the_switch_turns_it_off(gl, monkeypatch):
    assert depth_convention(gl).reversed  # llvmpipe: GL 4.5
    monkeypatch.setenv(ENV_REVERSED_Z, "0")
    fallback = depth_convention(gl)
    assert not fallback.reversed and fallback.max_depth_ratio == 1e4 and fallback.depth_format == "depth24"


def test_fallback_renders_like_reversed_z(render_scene, monkeypatch):
    """Outline, transparency and MSAA drawn over the opaque depth: both conventions agree."""
    reversed_z = render_scene(SCENE)
    monkeypatch.setenv(ENV_REVERSED_Z, "0")
    fixed_point = render_scene(SCENE)
    difference = np.abs(reversed_z.astype(int) - fixed_point.astype(int))
    assert reversed_z.std() > 10
    assert difference.max() <= 2


def test_ambient_occlusion_shades_only_where_a_surface_was_drawn_in_both_conventions(render_scene, monkeypatch):
    """The AO pass draws its full-screen triangle on the far plane and depth-tests it against
    the prepass: the sky is left at 1 (open) without shading it, surfaces get occlusion.
    Clearing the prepass depth, or the test's direction flipped, leaves every pixel at 1."""
    overrides = ["render.mode=ambient_occlusion", "render.ambient_occlusion={radius: 0.5, samples: 8}",
                 "camera.position=[0, 1.2, 4]"]
    views = {}
    for reversed_z in ("1", "0"):
        monkeypatch.setenv(ENV_REVERSED_Z, reversed_z)
        views[reversed_z] = render_scene(SCENE, overrides)[..., 0].astype(int)
    for ao in views.values():
        sky = ao[:8]  # the camera looks over the plane's far edge
        assert (sky == 255).all()
        assert (ao < 200).sum() > 50  # creases where the box and sphere meet the plane
    assert np.abs(views["1"] - views["0"]).max() <= 2
