"""KHR_materials_pbrSpecularGlossiness read as the metallic-roughness model with
KHR_materials_specular (mesh.gltf, docs/scene-notes.md "Layers of the pbr model"): the
conversion against the extension's own BRDF inputs, the effect, and the GPU against the
reference."""
from __future__ import annotations

import numpy as np
import pytest

import scenerender
from conftest import scene
from gltf_files import GlbBuilder, sphere, sphere_uv
from scenerender.colorspace import srgb_decode
from scenerender.raytrace import render_reference, shading
from scenerender.tools.quality import frame_errors
from pbr_glb_scene import glb_scene

SPECULAR_GLOSSINESS = "KHR_materials_pbrSpecularGlossiness"
GOLDISH = {"diffuseFactor": [0.5, 0.3, 0.2, 1.0], "specularFactor": [0.9, 0.6, 0.3], "glossinessFactor": 0.7}

SCENE = glb_scene()


def specular_glossiness_glb(path, values: dict | None, base: dict | None = None, textures: dict | None = None):
    """A sphere (radius 1) of one material: pbrMetallicRoughness ``base`` (a grey rough
    dielectric by default) and, unless ``values`` is None, the specular-glossiness extension
    with ``values``; ``textures``: {key: (H, W, 4) uint8 pixels} set on the extension."""
    builder = GlbBuilder()
    pbr = base or {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0.0, "roughnessFactor": 0.9}
    extensions = {}
    if values is not None:
        values = dict(values)
        for key, pixels in (textures or {}).items():
            values[key] = {"index": builder.texture(pixels)}
        extensions[SPECULAR_GLOSSINESS] = values
        builder.uses(SPECULAR_GLOSSINESS)
    material = builder.material(name="old", pbrMetallicRoughness=pbr, extensions=extensions)
    mesh = sphere(1.0, 4)
    builder.node(builder.mesh(builder.primitive(mesh, material, uv=sphere_uv(mesh))))
    return builder.write(path)


def _linear(gl, tmp_path):
    loaded = scene(SCENE, base_dir=tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        return renderer.render(0).linear[..., :3]


def _specification_brdf(n, l, v, diffuse, specular, glossiness):
    """(P, 3) pi f N.L of the extension's inputs, c_diff = diffuse (1 - max(specular)),
    F0 = specular, alpha = (1 - glossiness)^2, in glTF's BRDF (Appendix B): (1 - F) c_diff / pi
    + F D V, F = F0 + (1 - F0) (1 - V.H)^5."""
    c_diff = diffuse * (1.0 - specular.max())
    alpha = shading.pbr_alpha(np.full(len(n), 1.0 - glossiness))
    h = shading.safe_normalize(l + v)
    v_dot_h = np.clip(np.sum(v * h, axis=1), 0.0, 1.0)
    fresnel = specular + (1.0 - specular) * ((1.0 - v_dot_h) ** 5)[:, None]
    n_dot_l, n_dot_v = np.sum(n * l, axis=1), np.sum(n * v, axis=1)
    d = shading.ggx_distribution(np.clip(np.sum(n * h, axis=1), 0.0, 1.0), alpha)
    vis = shading.smith_visibility(n_dot_v, n_dot_l, alpha)
    return ((1.0 - fresnel) * c_diff / np.pi + fresnel * (d * vis)[:, None]) * np.pi * n_dot_l[:, None]


def test_the_conversion_gives_the_extensions_brdf_exactly(tmp_path):
    # the material read from the file, through the reference's BRDF, against the extension's
    # formula written out: equal to rounding (1e-12) over random directions
    specular_glossiness_glb(tmp_path / "model.glb", GOLDISH)
    material = scene(SCENE, base_dir=tmp_path).world.materials()[0]
    rng = np.random.default_rng(7)
    count = 500
    n = np.tile([0.0, 0.0, 1.0], (count, 1))
    l, v = rng.normal(size=(2, count, 3))
    l[:, 2], v[:, 2] = np.abs(l[:, 2]) + 0.05, np.abs(v[:, 2]) + 0.05
    l /= np.linalg.norm(l, axis=1, keepdims=True)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    f0, f90 = material.dielectric_f0_f90()
    layers = {"f0": np.tile(f0, (count, 1)), "f90": np.full(count, f90), "clearcoat": np.zeros(count),
              "clearcoat_roughness": np.zeros(count), "sheen_color": np.zeros((count, 3)),
              "sheen_roughness": np.zeros(count), "transmission": np.zeros(count)}
    base = np.tile(material.diffuse(0.0)[:3], (count, 1))
    converted = shading.pbr_direct_term(n, l, v, np.ones((count, 3)), base, np.full(count, material.metallic(0.0)),
                                        np.full(count, material.roughness(0.0)), layers)
    expected = _specification_brdf(n, l, v, np.array(GOLDISH["diffuseFactor"][:3]),
                                   np.array(GOLDISH["specularFactor"]), GOLDISH["glossinessFactor"])
    assert np.abs(converted - expected).max() < 1e-12
    assert expected.max() > 0.5  # a real highlight among the directions


def test_the_specular_colour_tints_the_highlight_and_glossiness_sharpens_it(gl, tmp_path):
    # metal-rough alone (a grey rough dielectric): a dim white highlight; the extension,
    # which takes the material's place: a bright, orange, narrow highlight
    specular_glossiness_glb(tmp_path / "model.glb", None)
    plain = _linear(gl, tmp_path)
    specular_glossiness_glb(tmp_path / "model.glb", {**GOLDISH, "diffuseFactor": [0, 0, 0, 1]})
    gold = _linear(gl, tmp_path)
    peak = np.unravel_index(np.argmax(gold[..., 0]), gold.shape[:2])
    assert gold[peak][0] > 3.0 * plain[..., 0].max()
    assert gold[peak][2] / gold[peak][0] == pytest.approx(0.3 / 0.9, rel=0.15)  # F0's colour near normal incidence
    assert (gold.mean(axis=2) > 0.5 * gold[peak].mean()).sum() < 60


def test_the_diffuse_texture_is_the_base_colour_texture(gl, tmp_path):
    half = np.zeros((8, 8, 4), np.uint8)
    half[..., 3] = 255
    half[:, :4, 0] = 255  # red on the left half of the texture, black on the right
    values = {"diffuseFactor": [1, 1, 1, 1], "specularFactor": [0.04, 0.04, 0.04], "glossinessFactor": 0.2}
    specular_glossiness_glb(tmp_path / "model.glb", values, textures={"diffuseTexture": half})
    material = scene(SCENE, base_dir=tmp_path).world.materials()[0]
    assert "diffuse_map" in material.maps
    image = _linear(gl, tmp_path)
    # u runs round the sphere from the back (-Z): the front's left (u < 0.5) is red, its right
    # black (the 8 texels' bilinear blend spans u 0.44 to 0.56, columns 44 to 58)
    assert image[36, 32, 0] > 5 * image[36, 32, 1] and image[36, 64, 0] < 0.2 * image[36, 32, 0]


def test_gpu_matches_the_reference(gl, tmp_path):
    # tolerances of the layers' comparison (tests/test_pbr_layers.py, the same scene)
    specular_glossiness_glb(tmp_path / "model.glb", GOLDISH)
    loaded = scenerender.Scene.from_yaml(SCENE, tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        frame = renderer.render(0)
    errors = frame_errors(render_reference(loaded, 0, spp=3), frame.pixels, frame.linear, with_flip=False)
    assert errors["rmse_linear"] < 1.5, errors
    assert errors["interior_rmse"] < 0.25, errors


def test_the_specular_glossiness_texture_gives_what_its_texel_as_factors_gives(gl, tmp_path):
    # one texel everywhere: specular (sRGB) 200, 150, 100 and glossiness 0.6 (alpha 153),
    # times the factors, against those products given as factors (whose conversion is the
    # extension's BRDF, above): within 1 of 255 (the GPU's sRGB decode and float32)
    texel = np.array([200, 150, 100, 153], np.uint8)
    values = {"diffuseFactor": [0.6, 0.5, 0.4, 1.0], "specularFactor": [0.9, 0.8, 0.7], "glossinessFactor": 0.9}
    specular_glossiness_glb(tmp_path / "model.glb", values, textures={
        "specularGlossinessTexture": np.tile(texel, (4, 4, 1))})
    textured = _linear(gl, tmp_path)
    products = {"diffuseFactor": values["diffuseFactor"],
                "specularFactor": [f * float(srgb_decode(t / 255.0)) for f, t in zip(values["specularFactor"], texel[:3])],
                "glossinessFactor": values["glossinessFactor"] * texel[3] / 255.0}
    specular_glossiness_glb(tmp_path / "model.glb", products)
    factors = _linear(gl, tmp_path)
    assert np.abs(textured - factors).max() < 0.005 * factors.max()
    assert factors.max() > 0.5


def test_gpu_matches_the_reference_with_a_specular_glossiness_texture(gl, tmp_path):
    ramp = np.round(255 * (np.arange(8) + 0.5) / 8).astype(np.uint8)
    pixels = np.zeros((8, 8, 4), np.uint8)
    pixels[..., 0], pixels[..., 1], pixels[..., 2] = ramp[None, :], 120, ramp[::-1][None, :]
    pixels[..., 3] = ramp[:, None]  # glossiness down the rows
    specular_glossiness_glb(tmp_path / "model.glb", GOLDISH, textures={"specularGlossinessTexture": pixels})
    loaded = scenerender.Scene.from_yaml(SCENE, tmp_path)
    assert "specular_glossiness_map" in loaded.world.materials()[0].maps
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        frame = renderer.render(0)
    errors = frame_errors(render_reference(loaded, 0, spp=3), frame.pixels, frame.linear, with_flip=False)
    assert errors["rmse_linear"] < 1.5, errors
    assert errors["interior_rmse"] < 0.25, errors
