"""The pbr model's specular term from rectangle and disk lights (linearly transformed
cosines, shaders/lighting/area.glsl) against the CPU reference: a light low over a glossy
metal floor (benchmarks/quality/scenes/area_highlight.yaml, metallic 1, so the floor is its
specular term alone), the mean of the floor where the reference's reflection is above a
quarter of its brightest. The representative point it replaced read 1.84x there."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

import scenerender
from scenerender.raytrace import render_reference
from scenerender.rendering.draw import LTC_TABLE

SCENE = Path(__file__).resolve().parent.parent / "benchmarks" / "quality" / "scenes" / "area_highlight.yaml"
METAL = ["objects[0].material.metallic=1", "objects[0].material.base_color=[0.9, 0.9, 0.9]", "render.size=[160, 120]"]
DISK = ["lights[0]={type: disk, position: [0, 1.0, -1.8], direction: [0, -0.35, 1], radius: 0.35, intensity: 8}"]


def test_the_table_is_what_the_shader_expects():
    table = np.load(LTC_TABLE)
    assert table.dtype == np.float32 and table.shape[2] == 6 and table.shape[0] >= 16
    assert np.isfinite(table).all()
    # the magnitude is a hemisphere integral of f cos with F = 1: at most 1; its Fresnel part
    # a share of it
    assert (table[:, :, 4] > 0.0).all() and (table[:, :, 4] <= 1.001).all()
    assert (table[:, :, 5] >= 0.0).all() and (table[:, :, 5] <= table[:, :, 4]).all()


@pytest.mark.parametrize("light", [[], DISK], ids=["rect", "disk"])
def test_a_glossy_reflection_of_an_area_light_matches_the_reference(gl, light):
    scene = scenerender.Scene.from_yaml(SCENE.read_text(), str(SCENE.parent), METAL + light)
    reference = render_reference(scene, 0, spp=4)
    with scenerender.Renderer(scene, gl=gl, want_linear=True) as renderer:
        gpu = renderer.render(0).linear[:, :, :3].astype(np.float64).mean(axis=2)
    ref = reference.linear.astype(np.float64).mean(axis=2)
    gpu, ref = ndimage.uniform_filter(gpu, 3), ndimage.uniform_filter(ref, 3)
    floor = ~reference.mixed & (reference.object == 0)
    reflection = floor & (ref > ref[floor].max() / 4.0)
    assert reflection.sum() > 100
    ratio = gpu[reflection].mean() / ref[reflection].mean()
    assert 0.92 < ratio < 1.08, ratio
    rest = floor & ~reflection
    assert 0.9 < gpu[rest].mean() / ref[rest].mean() < 1.1
