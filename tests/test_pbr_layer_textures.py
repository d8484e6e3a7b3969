"""The pbr layers' textures (docs/scene-notes.md, "Layers of the pbr model"): glTF's
clearcoatTexture, clearcoatRoughnessTexture, sheenColorTexture, sheenRoughnessTexture,
specularTexture, specularColorTexture, iridescenceTexture and iridescenceThicknessTexture
multiply or set their factors per pixel, and clearcoatNormalTexture bends the coat alone, on
the GPU (lighting/material.glsl, sample_layers) and in the reference, read through their
texCoord and KHR_texture_transform like any texture."""
from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

import scenerender
from conftest import scene
from gltf_files import GlbBuilder, sphere, sphere_uv
from scenerender.cli import main
from scenerender.raytrace import render_reference
from scenerender.rendering.features import material_defines
from scenerender.tools.quality import frame_errors
from pbr_glb_scene import glb_scene, render_glb

SCENE = glb_scene()

# (extension, its factors, the texture's key): each layer strong enough to see
TEXTURED = {
    "clearcoat": ("KHR_materials_clearcoat", {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.3},
                  "clearcoatTexture"),
    "clearcoat_roughness": ("KHR_materials_clearcoat", {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.6},
                            "clearcoatRoughnessTexture"),
    "sheen_color": ("KHR_materials_sheen", {"sheenColorFactor": [1.0, 0.9, 0.8], "sheenRoughnessFactor": 0.4},
                    "sheenColorTexture"),
    "sheen_roughness": ("KHR_materials_sheen", {"sheenColorFactor": [1.0, 1.0, 1.0], "sheenRoughnessFactor": 0.8},
                        "sheenRoughnessTexture"),
    "specular": ("KHR_materials_specular", {}, "specularTexture"),
    "specular_color": ("KHR_materials_specular", {"specularColorFactor": [1.5, 1.0, 0.5]}, "specularColorTexture"),
    "iridescence": ("KHR_materials_iridescence", {"iridescenceFactor": 1.0, "iridescenceIor": 1.8,
                                                  "iridescenceThicknessMaximum": 600}, "iridescenceTexture"),
    "iridescence_thickness": ("KHR_materials_iridescence", {"iridescenceFactor": 1.0, "iridescenceIor": 1.8,
                                                            "iridescenceThicknessMaximum": 600},
                              "iridescenceThicknessTexture"),
}


def gradient(channels_from: float = 0.0) -> np.ndarray:
    """(8, 8, 4) uint8: every channel (alpha too) rising from ``channels_from`` on the left to
    1 on the right, the same down each column."""
    ramp = channels_from + (1.0 - channels_from) * (np.arange(8) + 0.5) / 8.0
    return np.tile(np.round(ramp * 255).astype(np.uint8)[None, :, None], (8, 1, 4))


def textured_glb(path, extension: str, factors: dict, key: str | None, pixels: np.ndarray | None = None,
                 **texture_info):
    """A sphere of a dark-red dielectric (roughness 0.5) with ``extension``'s ``factors``
    and, where ``key`` is given, its texture of ``pixels`` (``texture_info`` added to the
    textureInfo, e.g. a KHR_texture_transform); texture set 1 is set 0 mirrored in u."""
    builder = GlbBuilder()
    values = dict(factors)
    if key is not None:
        values[key] = {"index": builder.texture(pixels), **texture_info}
    builder.uses(extension)
    pbr = {"baseColorFactor": [0.3, 0.05, 0.04, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5}
    material = builder.material(name="layered", pbrMetallicRoughness=pbr, extensions={extension: values})
    mesh = sphere(1.0, 4)
    uv = sphere_uv(mesh)
    primitive = builder.primitive(mesh, material, uv=uv)
    primitive["attributes"]["TEXCOORD_1"] = builder.accessor(np.column_stack([1.0 - uv[:, 0], uv[:, 1]]), "VEC2")
    builder.node(builder.mesh(primitive))
    return builder.write(path)


@pytest.mark.parametrize("name", list(TEXTURED))
def test_gpu_matches_the_reference_with_each_layer_texture(gl, tmp_path, name):
    # the layers' stated tolerances (tests/test_pbr_layers.py: linear RMSE of the image 1.5 %,
    # 2.5 % with a sheen, 0.25 % inside surfaces), a texture that rises across the sphere
    extension, factors, key = TEXTURED[name]
    textured_glb(tmp_path / "model.glb", extension, factors, key, gradient())
    loaded, frame = render_glb(gl, tmp_path)
    errors = frame_errors(render_reference(loaded, 0, spp=3), frame.pixels, frame.linear, with_flip=False)
    assert errors["rmse_linear"] < (2.5 if "sheen" in name else 1.5), errors
    assert errors["interior_rmse"] < 0.25, errors


@pytest.mark.parametrize("name", list(TEXTURED))
def test_each_texture_changes_the_picture_and_a_white_one_does_not(gl, tmp_path, name):
    # the factors alone; the same with a white texture: the same bytes (it multiplies by 1),
    # but for the specular colour, whose F0 is clamped after the texture (within 1 of 255);
    # with the gradient texture: a different picture
    extension, factors, key = TEXTURED[name]
    textured_glb(tmp_path / "model.glb", extension, factors, None)
    plain = render_glb(gl, tmp_path)[1].pixels
    textured_glb(tmp_path / "model.glb", extension, factors, key, np.full((4, 4, 4), 255, np.uint8))
    loaded, white = render_glb(gl, tmp_path)
    map_key = {"specular": "specular_factor"}.get(name, name) + "_map"
    assert f"HAS_{map_key.upper()}" in material_defines(loaded.world.materials()[0], "pbr")
    if name == "specular_color":
        assert np.abs(white.pixels.astype(int) - plain).max() <= 1
    else:
        assert np.array_equal(white.pixels, plain)
    textured_glb(tmp_path / "model.glb", extension, factors, key, gradient())
    varied = render_glb(gl, tmp_path)[1].pixels
    assert np.abs(varied.astype(int) - plain).max() > 10


def _coat_highlight(gl, tmp_path, pixels: np.ndarray, **texture_info) -> float:
    """The brightest linear value of a full coat (roughness 0.2) whose texture is ``pixels``,
    lit from the upper right: the coat's highlight lies at u 0.56 (x 0.35), 15 against the
    base's 0.66."""
    extension, factors, key = TEXTURED["clearcoat"]
    textured_glb(tmp_path / "model.glb", extension, {**factors, "clearcoatRoughnessFactor": 0.2}, key, pixels,
                 **texture_info)
    loaded = scenerender.Scene.from_yaml(SCENE.replace("[0.6, 0.8, 4]", "[2, 0.5, 3]"), tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        return float(renderer.render(0).linear[..., :3].mean(axis=2).max())


def test_the_coat_lies_where_its_texture_is_white_through_its_transform_and_texcoord(gl, tmp_path):
    # a texture white on its right half (u > 0.5) keeps the coat's highlight; white on its
    # left half removes it; KHR_texture_transform's offset 0.5 along u moves the left one
    # back over it (the pattern repeats); texCoord 1, set 1 mirrored in u, swaps them again
    right = np.zeros((4, 64, 4), np.uint8)
    right[:, 32:] = 255
    left = right[:, ::-1].copy()
    coated = _coat_highlight(gl, tmp_path, right)
    assert coated > 10.0
    assert _coat_highlight(gl, tmp_path, left) < 0.1 * coated
    assert _coat_highlight(gl, tmp_path, left, extensions={"KHR_texture_transform": {"offset": [0.5, 0]}}) \
        == pytest.approx(coated, rel=0.02)
    assert _coat_highlight(gl, tmp_path, left, texCoord=1) == pytest.approx(coated, rel=0.02)


def test_gpu_matches_the_reference_through_texcoord_1_and_a_transform(gl, tmp_path):
    extension, factors, key = TEXTURED["sheen_color"]
    textured_glb(tmp_path / "model.glb", extension, factors, key, gradient(), texCoord=1,
                 extensions={"KHR_texture_transform": {"offset": [0.2, 0], "rotation": 0.3, "scale": [1.5, 1]}})
    material = scene(SCENE, base_dir=tmp_path).world.materials()[0]
    assert material.maps["sheen_color_map"].uv_set == 1
    assert {"SHEEN_COLOR_MAP_UV1", "UV_AFFINE"} <= set(material_defines(material, "pbr"))
    loaded, frame = render_glb(gl, tmp_path)
    errors = frame_errors(render_reference(loaded, 0, spp=3), frame.pixels, frame.linear, with_flip=False)
    assert errors["rmse_linear"] < 2.5 and errors["interior_rmse"] < 0.25, errors


def test_the_scene_keys_set_the_same_maps_as_the_extensions(gl, tmp_path):
    # a gradient along u alone, so the two coordinate conventions read the same texels
    extension, factors, key = TEXTURED["clearcoat"]
    textured_glb(tmp_path / "model.glb", extension, factors, key, gradient())
    from_file = render_glb(gl, tmp_path)[1].pixels
    Image.fromarray(gradient()).save(tmp_path / "coat.png")
    textured_glb(tmp_path / "model.glb", extension, factors, None)
    text = SCENE.replace("  - mesh: model.glb", "  - {mesh: model.glb, material_overrides: {layered: "
                         "{clearcoat_map: coat.png}}}")
    loaded = scenerender.Scene.from_yaml(text, tmp_path)
    with scenerender.Renderer(loaded, gl=gl) as renderer:
        from_keys = renderer.render(0).pixels
    # within 1 of 255: the file's texture coordinates are flipped in v by the texture's
    # transform (glTF's v runs down), which rounds differently from the scene map's identity
    assert np.abs(from_file.astype(int) - from_keys).max() <= 1


def test_the_film_takes_its_minimum_thickness_where_its_texture_is_0_and_its_maximum_where_1(gl, tmp_path):
    # a thickness texture 0 on its left half (u < 0.5, the sphere's left as seen) and 1 on
    # its right: each half draws as the film of that thickness alone, iridescenceThicknessMinimum
    # 250 nm and iridescenceThicknessMaximum 600 nm, to the byte (the columns beside the edge
    # and the poles, where the halves meet within a few texels of the mip chain, aside)
    extension, factors, key = TEXTURED["iridescence_thickness"]
    halves = np.zeros((4, 64, 4), np.uint8)
    halves[:, 32:] = 255
    textured_glb(tmp_path / "model.glb", extension, {**factors, "iridescenceThicknessMinimum": 250}, key, halves)
    textured = render_glb(gl, tmp_path)[1].pixels.astype(int)
    alone = {}
    for thickness in (250, 600):
        textured_glb(tmp_path / "model.glb", extension, {**factors, "iridescenceThicknessMaximum": thickness}, None)
        alone[thickness] = render_glb(gl, tmp_path)[1].pixels.astype(int)
    left, right = (slice(16, 56), slice(0, 44)), (slice(16, 56), slice(52, None))
    assert np.array_equal(textured[left], alone[250][left])
    assert np.array_equal(textured[right], alone[600][right])
    assert np.abs(alone[250] - alone[600]).max() > 10


def test_the_iridescence_scene_keys_set_the_same_as_the_file(gl, tmp_path):
    extension, factors, key = TEXTURED["iridescence_thickness"]
    textured_glb(tmp_path / "model.glb", extension, {**factors, "iridescenceThicknessMinimum": 250}, key, gradient())
    from_file = render_glb(gl, tmp_path)[1].pixels
    Image.fromarray(gradient()).save(tmp_path / "film.png")
    textured_glb(tmp_path / "model.glb", extension, factors, None)
    text = SCENE.replace("  - mesh: model.glb", "  - {mesh: model.glb, material_overrides: {layered: "
                         "{iridescence_thickness_map: film.png, iridescence_thickness_min: 250}}}")
    loaded = scenerender.Scene.from_yaml(text, tmp_path)
    with scenerender.Renderer(loaded, gl=gl) as renderer:
        from_keys = renderer.render(0).pixels
    assert np.abs(from_file.astype(int) - from_keys).max() <= 1  # as the coat's keys above


def coat_normals(left: tuple, right: tuple) -> np.ndarray:
    """(4, 64, 4) uint8 tangent-space normal map: unit ``left`` (x, y, z) on its left half
    (u < 0.5), ``right`` on its right, encoded as n * 0.5 + 0.5."""
    pixels = np.full((4, 64, 4), 255, np.uint8)
    for columns, normal in ((slice(0, 32), left), (slice(32, 64), right)):
        unit = np.asarray(normal, float) / np.linalg.norm(normal)
        pixels[:, columns, :3] = np.round((unit * 0.5 + 0.5) * 255).astype(np.uint8)
    return pixels


COAT = {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.4}
FLAT = (0.0, 0.0, 1.0)
TILTED = (0.27, 0.0, 1.0)  # 15 degrees towards the tangent (u)


def test_a_flat_coat_normal_map_gives_the_coat_without_one(gl, tmp_path):
    # a flat map (128, 128, 255: 0.3 degrees from (0, 0, 1)) keeps the picture within 3 of
    # 255 (at the coat's highlight, which that moves); the coat's own normal, on a surface
    # without a normal map of its own
    textured_glb(tmp_path / "model.glb", "KHR_materials_clearcoat", COAT, None)
    plain = render_glb(gl, tmp_path)[1].pixels.astype(int)
    textured_glb(tmp_path / "model.glb", "KHR_materials_clearcoat", COAT, "clearcoatNormalTexture",
                 coat_normals(FLAT, FLAT))
    loaded, flat = render_glb(gl, tmp_path)
    assert {"HAS_CLEARCOAT_NORMAL_MAP", "HAS_TANGENTS"} <= set(material_defines(loaded.world.materials()[0], "pbr"))
    assert np.abs(flat.pixels.astype(int) - plain).max() <= 3


def test_the_coats_normal_map_moves_its_highlight_on_the_gpu_as_in_the_reference(gl, tmp_path):
    # flat on the left half, tilted 15 degrees on the right: the coat's highlight, at the
    # right of the sphere's front, moves; GPU against the reference within the layers'
    # tolerances (linear RMSE of the image 1.5 %, inside surfaces 0.25 %; measured 0.41 /
    # 0.18 %; at 30 degrees 0.85 / 0.56 %: a sharp highlight at the rim, shaded once a pixel)
    textured_glb(tmp_path / "model.glb", "KHR_materials_clearcoat", COAT, None)
    plain = render_glb(gl, tmp_path)[1].pixels.astype(int)
    textured_glb(tmp_path / "model.glb", "KHR_materials_clearcoat", COAT, "clearcoatNormalTexture",
                 coat_normals(FLAT, TILTED), scale=1.0)
    loaded, frame = render_glb(gl, tmp_path)
    changed = np.abs(frame.pixels.astype(int) - plain).max(axis=2)
    assert changed[:, 52:].max() > 10  # the tilted half
    assert changed[16:56, :44].max() <= 3  # the flat half (as the flat map above)
    errors = frame_errors(render_reference(loaded, 0, spp=3), frame.pixels, frame.linear, with_flip=False)
    assert errors["rmse_linear"] < 1.5, errors
    assert errors["interior_rmse"] < 0.25, errors


@pytest.mark.parametrize("extension,key", [("KHR_materials_clearcoat", "clearcoatNormalTexture"),
                                           ("KHR_materials_iridescence", "iridescenceTexture"),
                                           ("KHR_materials_iridescence", "iridescenceThicknessTexture")])
def test_the_textures_are_read_without_a_warning(tmp_path, extension, key):
    textured_glb(tmp_path / "model.glb", extension, {}, key, gradient())
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "model.glb")])
    assert result.exit_code == 0, result.output
    assert "not read" not in result.output, result.output
