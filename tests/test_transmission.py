"""KHR_materials_transmission and KHR_materials_volume (docs/scene-notes.md, "Transmission
and volume"): from a GLB written here and from the scene's material keys, on the GPU (the
transparent pass over a mip-mapped copy of the opaque scene) and in the reference (paths
through the rough dielectric), with the same weights."""
from __future__ import annotations

import numpy as np
import pytest
import trimesh
from click.testing import CliRunner

import scenerender
from conftest import render, scene
from gltf_files import GlbBuilder, quad
from scenerender.cli import main
from scenerender.raytrace import ambient_fit, render_reference
from scenerender.raytrace.transmission import Interface, scatter
from scenerender.rendering.features import material_defines


def _box(extents, center) -> trimesh.Trimesh:
    """A box with a normal of its own at each face's corners (flat faces)."""
    mesh = trimesh.creation.box(extents=extents)
    mesh.apply_translation(center)
    mesh.unmerge_vertices()
    return mesh


def glass_glb(path, thickness: float = 0.0, roughness: float = 0.1, extensions: dict | None = None,
              base=(1.0, 1.0, 1.0)):
    """A red box (0.8 a side, centred at (0.4, 0, -1.5)) behind a pane of glass at the origin
    facing +Z (1.6 x 1.2): a thin quad where ``thickness`` is 0, else a slab that thick.
    ``extensions``: the pane's material extensions (default full transmission, and a volume
    of that thickness attenuating to grey over 0.2)."""
    if extensions is None:
        extensions = {"KHR_materials_transmission": {"transmissionFactor": 1.0}}
        if thickness > 0.0:
            extensions["KHR_materials_volume"] = {"thicknessFactor": thickness, "attenuationDistance": 0.2,
                                                  "attenuationColor": [0.5, 0.5, 0.5]}
    builder = GlbBuilder()
    red = builder.material(name="red", pbrMetallicRoughness={"baseColorFactor": [0.9, 0.08, 0.05, 1],
                                                             "metallicFactor": 0.0, "roughnessFactor": 0.7})
    glass = builder.material(name="glass", doubleSided=True, extensions=extensions,
                             pbrMetallicRoughness={"baseColorFactor": [*base, 1], "metallicFactor": 0.0,
                                                   "roughnessFactor": roughness})
    for name in extensions:
        builder.uses(name)
    if thickness > 0.0:
        pane = _box([1.6, 1.2, thickness], [0.0, 0.0, 0.0])
    else:
        pane = quad(1.0)[0]
        pane.apply_scale([1.6, 1.2, 1.0])
        pane.vertex_normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    builder.node(builder.mesh(builder.primitive(_box([0.8, 0.8, 0.8], [0.4, 0.0, -1.5]), red)))
    builder.node(builder.mesh(builder.primitive(pane, glass)))
    return builder.write(path)


SCENE = """
render: {{size: [{w}, {h}], samples: 4, shading: pbr, background: [0.55, 0.6, 0.7]}}
camera: {{position: [0, 0, 4], target: [0, 0, 0], fov: 40}}
lights:
  - {{type: directional, direction: [-0.4, -0.6, -1], intensity: 1.5}}
  - {{type: ambient, color: [0.3, 0.3, 0.3]}}
objects:
  - mesh: model.glb
"""
SIZE = (96, 72)
# the pane (1.6 x 1.2 at distance 4, 40 degrees) covers columns 27..68, rows 20..51; the
# box behind it columns 48..63, rows 28..43 (seen straight through)
THROUGH_BOX = (slice(31, 41), slice(51, 61))
THROUGH_BACKGROUND = (slice(24, 48), slice(30, 44))


def _scene_text(width=SIZE[0], height=SIZE[1]) -> str:
    return SCENE.format(w=width, h=height)


def _gpu(gl, tmp_path):
    loaded = scene(_scene_text(), base_dir=tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        return renderer.render(0)


def test_transmission_shows_the_object_behind(gl, tmp_path):
    glass_glb(tmp_path / "model.glb")
    seen = _gpu(gl, tmp_path).linear[..., :3]
    glass_glb(tmp_path / "model.glb", extensions={})  # the same pane, opaque white
    opaque = _gpu(gl, tmp_path).linear[..., :3]
    through, blocked = seen[THROUGH_BOX].mean(axis=(0, 1)), opaque[THROUGH_BOX].mean(axis=(0, 1))
    assert through[0] > 3.0 * through[1]  # red: the box shows through
    assert blocked[0] < 1.5 * blocked[1]  # the opaque pane hides it
    # beside the box the background shows, a little darkened by the pane's reflection share
    background = seen[THROUGH_BACKGROUND].mean(axis=(0, 1))
    assert np.allclose(background, [0.55, 0.6, 0.7], rtol=0.12), background


def test_roughness_blurs_what_shows_through(gl, tmp_path):
    # the box's left edge seen through the pane: sharp when smooth, spread when rough
    edges = {}
    for roughness in (0.05, 0.6):
        glass_glb(tmp_path / "model.glb", roughness=roughness)
        red = _gpu(gl, tmp_path).linear[36, 38:62, 0]
        edges[roughness] = int(np.sum((red > red.min() + 0.1 * np.ptp(red)) & (red < red.max() - 0.1 * np.ptp(red))))
    assert edges[0.05] <= 2 and edges[0.6] >= 5, edges


@pytest.mark.parametrize("renderer", ["gpu", "reference"])
def test_a_volume_darkens_with_its_thickness(gl, tmp_path, renderer):
    # Beer-Lambert: grey 0.5 after 0.2 inside, so 0.1 thick lets 0.707 through, 0.3 thick 0.354
    means = {}
    for thickness in (0.1, 0.3):
        glass_glb(tmp_path / "model.glb", thickness=thickness, roughness=0.0)
        loaded = scene(_scene_text(), base_dir=tmp_path)
        if renderer == "gpu":
            linear = _gpu(gl, tmp_path).linear[..., :3]
        else:
            linear = render_reference(loaded, 0, spp=2).linear
        means[thickness] = float(linear[THROUGH_BACKGROUND].mean())
    ratio = means[0.3] / means[0.1]
    assert ratio == pytest.approx(0.5, abs=0.05), means


# Stated tolerances, GPU (4x MSAA) against the reference (6 x 6 samples a pixel) inside the
# pane: the linear RMSE of 4 x 4 pixel block means (the reference's paths are Monte Carlo
# noise pixel by pixel) as a share of the pane's mean, and the pane's mean. Measured
# (thickness, roughness): (0, 0) 0.4 %, mean -0.03 %: a smooth thin wall is exact;
# (0, 0.2) 4.2 %, +0.5 %: the mip chain's box blur is not the GGX lobe's spread;
# (0.1, 0.2) 3.0 %, +1.6 %: the reference crosses the slab's two faces, each taking its
# Fresnel share, where the GPU takes one, and bends through its side faces.
PANE = (slice(23, 49), slice(30, 66))
PANE_TOLERANCE = {(0.0, 0.0): 0.01, (0.0, 0.2): 0.06, (0.1, 0.2): 0.045}


def _block_means(image: np.ndarray, k: int = 4) -> np.ndarray:
    """(H, W, 3) -> (H // k, W // k, 3) means of k x k blocks."""
    h, w = image.shape[0] // k * k, image.shape[1] // k * k
    return image[:h, :w].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))


@pytest.mark.parametrize("thickness,roughness", list(PANE_TOLERANCE))
def test_gpu_matches_the_reference_through_the_pane(gl, tmp_path, thickness, roughness):
    glass_glb(tmp_path / "model.glb", thickness=thickness, roughness=roughness)
    loaded = scenerender.Scene.from_yaml(_scene_text(), tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        gpu = renderer.render(0).linear[..., :3][PANE]
    ref = render_reference(loaded, 0, spp=6).linear[PANE]
    error = float(np.sqrt(np.mean((_block_means(gpu) - _block_means(ref)) ** 2)) / ref.mean())
    assert error < PANE_TOLERANCE[(thickness, roughness)], error
    assert float(gpu.mean() / ref.mean()) == pytest.approx(1.0, abs=0.025)


FURNACE = """
render: {{size: [64, 64], samples: 1, shading: pbr, background: [1, 1, 1]}}
camera: {{position: [0, 0, 3], target: [0, 0, 0], fov: 45}}
lights: [{{type: ambient, color: [1, 1, 1]}}]
objects:
  - mesh: {mesh}
    rotation: [90, 0, 0]
    material: {{base_color: [1, 1, 1], metallic: 0, roughness: {roughness}, transmission: 1, thickness: {thickness}}}
"""
PLANE = "{primitive: plane, size: [2, 2]}"
SPHERE = "{primitive: sphere, radius: 1, segments: 64, rings: 32}"


@pytest.mark.parametrize("roughness", [0.3, 0.6])
def test_white_furnace_a_thin_wall_loses_only_what_its_lobe_loses(roughness):
    # a clear white thin wall facing the eye in a uniform white surround (the background
    # behind it, the ambient light integrated over the hemisphere): it reflects F and lets
    # 1 - F through the mirrored GGX lobe, so it gives back the single-scattering lobe's
    # albedo E(N.V = 1), 1 minus the light the microfacets' masking loses (0.99 at roughness
    # 0.3, 0.82 at 0.6: the specification's BTDF loses what its BRDF does); measured 0.991, 0.821
    loaded = scenerender.Scene.from_yaml(FURNACE.format(mesh=PLANE, roughness=roughness, thickness=0), ".")
    ref = render_reference(loaded, 0, spp=2, ambient_samples=64)
    values = ref.linear[(ref.object == 0) & ~ref.mixed]
    scale, bias, _ = ambient_fit.evaluate(np.array([1.0]), np.array([roughness]))
    assert len(values) > 2000
    assert float(values.mean()) == pytest.approx(float(scale[0] + bias[0]), abs=0.02)


def test_white_furnace_a_smooth_volume_keeps_the_light():
    # a clear glass ball: what its surface does not reflect enters, is reflected inside or
    # leaves, and nothing absorbs it: the surround comes back whole (measured 0.986; the
    # paths still inside after MAX_INTERFACES are lost); rough, the lobe's loss at each
    # interface shows (0.931 at roughness 0.3), never a gain
    means = {}
    for roughness in (0.0, 0.3):
        loaded = scenerender.Scene.from_yaml(FURNACE.format(mesh=SPHERE, roughness=roughness, thickness=1), ".")
        ref = render_reference(loaded, 0, spp=2, ambient_samples=64)
        means[roughness] = float(ref.linear[(ref.object == 0) & ~ref.mixed].mean())
    assert means[0.0] == pytest.approx(1.0, abs=0.025)
    assert 0.88 < means[0.3] < means[0.0]


def test_an_interface_event_never_weighs_more_than_one():
    rng = np.random.default_rng(3)
    count = 4000
    n = np.tile([0.0, 0.0, 1.0], (count, 1))
    view = rng.normal(size=(count, 3))
    view[:, 2] = np.abs(view[:, 2]) + 0.05
    view /= np.linalg.norm(view, axis=1, keepdims=True)
    for inside in (False, True):
        for thin in (False, True):
            went = scatter(Interface(n, view, rng.uniform(0.002, 1.0, count), np.full((count, 3), 0.04),
                                     np.ones(count), np.full(count, 1.5), np.full(count, thin),
                                     np.full(count, inside and not thin)), rng)
            assert went.weight.max() <= 1.0 + 1e-9 and went.weight.min() >= 0.0
            passed = went.crossed & (went.weight[:, 0] > 0.0)
            assert np.all(went.l[passed, 2] < 0.0)  # what passes leaves on the far side


def test_a_material_without_transmission_renders_as_before(gl, tmp_path):
    glass_glb(tmp_path / "model.glb", extensions={})
    plain = render(gl, _scene_text(), base_dir=tmp_path)[0]
    glass_glb(tmp_path / "model.glb", extensions={"KHR_materials_transmission": {"transmissionFactor": 0.0},
                                                  "KHR_materials_volume": {"thicknessFactor": 0.0}})
    defaults = render(gl, _scene_text(), base_dir=tmp_path)[0]
    assert np.array_equal(plain, defaults)
    loaded = scene(_scene_text(), base_dir=tmp_path)
    assert not any("TRANSMISSION" in key for m in loaded.world.materials() for key in material_defines(m, "pbr"))
    result = CliRunner().invoke(main, ["graph", str(_write(tmp_path, _scene_text()))])
    assert result.exit_code == 0, result.output
    assert "transmission_source" not in result.output
    glass_glb(tmp_path / "model.glb")
    result = CliRunner().invoke(main, ["graph", str(_write(tmp_path, _scene_text()))])
    assert "transmission_source" in result.output


def _write(tmp_path, text: str):
    path = tmp_path / "scene.yaml"
    path.write_text(text)
    return path


def test_the_scene_keys_set_the_same_as_the_extensions(gl, tmp_path):
    glass_glb(tmp_path / "model.glb", thickness=0.1, roughness=0.2)
    from_file = render(gl, _scene_text(), base_dir=tmp_path)[0]
    glass_glb(tmp_path / "model.glb", thickness=0.1, roughness=0.2, extensions={})
    keys = ("material_overrides: {glass: {transmission: 1, thickness: 0.1, attenuation_distance: 0.2, "
            "attenuation_color: [0.5, 0.5, 0.5]}}")
    text = _scene_text().replace("  - mesh: model.glb", f"  - {{mesh: model.glb, {keys}}}")
    from_keys = render(gl, text, base_dir=tmp_path)[0]
    assert np.array_equal(from_file, from_keys)


def test_a_bad_attenuation_distance_is_an_error_naming_the_key(tmp_path):
    glass_glb(tmp_path / "model.glb", extensions={})
    text = _scene_text().replace("  - mesh: model.glb",
                                 "  - {mesh: model.glb, material_overrides: {glass: {attenuation_distance: 0}}}")
    result = CliRunner().invoke(main, ["validate", str(_write(tmp_path, text))])
    assert result.exit_code == 2
    assert "attenuation_distance" in result.output and "Traceback" not in result.output


def test_a_transmissive_material_blends_only_where_its_alpha_mode_says(tmp_path):
    # glass of glTF's OPAQUE mode covers what it shows (its alpha ignored); BLEND blends too
    glass_glb(tmp_path / "model.glb")
    for alpha_mode, blended in (("opaque", False), ("blend", True)):
        text = _scene_text().replace("  - mesh: model.glb", "  - {mesh: model.glb, material_overrides: "
                                     f"{{glass: {{opacity: 0.5, alpha_mode: {alpha_mode}}}}}}}")
        glass = next(m for m in scene(text, base_dir=tmp_path).world.materials() if m.transmissive)
        assert glass.transparent
        assert ("TRANSPARENT" in material_defines(glass, "pbr")) is blended


# A point light behind the pane (the red box further behind, off to the side): the light
# seen through the glass at the pixel where the eye's ray through the pane meets it
BACKLIT = """
render: {{size: [96, 72], samples: 4, shading: pbr, background: [0, 0, 0]}}
camera: {{position: [0, 0, 4], target: [0, 0, 0], fov: 40}}
lights:
  - {{type: point, position: [-0.3, 0.2, -0.8], intensity: 0.1, attenuation: [0, 0, 1]{shadows}}}
objects:
  - mesh: model.glb
{blocker}"""
# the eye's ray towards the light crosses the pane at (-0.25, 0.167, 0): column 41, row 31;
# the pane left of the box (black background behind it): its light is the light through alone
TOWARDS_LIGHT = (slice(29, 34), slice(39, 44))
BESIDE_THE_BOX = (slice(23, 49), slice(30, 46))
BLOCKER = ("  - mesh: {primitive: box, size: [0.3, 0.3, 0.05]}\n    position: [-0.28, 0.18, -0.4]\n"
           "    material: {base_color: [0.5, 0.5, 0.5]}\n")
# Stated tolerance, GPU (4x MSAA) against the reference (6 samples a pixel): beside the box,
# the RMSE of 4 x 4 block means over the reference's mean (the same formula on both sides:
# what is left is where in a pixel each evaluates it; measured 0.024, mean 0.986)
BACKLIT_TOLERANCE = 0.04


def _backlit(gl, tmp_path, shadows: str = "", blocker: str = ""):
    loaded = scenerender.Scene.from_yaml(BACKLIT.format(shadows=shadows, blocker=blocker), tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        return loaded, renderer.render(0).linear[..., :3]


def test_a_pane_lit_from_behind_brightens_on_the_cameras_side(gl, tmp_path):
    # KHR_materials_transmission's BTDF: the light behind shines through the rough pane
    # towards the eye, brightest where the eye looks straight at it (N.H_t = 1 there:
    # radiance (1 - F) pi D V N.L = 0.155 x 0.96 x 16 x 0.25 = 0.6 at roughness 0.5)
    glass_glb(tmp_path / "model.glb", roughness=0.5)
    loaded, gpu = _backlit(gl, tmp_path)
    assert 0.5 < float(gpu[TOWARDS_LIGHT].max()) < 0.7
    # the reference: next-event estimation through the same BTDF
    ref = render_reference(loaded, 0, spp=6).linear[BESIDE_THE_BOX]
    error = float(np.sqrt(np.mean((_block_means(gpu[BESIDE_THE_BOX]) - _block_means(ref)) ** 2)) / ref.mean())
    assert error < BACKLIT_TOLERANCE, error
    assert float(gpu[BESIDE_THE_BOX].mean() / ref.mean()) == pytest.approx(1.0, abs=0.03)
    # an opaque pane of the same base stays dark on the eye's side: the light is behind it
    glass_glb(tmp_path / "model.glb", roughness=0.5, extensions={})
    assert float(_backlit(gl, tmp_path)[1][TOWARDS_LIGHT].max()) < 0.01


def test_the_light_through_a_pane_is_shadowed_by_other_casters_not_by_the_pane(gl, tmp_path):
    # the light's shadow is looked up from the pane's far side: the pane casts a shadow but
    # does not darken its own light through; an opaque box between the light and the pane does
    glass_glb(tmp_path / "model.glb", roughness=0.5)
    _, unshadowed = _backlit(gl, tmp_path)
    loaded, shadowed = _backlit(gl, tmp_path, shadows=", shadows: true")
    assert np.allclose(shadowed[TOWARDS_LIGHT], unshadowed[TOWARDS_LIGHT], rtol=0.02, atol=1e-3)
    blocked_loaded, blocked = _backlit(gl, tmp_path, shadows=", shadows: true", blocker=BLOCKER)
    assert float(blocked[TOWARDS_LIGHT].max()) < 0.05 * float(unshadowed[TOWARDS_LIGHT].max())
    # the reference alike: its shadow ray leaves from the far side (what is left there is
    # the lit red box, seen through the rough pane by the paths that scatter towards it)
    ref = render_reference(blocked_loaded, 0, spp=2).linear
    assert float(ref[TOWARDS_LIGHT].mean()) < 0.05 * float(unshadowed[TOWARDS_LIGHT].mean())
    ref = render_reference(loaded, 0, spp=2).linear
    assert float(ref[TOWARDS_LIGHT].mean()) == pytest.approx(float(shadowed[TOWARDS_LIGHT].mean()), rel=0.1)
