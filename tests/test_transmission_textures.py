"""KHR_materials_transmission's transmissionTexture (red times transmission) and
KHR_materials_volume's thicknessTexture (green times thickness) per pixel, on the GPU
(lighting/material.glsl, sample_layers) and in the reference (docs/scene-notes.md,
"Transmission and volume")."""
from __future__ import annotations

import numpy as np
import pytest
import trimesh
from click.testing import CliRunner

import scenerender
from conftest import render, scene
from gltf_files import GlbBuilder
from scenerender.cli import main
from scenerender.raytrace import render_reference
from scenerender.rendering.features import material_defines
from test_transmission import PANE, _block_means, _box, _scene_text, glass_glb

# the box behind the pane seen straight through its upper half (rows 28..35) and its lower
# half (rows 36..43), away from the texture's edge at row 36
THROUGH_TOP = (slice(29, 34), slice(51, 61))
THROUGH_BOTTOM = (slice(38, 43), slice(51, 61))


def halves(top: float, bottom: float) -> np.ndarray:
    """(8, 8, 4) uint8: every channel ``top`` (0..1) in the upper half, ``bottom`` below."""
    pixels = np.empty((8, 8, 4), np.uint8)
    pixels[:4], pixels[4:] = round(top * 255), round(bottom * 255)
    return pixels


def pane_uv(mesh: trimesh.Trimesh) -> np.ndarray:
    """(N, 2) glTF texture coordinates (v down) of the 1.6 x 1.2 pane, planar in x and y."""
    return np.column_stack([mesh.vertices[:, 0] / 1.6 + 0.5, 0.5 - mesh.vertices[:, 1] / 1.2])


def textured_glass_glb(path, extensions: dict, thickness: float = 0.0, roughness: float = 0.0,
                       pixels: np.ndarray | None = None, key: tuple[str, str] | None = None):
    """test_transmission.glass_glb's red box behind a pane (a thin quad, or a slab
    ``thickness`` thick), the pane with texture coordinates and, where ``key`` (extension,
    its texture key) is given, that texture of ``pixels``."""
    builder = GlbBuilder()
    values = {name: dict(fields) for name, fields in extensions.items()}
    if key is not None:
        values[key[0]][key[1]] = {"index": builder.texture(pixels)}
    red = builder.material(name="red", pbrMetallicRoughness={"baseColorFactor": [0.9, 0.08, 0.05, 1],
                                                             "metallicFactor": 0.0, "roughnessFactor": 0.7})
    glass = builder.material(name="glass", doubleSided=True, extensions=values,
                             pbrMetallicRoughness={"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0,
                                                   "roughnessFactor": roughness})
    for name in values:
        builder.uses(name)
    if thickness > 0.0:
        pane = _box([1.6, 1.2, thickness], [0.0, 0.0, 0.0])
    else:
        pane = trimesh.Trimesh(vertices=[[-0.8, -0.6, 0], [0.8, -0.6, 0], [0.8, 0.6, 0], [-0.8, 0.6, 0]],
                               faces=[[0, 1, 2], [0, 2, 3]], process=False)
        pane.vertex_normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    builder.node(builder.mesh(builder.primitive(_box([0.8, 0.8, 0.8], [0.4, 0.0, -1.5]), red)))
    builder.node(builder.mesh(builder.primitive(pane, glass, uv=pane_uv(pane))))
    return builder.write(path)


TRANSMISSION = {"KHR_materials_transmission": {"transmissionFactor": 1.0}}
TRANSMISSION_KEY = ("KHR_materials_transmission", "transmissionTexture")
VOLUME = {"KHR_materials_transmission": {"transmissionFactor": 1.0},
          "KHR_materials_volume": {"thicknessFactor": 0.3, "attenuationDistance": 0.2,
                                   "attenuationColor": [0.5, 0.5, 0.5]}}
THICKNESS_KEY = ("KHR_materials_volume", "thicknessTexture")


def _gpu(gl, tmp_path) -> np.ndarray:
    loaded = scene(_scene_text(), base_dir=tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        return renderer.render(0).linear[..., :3]


def _red_share(linear: np.ndarray, where) -> float:
    """How red the mean of ``where`` is: red over green."""
    mean = linear[where].mean(axis=(0, 1))
    return float(mean[0] / mean[1])


def test_a_white_map_gives_the_factors_picture_and_none_the_same_bytes(gl, tmp_path):
    for extensions, key, thickness in ((TRANSMISSION, TRANSMISSION_KEY, 0.0), (VOLUME, THICKNESS_KEY, 0.3)):
        glass_glb(tmp_path / "model.glb", thickness=thickness, roughness=0.0, extensions=extensions)
        before = render(gl, _scene_text(), base_dir=tmp_path)[0]
        textured_glass_glb(tmp_path / "model.glb", extensions, thickness)  # with texture coordinates, no map
        plain = render(gl, _scene_text(), base_dir=tmp_path)[0]
        assert np.array_equal(before, plain)
        textured_glass_glb(tmp_path / "model.glb", extensions, thickness, pixels=halves(1, 1), key=key)
        material = scene(_scene_text(), base_dir=tmp_path).world.materials()[1]
        map_key = {"transmissionTexture": "transmission_map", "thicknessTexture": "thickness_map"}[key[1]]
        assert f"HAS_{map_key.upper()}" in material_defines(material, "pbr")
        white = render(gl, _scene_text(), base_dir=tmp_path)[0]
        assert np.array_equal(white, plain)


@pytest.mark.parametrize("renderer", ["gpu", "reference"])
def test_the_transmission_map_shows_the_box_where_it_is_white(gl, tmp_path, renderer):
    # the upper half lets all through (red box behind), the lower a fifth: there the pane's
    # own white diffuse covers the box
    textured_glass_glb(tmp_path / "model.glb", TRANSMISSION, pixels=halves(1.0, 0.2), key=TRANSMISSION_KEY)
    if renderer == "gpu":
        linear = _gpu(gl, tmp_path)
    else:
        linear = render_reference(scene(_scene_text(), base_dir=tmp_path), 0, spp=3).linear
    assert _red_share(linear, THROUGH_TOP) > 3.0
    assert _red_share(linear, THROUGH_BOTTOM) < 2.0


def test_gpu_matches_the_reference_with_a_two_valued_transmission_map(gl, tmp_path):
    # test_transmission's smooth thin pane tolerance (1 % of the pane's mean, block RMSE;
    # measured 0.16 %, the mean 0.04 % low)
    textured_glass_glb(tmp_path / "model.glb", TRANSMISSION, pixels=halves(1.0, 0.2), key=TRANSMISSION_KEY)
    loaded = scenerender.Scene.from_yaml(_scene_text(), tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        gpu = renderer.render(0).linear[..., :3][PANE]
    ref = render_reference(loaded, 0, spp=6).linear[PANE]
    error = float(np.sqrt(np.mean((_block_means(gpu) - _block_means(ref)) ** 2)) / ref.mean())
    assert error < 0.01, error
    assert float(gpu.mean() / ref.mean()) == pytest.approx(1.0, abs=0.025)


def test_the_thickness_map_attenuates_each_half_as_its_thickness_does(gl, tmp_path):
    # a map of 1 above and 1/3 below on a thickness of 0.3: on the GPU each half is the
    # picture of a volume 0.3 and 0.1 thick, at the same slab (Beer-Lambert over the
    # thickness, not the slab's depth; the reference follows the slab itself)
    textured_glass_glb(tmp_path / "model.glb", VOLUME, 0.3, pixels=halves(1.0, 1.0 / 3.0), key=THICKNESS_KEY)
    textured = _gpu(gl, tmp_path)
    factors = {}
    for thickness in (0.3, 0.1):
        extensions = {**VOLUME, "KHR_materials_volume": {**VOLUME["KHR_materials_volume"], "thicknessFactor": thickness}}
        textured_glass_glb(tmp_path / "model.glb", extensions, 0.3)
        factors[thickness] = _gpu(gl, tmp_path)
    background = (slice(24, 33), slice(30, 44))  # the upper half beside the box
    lower = (slice(39, 48), slice(30, 44))
    assert textured[background].mean() == pytest.approx(factors[0.3][background].mean(), rel=0.01)
    assert textured[lower].mean() == pytest.approx(factors[0.1][lower].mean(), rel=0.01)
    assert factors[0.1][lower].mean() > 1.5 * factors[0.3][lower].mean()


def test_the_scene_keys_set_the_same_maps_as_the_extension(gl, tmp_path):
    from PIL import Image
    textured_glass_glb(tmp_path / "model.glb", TRANSMISSION, pixels=halves(1.0, 0.2), key=TRANSMISSION_KEY)
    from_file = render(gl, _scene_text(), base_dir=tmp_path)[0]
    Image.fromarray(halves(1.0, 0.2)).save(tmp_path / "through.png")
    textured_glass_glb(tmp_path / "model.glb", TRANSMISSION)
    text = _scene_text().replace("  - mesh: model.glb", "  - {mesh: model.glb, material_overrides: {glass: "
                                 "{transmission_map: through.png}}}")
    from_keys = render(gl, text, base_dir=tmp_path)[0]
    # within 1 of 255: the file's coordinates are flipped in v by its texture transform
    assert np.abs(from_file.astype(int) - from_keys).max() <= 1


def test_the_textures_are_read_without_a_warning(tmp_path):
    textured_glass_glb(tmp_path / "model.glb", VOLUME, 0.3, pixels=halves(1, 0.5), key=THICKNESS_KEY)
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "model.glb")])
    assert result.exit_code == 0, result.output
    assert "is not read" not in result.output
