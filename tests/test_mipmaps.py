"""Mipmap levels made on the CPU: the sizes GL expects, means in linear light, every level
uploaded and sampled."""
from __future__ import annotations

import numpy as np
import pytest

from scenerender.colorspace import srgb_decode, srgb_encode
from scenerender.world import mipmaps
from scenerender.world.mipmaps import mip_chain

RNG = np.random.default_rng(7)


def _image(height, width):
    return RNG.integers(0, 256, size=(height, width, 4)).astype(np.uint8)


@pytest.mark.parametrize("shape, sizes", [
    ((8, 8), [(4, 4), (2, 2), (1, 1)]),
    ((4, 16), [(2, 8), (1, 4), (1, 2), (1, 1)]),
    ((9, 6), [(4, 3), (2, 1), (1, 1)]),
    ((1, 1), []),
])
def test_each_level_is_half_the_one_above_rounded_down(shape, sizes):
    assert [level.shape[:2] for level in mip_chain(_image(*shape), srgb=True)] == sizes


def test_an_even_level_is_the_two_by_two_mean_in_linear_light_exactly_rounded():
    image = _image(4, 4)
    level = mip_chain(image, srgb=True)[0]
    linear = srgb_decode(image[..., :3] / 255.0).reshape(2, 2, 2, 2, 3).mean(axis=(1, 3))
    assert np.array_equal(level[..., :3], np.rint(srgb_encode(linear) * 255.0).astype(np.uint8))
    alpha = image[..., 3].reshape(2, 2, 2, 2).mean(axis=(1, 3))
    assert np.abs(level[..., 3].astype(float) - alpha).max() <= 0.5


def test_black_and_white_average_to_mid_grey_in_light_not_in_code():
    image = np.zeros((2, 2, 4), np.uint8)
    image[0] = 255
    assert mip_chain(image, srgb=True)[0][0, 0, 0] == 188  # linear 0.5; averaging codes gives 128
    assert mip_chain(image, srgb=False)[0][0, 0, 0] == 128  # data maps (normals) average as stored


def test_odd_sides_keep_the_mean_and_constant_images_stay_constant():
    for shape in ((9, 6), (7, 13), (5, 1)):
        flat = np.full(shape + (4,), 77, np.uint8)
        assert all(np.all(level == 77) for level in mip_chain(flat, srgb=True))
        ramp = _image(*shape)
        mean = srgb_decode(ramp[..., 0] / 255.0).mean()
        half = mipmaps._halve(mipmaps._halve(mipmaps._to_linear(ramp, True), 0), 1)
        assert half[..., 0].mean() == pytest.approx(mean, rel=1e-5)  # area weights keep every texel's share


def test_large_levels_made_in_bands_are_the_same(monkeypatch):
    image = _image(64, 32)
    whole = mip_chain(image, srgb=True)
    monkeypatch.setattr(mipmaps, "_BAND_ROWS", 8)
    assert all(np.array_equal(a, b) for a, b in zip(whole, mip_chain(image, srgb=True)))


@pytest.mark.gl
def test_every_level_is_uploaded_and_sampled(gl):
    """The texture the renderer samples holds the CPU levels: texelFetch at each level
    returns them (decoded), so the texture is complete and no driver level replaced them."""
    from scenerender.gpu.textures import TextureCache

    image = _image(32, 16)
    texture = TextureCache(gl)._upload_2d(image, srgb=True)
    levels = mip_chain(np.ascontiguousarray(image[::-1]), srgb=True)
    program = gl.program(
        vertex_shader="#version 430\nvoid main() { gl_Position = vec4(vec2(gl_VertexID & 1, gl_VertexID >> 1) * 4.0 - 1.0, 0.0, 1.0); }",
        fragment_shader="#version 430\nuniform sampler2D t; uniform int level; out vec4 colour;\n"
                        "void main() { colour = texelFetch(t, ivec2(gl_FragCoord.xy), level); }")
    vao = gl.vertex_array(program, [])
    for index, expected in enumerate(levels, start=1):
        height, width = expected.shape[:2]
        target = gl.texture((width, height), 4, dtype="f4")
        fbo = gl.framebuffer([target])
        fbo.use()
        texture.use(0)
        program["t"], program["level"] = 0, index
        vao.render(vertices=3)
        got = np.frombuffer(target.read(), np.float32).reshape(height, width, 4)
        assert np.abs(got[..., :3] - srgb_decode(expected[..., :3] / 255.0)).max() < 2e-3
        fbo.release()
        target.release()
    texture.release()
