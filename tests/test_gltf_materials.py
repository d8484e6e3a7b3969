"""glTF materials honoured: each input of a glTF 2.0 material changes the picture as the
specification says. Every test writes its own small GLB (tests/gltf_files.py) and renders
it at 64 x 64 looking down -Z at a quad or sphere in the XY plane; the inputs trimesh drops
(normalTexture.scale, occlusionTexture.strength, KHR_texture_transform,
KHR_materials_emissive_strength, KHR_materials_unlit, sampler wrap modes) are read from the
file's JSON (scenerender/mesh/gltf.py) and checked here too."""
from __future__ import annotations

import numpy as np
import pytest

import scenerender
from gltf_files import GlbBuilder, quad, sphere
from scenerender.errors import Warnings
from scenerender.mesh import load_mesh
from scenerender.mesh.gltf import GltfMaterial, read_gltf, split_glb
from scenerender.rendering.renderer import GraphRenderer

SIZE = 64
FRONT = "[{type: directional, direction: [0, 0, -1]}]"  # light travelling with the view


def scene_text(lights: str = FRONT, extra: str = "", background=(0, 0, 0), camera_z: float = 5.0) -> str:
    return f"""
render: {{size: [{SIZE}, {SIZE}], samples: 1, background: {list(background)}{extra}}}
camera: {{position: [0, 0, {camera_z}], target: [0, 0, 0], projection: orthographic, height: 2.5}}
lights: {lights}
objects:
  - mesh: model.glb
"""


def render(gl, folder, text: str | None = None, warnings: Warnings | None = None, linear: bool = False) -> np.ndarray:
    """The frame's 8-bit pixels as floats, or with ``linear`` its linear colour (unclamped)."""
    options = {}
    if warnings is not None:
        options["on_warning"] = lambda line: warnings.items.append(line)
    scene = scenerender.Scene.from_yaml(text or scene_text(), folder, **options)
    with scenerender.Renderer(scene, gl=gl, want_linear=linear) as renderer:
        frame = renderer.render(0)
        return frame.linear[..., :3].astype(float) if linear else frame.pixels.astype(float)


def quad_file(folder, uv_pixels=None, colors=None, color_component=5126, node=None, **material) -> None:
    """model.glb: the 2 x 2 quad facing +Z with one material (``material`` are its glTF
    fields; a ``texture`` entry (pixels, sampler) becomes textures[0])."""
    builder = GlbBuilder()
    mesh, uv = quad()
    for key, value in list(material.items()):
        if isinstance(value, dict) and "pixels" in value:
            material[key] = {**{k: v for k, v in value.items() if k not in ("pixels", "sampler")},
                             "index": builder.texture(value["pixels"], value.get("sampler"))}
    pbr = {key: material.pop(key) for key in list(material) if key in (
        "baseColorFactor", "baseColorTexture", "metallicFactor", "roughnessFactor", "metallicRoughnessTexture")}
    index = builder.material(pbrMetallicRoughness=pbr, **material)
    builder.node(builder.mesh(builder.primitive(mesh, index, uv=uv, colors=colors, color_component=color_component)),
                 **(node or {}))
    builder.write(folder / "model.glb")


def sphere_file(folder, **material) -> None:
    builder = GlbBuilder()
    pbr = {key: material.pop(key) for key in list(material) if key in (
        "baseColorFactor", "metallicFactor", "roughnessFactor")}
    index = builder.material(pbrMetallicRoughness=pbr, **material)
    builder.node(builder.mesh(builder.primitive(sphere(1.0, 5), index)))
    builder.write(folder / "model.glb")


def centre(image: np.ndarray, half: int = 8) -> np.ndarray:
    """Mean RGB of the central square."""
    c = SIZE // 2
    return image[c - half:c + half, c - half:c + half].reshape(-1, 3).mean(axis=0)


# -- base colour ---------------------------------------------------------------------------

def test_a_glb_renders_with_its_own_material_under_pbr_with_no_extra_key(gl, tmp_path):
    quad_file(tmp_path, baseColorFactor=[1, 0, 0, 1], metallicFactor=0)
    scene = scenerender.Scene.from_yaml(scene_text(), tmp_path)
    material = scene.world.objects[0].materials[0]
    assert material.model("blinn_phong") == "pbr"
    r, g, b = centre(render(gl, tmp_path))
    assert r > 150 and g < 40 and b < 40 and r > 5 * g  # red, and the dielectric's faint white reflection


def test_base_color_texture_is_srgb(gl, tmp_path):
    # unlit shows the base colour: an sRGB texel of 128 comes back as 128 (decoded to
    # linear 0.216, encoded again); read as linear it would come back as 188
    quad_file(tmp_path, baseColorTexture={"pixels": np.full((4, 4, 3), 128, np.uint8)},
              extensions={"KHR_materials_unlit": {}})
    assert np.abs(centre(render(gl, tmp_path)) - 128).max() <= 1


def test_base_color_factor_times_texture(gl, tmp_path):
    quad_file(tmp_path, baseColorFactor=[1, 0.5, 0, 1], baseColorTexture={"pixels": np.full((4, 4, 3), 255, np.uint8)},
              extensions={"KHR_materials_unlit": {}})
    r, g, b = centre(render(gl, tmp_path))
    assert r == pytest.approx(255, abs=1) and g == pytest.approx(188, abs=1) and b < 1  # linear 0.5 is sRGB 188


def test_vertex_colors_tint_the_base_color(gl, tmp_path):
    red = np.tile([1.0, 0.0, 0.0, 1.0], (4, 1))
    quad_file(tmp_path, colors=red, baseColorFactor=[1, 1, 1, 1], extensions={"KHR_materials_unlit": {}})
    r, g, b = centre(render(gl, tmp_path))
    assert r > 250 and g < 1 and b < 1


@pytest.mark.parametrize("component", [5126, 5121, 5123])
def test_vertex_colors_of_every_component_type_give_the_same_picture(gl, tmp_path, component):
    colors = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]])
    quad_file(tmp_path, colors=colors, color_component=component, extensions={"KHR_materials_unlit": {}})
    image = render(gl, tmp_path)
    # corners of the quad: bottom left red, bottom right green, top right blue, top left white
    quarter = SIZE // 4
    assert image[SIZE - quarter, quarter, 0] > 150 > image[SIZE - quarter, quarter, 1]
    assert image[SIZE - quarter, SIZE - quarter, 1] > 150 > image[SIZE - quarter, SIZE - quarter, 0]
    assert image[quarter, SIZE - quarter, 2] > 150 > image[quarter, SIZE - quarter, 1]


# -- metallic and roughness ------------------------------------------------------------------

def highlight(image: np.ndarray) -> np.ndarray:
    """RGB of the brightest pixel (of linear colour: a highlight above 1 keeps its hue)."""
    flat = image.reshape(-1, 3)
    return flat[np.argmax(flat.sum(axis=1))]


def test_metallic_one_colours_the_highlight_and_zero_leaves_it_white(gl, tmp_path):
    lights = "[{type: point, position: [1.5, 1.5, 4], attenuation: [1, 0, 0], intensity: 1.5}]"
    tints = {}
    for metallic in (0, 1):
        folder = tmp_path / str(metallic)
        folder.mkdir()
        sphere_file(folder, baseColorFactor=[1.0, 0.6, 0.1, 1], metallicFactor=metallic, roughnessFactor=0.15)
        r, g, b = highlight(render(gl, folder, scene_text(lights), linear=True))
        tints[metallic] = b / r
    assert tints[0] > 0.9   # a dielectric's highlight is the light's colour (F0 = 0.04, grey)
    assert tints[1] < 0.2   # a metal's is its base colour (blue / red = 0.1)


def test_roughness_spreads_the_highlight(gl, tmp_path):
    # a black dielectric shows the specular lobe alone
    lights = "[{type: point, position: [0, 0, 6], attenuation: [1, 0, 0], intensity: 3}]"
    areas, peaks = {}, {}
    for roughness in (0.15, 0.45):
        folder = tmp_path / str(roughness)
        folder.mkdir()
        sphere_file(folder, baseColorFactor=[0, 0, 0, 1], metallicFactor=0, roughnessFactor=roughness)
        image = render(gl, folder, scene_text(lights))[..., 0]
        areas[roughness] = int((image > 40).sum())
        peaks[roughness] = image.max()
    assert areas[0.45] > 3 * areas[0.15]
    assert peaks[0.15] > peaks[0.45]


def test_metallic_roughness_texture_blue_is_metal_green_is_rough(gl, tmp_path):
    # left half: blue 0 (dielectric: diffuse gold); right half: blue 255 (metal: no diffuse,
    # a specular lobe as rough as green 255 makes it, a quarter of the light back at the eye)
    pixels = np.zeros((4, 4, 3), np.uint8)
    pixels[:, :, 1] = 255
    pixels[:, 2:, 2] = 255
    quad_file(tmp_path, baseColorFactor=[1.0, 0.7, 0.2, 1], metallicFactor=1, roughnessFactor=1,
              metallicRoughnessTexture={"pixels": pixels, "sampler": {"magFilter": 9728, "wrapS": 33071,
                                                                      "wrapT": 33071}})
    image = render(gl, tmp_path)
    left = image[24:40, 10:24].reshape(-1, 3).mean(axis=0)
    right = image[24:40, 40:54].reshape(-1, 3).mean(axis=0)
    assert left[0] > 1.5 * right[0]
    pixels[:, :, 1] = 100  # smoother: the metal's lobe narrows and its peak, towards the eye, grows
    quad_file(tmp_path, baseColorFactor=[1.0, 0.7, 0.2, 1], metallicFactor=1, roughnessFactor=1,
              metallicRoughnessTexture={"pixels": pixels, "sampler": {"magFilter": 9728, "wrapS": 33071,
                                                                      "wrapT": 33071}})
    assert render(gl, tmp_path)[24:40, 40:54, 0].mean() > right[0] + 30


# -- normal and occlusion textures -----------------------------------------------------------------

def tilted_normal_map() -> np.ndarray:
    """A constant tangent-space normal tilted 60 degrees towards +U."""
    n = np.array([np.sin(np.radians(60)), 0.0, np.cos(np.radians(60))])
    return np.tile(np.round((n * 0.5 + 0.5) * 255).astype(np.uint8), (4, 4, 1))


@pytest.mark.parametrize("scale", [0.0, 1.0])
def test_normal_texture_tilts_the_normal_by_its_scale(gl, tmp_path, scale):
    quad_file(tmp_path, baseColorFactor=[1, 1, 1, 1], metallicFactor=0, roughnessFactor=1)
    flat = centre(render(gl, tmp_path))[0]
    quad_file(tmp_path, baseColorFactor=[1, 1, 1, 1], metallicFactor=0, roughnessFactor=1,
              normalTexture={"pixels": tilted_normal_map(), "scale": scale})
    mapped = centre(render(gl, tmp_path))[0]
    if scale == 0.0:
        assert mapped == pytest.approx(flat, abs=1)
    else:
        assert mapped < flat - 40  # the light now meets the surface at 60 degrees


@pytest.mark.parametrize("strength,expected", [(1.0, 0.25), (0.5, 0.625), (0.0, 1.0)])
def test_occlusion_texture_darkens_ambient_light_by_its_strength(gl, tmp_path, strength, expected):
    ambient = "[{type: ambient, color: [0.5, 0.5, 0.5]}]"
    occlusion = np.full((4, 4, 3), 64, np.uint8)  # linear data: 0.25
    quad_file(tmp_path, baseColorFactor=[1, 1, 1, 1], metallicFactor=0, roughnessFactor=1)
    open_value = render(gl, tmp_path, scene_text(ambient, ", output_transform: linear"))
    quad_file(tmp_path, baseColorFactor=[1, 1, 1, 1], metallicFactor=0, roughnessFactor=1,
              occlusionTexture={"pixels": occlusion, "strength": strength})
    occluded = render(gl, tmp_path, scene_text(ambient, ", output_transform: linear"))
    expected_value = 1.0 + strength * (64 / 255 - 1.0)
    assert centre(occluded)[0] == pytest.approx(centre(open_value)[0] * expected_value, abs=1.5)
    assert expected == pytest.approx(1.0 + strength * (0.25 - 1.0), abs=0.01)


# -- emission ----------------------------------------------------------------------------------

def test_emission_lights_the_side_no_light_reaches(gl, tmp_path):
    behind = "[{type: directional, direction: [0, 0, 1]}]"  # lights the far side only
    sphere_file(tmp_path, baseColorFactor=[1, 1, 1, 1], metallicFactor=0)
    assert centre(render(gl, tmp_path, scene_text(behind))).max() < 1
    sphere_file(tmp_path, baseColorFactor=[1, 1, 1, 1], metallicFactor=0, emissiveFactor=[0.5, 0.1, 0.0])
    lit = render(gl, tmp_path, scene_text(behind, ", output_transform: linear"))
    assert centre(lit) == pytest.approx([0.5 * 255, 0.1 * 255, 0.0], abs=1.5)


def test_emissive_strength_and_texture(gl, tmp_path):
    behind = "[{type: directional, direction: [0, 0, 1]}]"
    texture = np.full((4, 4, 3), 255, np.uint8)
    texture[:, :, 2] = 0
    quad_file(tmp_path, baseColorFactor=[0, 0, 0, 1], emissiveFactor=[0.2, 0.1, 0.3],
              emissiveTexture={"pixels": texture},
              extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 3.0}})
    r, g, b = centre(render(gl, tmp_path, scene_text(behind, ", output_transform: linear")))
    assert r == pytest.approx(0.6 * 255, abs=1.5) and g == pytest.approx(0.3 * 255, abs=1.5) and b < 1


# -- alpha ---------------------------------------------------------------------------------------

def alpha_halves(left: int, right: int) -> np.ndarray:
    pixels = np.full((4, 4, 4), 255, np.uint8)
    pixels[:, :2, 3] = left
    pixels[:, 2:, 3] = right
    return pixels


CLAMPED = {"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}
UNLIT = {"KHR_materials_unlit": {}}


def test_alpha_mask_cuts_pixels_below_the_cutoff(gl, tmp_path):
    texture = {"pixels": alpha_halves(50, 200), "sampler": CLAMPED}
    quad_file(tmp_path, baseColorTexture=texture, alphaMode="MASK", alphaCutoff=0.5, extensions=UNLIT)
    image = render(gl, tmp_path)
    assert image[20:44, 12:28].max() == 0     # alpha 50/255 < 0.5: cut, the background shows
    assert image[20:44, 36:52].min() > 250    # alpha 200/255 kept, drawn opaque
    quad_file(tmp_path, baseColorTexture=texture, alphaMode="MASK", alphaCutoff=0.1, extensions=UNLIT)
    assert render(gl, tmp_path)[20:44, 12:52].min() > 250


def test_alpha_mask_cuts_the_shadow_and_the_depth_view(gl, tmp_path):
    # the quad spans x 0..2 at z = 1 over a backdrop at z = 0; its left half (x 0..1) is cut
    # away. The light travels along (-1, 0, -1): the kept half shadows the backdrop at x 0..1,
    # seen through the cut; the cut half would have shadowed x -1..0.
    texture = {"pixels": alpha_halves(50, 200), "sampler": CLAMPED}
    quad_file(tmp_path, baseColorTexture=texture, alphaMode="MASK", metallicFactor=0, doubleSided=True)
    text = f"""
render: {{size: [{SIZE}, {SIZE}], samples: 1, background: [0, 0, 0]}}
camera: {{position: [0, 0, 5], target: [0, 0, 0], projection: orthographic, height: 2.5}}
lights: [{{type: directional, direction: [-1, 0, -1], shadows: true}}]
objects:
  - mesh: model.glb
    position: [1, 0, 1]
  - mesh: {{primitive: plane, size: 8}}
    rotation: [90, 0, 0]
"""
    free, through_cut = (slice(20, 44), slice(8, 28)), (slice(20, 44), slice(36, 56))
    image = render(gl, tmp_path, text)
    assert image[free].min() > 100 and image[through_cut].max() < 5
    shadow = render(gl, tmp_path, text.replace("samples: 1", "samples: 1, mode: shadow"))
    assert shadow[free].min() > 250 and shadow[through_cut].max() < 5
    depth = render(gl, tmp_path, text.replace("samples: 1", "samples: 1, mode: depth"))
    assert abs(depth[free].mean() - depth[through_cut].mean()) < 3  # the backdrop on both sides


@pytest.mark.parametrize("samples", [1, 4])
def test_alpha_mask_cuts_the_depth_prepass(gl, tmp_path, samples):
    # with a depth prepass (forced here; chosen for deep or shadowed MSAA scenes) a cut-away
    # pixel must hold no depth, or the shading draw's discard leaves the clear colour there
    # instead of the lit backdrop behind the hole
    texture = {"pixels": alpha_halves(50, 200), "sampler": CLAMPED}
    quad_file(tmp_path, baseColorTexture=texture, alphaMode="MASK", metallicFactor=0, doubleSided=True)
    text = f"""
render: {{size: [{SIZE}, {SIZE}], samples: {samples}, background: [0, 0, 0]}}
camera: {{position: [0, 0, 5], target: [0, 0, 0], projection: orthographic, height: 2.5}}
lights: [{{type: directional, direction: [0, 0, -1], shadows: true}}]
objects:
  - mesh: model.glb
    position: [0, 0, 1]
  - mesh: {{primitive: plane, size: 8}}
    rotation: [90, 0, 0]
"""
    world = scenerender.Scene.from_yaml(text, tmp_path).world
    renderer = GraphRenderer(world, gl, tuning={"depth_prepass": True})
    try:
        assert "depth prepass" in renderer.compiled.dump()
        image = renderer.render(0).pixels.astype(float)
    finally:
        renderer.release()
    through_cut, kept = (slice(20, 44), slice(12, 28)), (slice(20, 44), slice(36, 52))
    assert image[through_cut].min() > 100  # the lit backdrop, not the black clear colour
    assert image[kept].min() > 100


def test_alpha_blend_is_transparent_and_opaque_ignores_alpha(gl, tmp_path):
    half = np.full((4, 4, 4), 255, np.uint8)
    half[..., 3] = 128
    quad_file(tmp_path, baseColorTexture={"pixels": half}, alphaMode="BLEND", extensions=UNLIT)
    blended = centre(render(gl, tmp_path, scene_text(extra=", output_transform: linear")))
    assert blended == pytest.approx([128, 128, 128], abs=2)  # half white over black
    quad_file(tmp_path, baseColorTexture={"pixels": half}, alphaMode="OPAQUE", extensions=UNLIT)
    assert centre(render(gl, tmp_path)).min() > 250


# -- faces and placement -------------------------------------------------------------------------------

@pytest.mark.parametrize("double_sided", [False, True])
def test_double_sided_false_hides_the_back_face(gl, tmp_path, double_sided):
    quad_file(tmp_path, baseColorFactor=[1, 1, 1, 1], doubleSided=double_sided, extensions=UNLIT,
              node={"rotation": [0.0, 1.0, 0.0, 0.0]})  # turned 180 degrees about Y: its back faces the camera
    seen = centre(render(gl, tmp_path)).max()
    assert (seen > 250) if double_sided else (seen == 0)


def test_node_transforms_place_the_mesh(gl, tmp_path):
    builder = GlbBuilder()
    mesh, uv = quad(0.5)
    material = builder.material(pbrMetallicRoughness={"baseColorFactor": [1, 1, 1, 1]}, extensions=UNLIT)
    child = builder.node(builder.mesh(builder.primitive(mesh, material)), root=False,
                         translation=[0.0, 0.5, 0.0])
    # the parent turns 90 degrees about Z (+Y becomes -X) and moves 0.25 up: the child's
    # centre lands at (-0.5, 0.25)
    s = float(np.sqrt(0.5))
    builder.node(None, children=[child], rotation=[0.0, 0.0, s, s], translation=[0.0, 0.25, 0.0])
    builder.write(tmp_path / "model.glb")
    image = render(gl, tmp_path)[..., 0]
    ys, xs = np.nonzero(image > 128)
    pixel = 2.5 / SIZE
    assert (xs.mean() + 0.5) * pixel - 1.25 == pytest.approx(-0.5, abs=pixel)
    assert 1.25 - (ys.mean() + 0.5) * pixel == pytest.approx(0.25, abs=pixel)


def test_texture_transform_moves_and_turns_the_texture(gl, tmp_path):
    pixels = np.zeros((4, 4, 3), np.uint8)
    pixels[:, :2] = 255  # left half white
    base = {"pixels": pixels, "sampler": {"magFilter": 9728}}
    quad_file(tmp_path, baseColorTexture=base, extensions=UNLIT)
    plain = render(gl, tmp_path)[..., 0] > 128
    assert plain[:, :SIZE // 2 - 8].mean() > 0.5 > plain[:, SIZE // 2 + 8:].mean()
    moved = {**base, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0.0]}}}
    quad_file(tmp_path, baseColorTexture=moved, extensions=UNLIT)
    shifted = render(gl, tmp_path)[..., 0] > 128
    assert shifted[:, :SIZE // 2 - 8].mean() < 0.5 < shifted[:, SIZE // 2 + 8:].mean()  # halves swapped
    turned = {**base, "extensions": {"KHR_texture_transform": {"rotation": float(np.pi / 2)}}}
    quad_file(tmp_path, baseColorTexture=turned, extensions=UNLIT)
    rotated = render(gl, tmp_path)[..., 0] > 128
    inner = rotated[12:52, 12:52]
    # the white half is now the top or bottom half: rows differ, columns do not
    assert abs(inner[:20].mean() - inner[20:].mean()) > 0.8 and abs(inner[:, :20].mean() - inner[:, 20:].mean()) < 0.2


# -- scene overrides --------------------------------------------------------------------------------

def test_a_scene_overrides_a_glb_material_by_name_or_replaces_it(gl, tmp_path):
    quad_file(tmp_path, name="paint", baseColorFactor=[1, 0, 0, 1], metallicFactor=0)
    text = scene_text()
    override = text + "    material_overrides: {paint: {base_color: [0, 0, 1]}}\n"
    r, g, b = centre(render(gl, tmp_path, override))
    assert b > 150 and r < 40 and b > 5 * r
    replaced = text + "    material: {diffuse: [0, 1, 0], shading: blinn_phong}\n"
    r, g, b = centre(render(gl, tmp_path, replaced))
    assert g > 150 and g > r + 80  # green, with Blinn-Phong's white highlight
    scene = scenerender.Scene.from_yaml(replaced, tmp_path)
    assert scene.world.objects[0].materials[0].model("blinn_phong") == "blinn_phong"


# -- what trimesh drops, read from the JSON ------------------------------------------------------------

def test_the_inputs_trimesh_drops_are_read_from_the_file(tmp_path):
    builder = GlbBuilder()
    mesh, uv = quad()
    texture = builder.texture(np.full((4, 4, 3), 128, np.uint8), {"wrapS": 33648, "wrapT": 33648, "magFilter": 9728})
    material = builder.material(
        name="all", pbrMetallicRoughness={"baseColorTexture": {"index": texture, "extensions": {
            "KHR_texture_transform": {"offset": [0.25, 0.5], "scale": [2, 3], "rotation": 0.0}}}},
        normalTexture={"index": texture, "scale": 0.4}, occlusionTexture={"index": texture, "strength": 0.7},
        emissiveFactor=[1, 0.5, 0.25], extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
        alphaMode="MASK", alphaCutoff=0.3, doubleSided=True)
    builder.node(builder.mesh(builder.primitive(mesh, material, uv=uv)))
    path = builder.write(tmp_path / "model.glb")
    gltf = read_gltf(split_glb(path.read_bytes()), str(path), lambda name: b"")
    read = gltf.materials[0]
    assert isinstance(read, GltfMaterial) and read.name == "all"
    assert read.normal_map.scale == 0.4 and read.occlusion_map.scale == 0.7
    assert read.emissive == (1.0, 0.5, 0.25) and read.emissive_strength == 4.0
    assert read.alpha_mode == "mask" and read.alpha_cutoff == 0.3 and read.double_sided
    assert read.base_color_map.wrap == "mirror" and read.base_color_map.nearest
    # glTF's (u, v) -> (2u + 0.25, 3v + 0.5), v pointing down; in GL's v-up coordinates
    # (v_gl = 1 - v): v_gl' = 1 - (3 (1 - v_gl) + 0.5) = 3 v_gl - 2.5
    assert read.base_color_map.uv_scale == pytest.approx((2.0, 3.0))
    assert read.base_color_map.uv_offset == pytest.approx((0.25, -2.5))
    assert read.base_color_map.uv_skew == pytest.approx((0.0, 0.0))
    loaded = load_mesh(path, warnings=Warnings())
    assert list(loaded.materials) == ["all"] and loaded.groups[0].material == "all"
    assert len(loaded.images) == 1


def test_an_unsupported_texture_set_and_broken_materials_are_warnings(gl, tmp_path):
    builder = GlbBuilder()
    mesh, uv = quad()
    texture = builder.texture(np.full((4, 4, 3), 255, np.uint8))
    material = builder.material(pbrMetallicRoughness={"baseColorTexture": {"index": texture, "texCoord": 1}})
    builder.node(builder.mesh(builder.primitive(mesh, material, uv=uv)))
    builder.write(tmp_path / "model.glb")
    warnings = Warnings()
    render(gl, tmp_path, warnings=warnings)
    assert any("texture coordinate set 1" in line for line in warnings.items)
    builder.json["materials"][0]["normalTexture"] = {"index": texture, "scale": "big"}
    builder.write(tmp_path / "model.glb")
    warnings = Warnings()
    image = render(gl, tmp_path, warnings=warnings)
    assert any("materials not read" in line and "normalTexture.scale" in line for line in warnings.items)
    assert centre(image).max() > 100  # drawn, with the scene's default material
