"""Into a multisampled 8-bit sRGB target the opaque pass writes the sRGB encoding from its
shader, with the device's own encoding turned off while it draws (rendering/passes/
forward.py, pipeline.shader_encoding_pays): the frames agree with the device's encoding
within a level, and the device encodes again for the passes after it (the glass in front
blends in linear light)."""
from __future__ import annotations

import numpy as np
import pytest

import scenerender
from scenerender.rendering.passes import forward
from scenerender.rendering.renderer import GraphRenderer, plan

LIT_AND_GLASS = """
render: {size: [160, 120], samples: 4, background: [0.3, 0.4, 0.6]}
camera: {position: [0.3, 1.3, 4.2], target: [0, 0.4, 0], fov: 45}
lights:
  - {type: point, position: [1.5, 3, 2], color: [1, 0.9, 0.8], shadows: {size: 256}}
  - {type: ambient, color: [0.1, 0.1, 0.12]}
materials:
  glass: {diffuse: [0.6, 0.85, 1.0], specular: [1, 1, 1], shininess: 200, opacity: 0.35}
objects:
  - {mesh: {primitive: plane, size: 6}, material: {diffuse: [0.7, 0.7, 0.7]}, cast_shadows: false}
  - {mesh: {primitive: sphere, radius: 0.5}, position: [0, 0.5, 0], material: {diffuse: [0.9, 0.3, 0.2], specular: [0.5, 0.5, 0.5], shininess: 40}}
  - {mesh: {primitive: box, size: [1.4, 0.9, 0.05]}, position: [0.5, 0.55, 1.3], material: glass}
"""


def frames(gl, **tuning) -> np.ndarray:
    world = scenerender.Scene.from_yaml(LIT_AND_GLASS).world
    renderer = GraphRenderer(world, gl, tuning=tuning)
    try:
        return renderer.render(0).pixels.astype(int)
    finally:
        renderer.release()


def assert_agree_with_the_device_encoding(gl):
    """Within 1 level everywhere: each sample is at most a level off (the device rounds
    the exact curve's value either way for about 7 % of values)."""
    difference = np.abs(frames(gl) - frames(gl, shader_srgb_encoding=False))
    assert difference.max() <= 1, (f"the shader's sRGB encoding against the device's: {difference.max()} levels "
                                    f"apart, {(difference > 1).mean():.2%} of values more than 1")


def test_shader_encoding_agrees_with_the_device_encoding(gl):
    assert_agree_with_the_device_encoding(gl)


def test_the_comparison_catches_the_encoding_done_twice(gl, monkeypatch):
    """Were the device's encoding left on while the shaders encode, every lit value would
    be encoded twice: the comparison above fails."""
    monkeypatch.setattr(forward, "GL_FRAMEBUFFER_SRGB", 0x0BD0)  # GL_DITHER: turning it off changes nothing
    with pytest.raises(AssertionError, match="the shader's sRGB encoding against the device's"):
        assert_agree_with_the_device_encoding(gl)


@pytest.mark.parametrize("samples, encoded", [(4, True), (1, False)])
def test_the_shader_encodes_only_a_multisampled_target(samples, encoded):
    """With one sample the device's encoding costs what the shader's does, and stays (the
    frames' bytes are those of before); the graph says which."""
    world = scenerender.Scene.from_yaml(LIT_AND_GLASS, overrides=[f"render.samples={samples}"]).world
    opaque = next(node.render_pass for node in plan(world, (160, 120), samples).compiled.passes
                  if node.render_pass.name == "opaque")
    assert opaque.encode_in_shader is encoded
    assert ("encoded by the shader" in opaque.describe()) is encoded
