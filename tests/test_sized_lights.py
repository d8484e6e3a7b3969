"""Lights with a size (a point or spot light's ``radius``, a directional light's
``angular_diameter``): a box on a floor against the CPU reference, which draws the light's
directions over its cone (scenerender/raytrace/sized_lights.py), by region
(scenerender/tools/penumbra.py: umbra, penumbra band, open ground, each smoothed over
3 x 3 pixels of one surface); the penumbra's growth with the caster's height; and size 0
rendering today's bytes with today's programs.

Images are 160 x 120, the reference 8 x 8 samples a pixel (about 5 s each)."""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import scenerender
from scenerender.cli import main
from scenerender.raytrace import render_reference
from scenerender.tools.penumbra import penumbra_errors, penumbra_regions
from scenerender.raytrace.sized_lights import sphere_directions
from scenerender.rendering.features import SceneFeatures
from scenerender.rendering.renderer import plan

SPP = 8

# the scene: a sphere light of radius 0.3 m, 2.5 m above the floor beside a 1 m box
BOX_ON_FLOOR = """
render: {{size: [160, 120], background: [0, 0, 0]}}
camera: {{position: [0, 4.5, 4.5], target: [0, 0, 0.2], fov: 45}}
lights:
  - {light}
objects:
  - mesh: {{primitive: plane, size: 8}}
    material: {{diffuse: [0.8, 0.8, 0.8], specular: [0, 0, 0]}}
  - mesh: {{primitive: box, size: [1, {height}, 1]}}
    position: [0, {centre}, 0]
    material: {{diffuse: [0.8, 0.8, 0.8], specular: [0, 0, 0]}}
"""
SPHERE_LIGHT = "{type: point, position: [0.9, 2.5, 0], radius: 0.3, attenuation: [0, 0, 1], intensity: 6, shadows: true}"


def box_scene(light: str = SPHERE_LIGHT, height: float = 1.0, overrides=(), lift: float = 0.0) -> scenerender.Scene:
    """The box ``height`` tall, its base ``lift`` above the floor."""
    text = BOX_ON_FLOOR.format(light=light, height=height, centre=lift + height / 2)
    return scenerender.Scene.from_yaml(text, ".", list(overrides))


def gpu_linear(scene, gl) -> np.ndarray:
    with scenerender.Renderer(scene, gl=gl, want_linear=True) as renderer:
        return renderer.render(0).linear[:, :, :3].astype(np.float64)


def gpu_pixels(scene, gl) -> np.ndarray:
    with scenerender.Renderer(scene, gl=gl) as renderer:
        return renderer.render(0).pixels


@pytest.fixture(scope="module")
def sphere_reference():
    return render_reference(box_scene(), 0, spp=SPP)


# -- against the reference ------------------------------------------------------------------

def test_box_under_a_sphere_light_matches_the_reference_by_region(gl, sphere_reference):
    """Penumbra band: RMS within 10 % of the band's mean (the goal; measured 6-7 %) and its
    mean within 3 %; open ground within 2 %; the umbra lets through under 2 % of the lit
    level. Breaking the penumbra's width (half or twice as wide) fails the band's RMS."""
    errors = penumbra_errors(sphere_reference, gpu_linear(box_scene(), gl))
    assert errors["penumbra_pixels"] > 300
    assert errors["penumbra_rms"] < 10.0, errors
    assert abs(errors["penumbra_bias"]) < 3.0, errors
    assert abs(errors["open_bias"]) < 2.0 and errors["open_rms"] < 2.0, errors
    assert abs(errors["umbra_leak"]) < 2.0, errors


def test_a_point_light_of_equal_power_misses_the_band(gl, sphere_reference):
    """What the test above catches: today's hard shadow is right on open ground and off by
    more than 25 % in the band (32 %; 46 % unsmoothed, the issue's 45 %)."""
    errors = penumbra_errors(sphere_reference, gpu_linear(box_scene(overrides=["lights[0].radius=0"]), gl))
    assert abs(errors["open_bias"]) < 2.0
    assert errors["penumbra_rms"] > 25.0, errors


def band_area(visibility: np.ndarray, floor: np.ndarray) -> float:
    """Floor pixels partly lit, each counted by 4 v (1 - v) for its visibility v (1 at half
    lit, 0 in the open and the umbra): an area that needs no threshold."""
    v = np.clip(visibility[floor], 0.0, 1.0)
    return float(np.sum(4.0 * v * (1.0 - v)))


def test_the_penumbra_widens_with_the_casters_height_as_the_references_does(gl):
    """A 5 cm plate held 0.3 m and 1.0 m above the floor: the partly lit floor grows with
    the height (the penumbra's width by about 5x, the outline by 1.5x), on the GPU by the
    reference's factor within 20 % (the GPU's visibility: the frame over the same frame
    without shadows). A penumbra of constant width (a wider PCF filter) grows by 1.5x."""
    growth = {}
    for who in ("gpu", "reference"):
        areas = []
        for lift in (0.3, 1.0):
            scene = box_scene(height=0.05, lift=lift)
            if who == "gpu":
                lit = gpu_linear(scene, gl).mean(axis=2)
                open_sky = gpu_linear(box_scene(height=0.05, lift=lift, overrides=["lights[0].shadows=false"]),
                                      gl).mean(axis=2)
                visibility = np.where(open_sky > 1e-4, lit / np.maximum(open_sky, 1e-4), 1.0)
                floor = open_sky > 1e-4
            else:
                ref = render_reference(scene, 0, spp=SPP)
                visibility = 1.0 - ref.shadow[:, :, 0]
                floor = ~ref.mixed & (ref.object == 0)
            areas.append(band_area(visibility, floor))
        growth[who] = areas[1] / areas[0]
    assert growth["reference"] > 3.0, growth
    assert abs(growth["gpu"] / growth["reference"] - 1.0) < 0.2, growth


@pytest.mark.parametrize("light, band_rms", [
    ("{type: spot, position: [0.9, 2.5, 0], direction: [-0.3, -1, 0], outer_angle: 70, inner_angle: 60, "
     "radius: 0.3, attenuation: [0, 0, 1], intensity: 6, shadows: true}", 10.0),
    ("{type: directional, direction: [-0.5, -1, 0.2], angular_diameter: 8, intensity: 1.2, shadows: true}", 10.0),
])
def test_a_spot_and_a_directional_light_with_a_size_match_the_reference(gl, light, band_rms):
    """The same box under a spot light of radius 0.3 and a sun 8 degrees wide: band within
    10 %, open ground within 2 %."""
    scene = box_scene(light)
    errors = penumbra_errors(render_reference(scene, 0, spp=SPP), gpu_linear(scene, gl))
    assert errors["penumbra_pixels"] > 100
    assert errors["penumbra_rms"] < band_rms, errors
    assert abs(errors["open_bias"]) < 2.0, errors


RECT_LIGHT = ("{type: rect, position: [0.9, 2.5, 0], direction: [0, -1, 0], width: 1, height: 0.5, intensity: 20, "
              "shadows: true}")
DISK_LIGHT = "{type: disk, position: [0.9, 2.5, 0], direction: [-0.2, -1, 0], radius: 0.4, intensity: 20, shadows: true}"


@pytest.mark.parametrize("light, band_rms", [(RECT_LIGHT, 8.5), (DISK_LIGHT, 7.0)], ids=["rect", "disk"])
def test_box_under_an_area_light_matches_the_reference_by_region(gl, light, band_rms):
    """The issue's 1 x 0.5 m rectangle (and a disk of radius 0.4, tilted), 2.5 m above the
    floor beside the box: the lit floor within 2 %, the umbra within 2 % of the lit level;
    the penumbra band's mean within 3 % and its RMS within 8.5 % for the rectangle, 7 % for
    the disk (the goal is 10 %; measured: the rectangle 7.8 % and +1.0 %, 6.1 % against a
    reference of 16 x 16 samples; the disk 5.6 % and -0.1 %). What each bound catches: the
    filter's taps unweighted by what their point of the light gives (the band's outer half
    too dark) read 10.2 % (10.9 % and -4.4 % before the filter below), the disk 7.8 % and
    -5.0 %; the rectangle's filter on the R2 sequence shifted along the diagonal (stripes
    along the box's foot) 8.7 %; a disc filter of the rectangle's area 16 %."""
    scene = box_scene(light)
    errors = penumbra_errors(render_reference(scene, 0, spp=SPP), gpu_linear(scene, gl))
    assert errors["penumbra_pixels"] > 300
    assert errors["penumbra_rms"] < band_rms, errors
    assert abs(errors["penumbra_bias"]) < 3.0, errors
    assert abs(errors["open_bias"]) < 2.0 and errors["open_rms"] < 3.0, errors
    assert abs(errors["umbra_leak"]) < 2.0, errors


def test_a_sphere_light_cut_by_the_horizon_lights_the_floor_as_the_reference(gl):
    """A sphere of radius 0.6 whose centre is 0.3 above the floor: near it, part of the
    sphere is below the floor's horizon (sphere_cosine's exact integral). Every 8 x 8 block
    of open floor within 5 % of the reference's (a pixel of it alone is noisy by 10 %: the
    light fills a wide cone), the whole open floor within 2 %."""
    light = "{type: point, position: [1.5, 0.3, 0], radius: 0.6, attenuation: [0, 0, 1], intensity: 1}"
    scene = box_scene(light)
    ref = render_reference(scene, 0, spp=SPP)
    gpu = gpu_linear(scene, gl)
    assert abs(penumbra_errors(ref, gpu)["open_bias"]) < 2.0
    floor = (~ref.mixed & (ref.object == 0)).reshape(15, 8, 20, 8).all(axis=(1, 3))
    blocks = [image.mean(axis=2).reshape(15, 8, 20, 8).mean(axis=(1, 3)) for image in (gpu, ref.linear)]
    lit = floor & (blocks[1] > 0.02)
    assert lit.sum() > 40
    assert np.abs(blocks[0][lit] / blocks[1][lit] - 1.0).max() < 0.05


def test_the_reference_draws_the_spheres_irradiance():
    """sphere_directions: the mean of N.L x weight is the sphere's irradiance over
    pi L sin^2 sigma, N.L itself while the sphere is above the horizon."""
    rng = np.random.Generator(np.random.PCG64(5))
    count = 200_000
    n = np.array([0.0, 1.0, 0.0])
    for angle in (0.0, 40.0):
        theta = math.radians(angle)
        to_centre = np.tile([math.sin(theta) * 3.0, math.cos(theta) * 3.0, 0.0], (count, 1))
        l, weight, reach = sphere_directions(to_centre, 0.5, rng)
        assert np.allclose(np.linalg.norm(l, axis=1), 1.0)
        assert float((l @ n * weight).mean()) == pytest.approx(math.cos(theta), rel=3e-3)
        assert np.all(reach <= 3.0) and np.all(reach >= 2.5 - 1e-9)


# -- size 0 is today's renderer --------------------------------------------------------------

SIZE_ZERO_LIGHTS = [
    ("{type: point, position: [0.9, 2.5, 0], attenuation: [0, 0, 1], intensity: 6, shadows: true}", "radius"),
    ("{type: spot, position: [0.9, 2.5, 0], direction: [-0.3, -1, 0], outer_angle: 60, shadows: true}", "radius"),
    ("{type: directional, direction: [-0.5, -1, 0.2], shadows: true}", "angular_diameter"),
]


@pytest.mark.parametrize("light, key", SIZE_ZERO_LIGHTS)
def test_size_zero_renders_the_same_bytes_with_the_same_programs(gl, light, key):
    absent = box_scene(light)
    zero = box_scene(light, overrides=[f"lights[0].{key}=0"])
    assert np.array_equal(gpu_pixels(absent, gl), gpu_pixels(zero, gl))
    for scene in (absent, zero):
        defines = SceneFeatures.of(scene.world, samples=4).lighting_defines()
        assert not any("SIZED" in name or "SOFT" in name for name in defines), defines


@pytest.mark.parametrize("light, key, value", [(light, key, "0.2") for light, key in SIZE_ZERO_LIGHTS])
def test_a_size_adds_its_defines_and_changes_the_frame(gl, light, key, value):
    """The other side of the test above: a size shows up in the defines and the image."""
    sized = box_scene(light, overrides=[f"lights[0].{key}={value}"])
    defines = SceneFeatures.of(sized.world, samples=4).lighting_defines()
    assert "SOFT_SHADOWS" in defines and any(name.endswith("_LIGHT_SIZED") for name in defines)
    assert not np.array_equal(gpu_pixels(box_scene(light), gl), gpu_pixels(sized, gl))


@pytest.mark.parametrize("light, key, value", [
    (SIZE_ZERO_LIGHTS[0][0], "radius", "-1"), (SIZE_ZERO_LIGHTS[2][0], "angular_diameter", "30"),
    (RECT_LIGHT, "width", "0"), (DISK_LIGHT, "radius", "-0.5"), (RECT_LIGHT, "attenuation", "[1, 0, 0]"),
])
def test_a_bad_size_is_exit_2_naming_the_key(tmp_path, light, key, value):
    given = re.search(rf"\b{key}: [^,}}]+", light)
    light = light.replace(given.group(0), f"{key}: {value}") if given else light[:-1] + f", {key}: {value}}}"
    (tmp_path / "s.yaml").write_text(f"lights:\n  - {light}\nobjects: []\n")
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "s.yaml")])
    assert result.exit_code == 2, result.output
    assert f"lights[0].{key}" in result.stderr and "s.yaml:2" in result.stderr, result.stderr
    assert "Traceback" not in result.stderr


def test_a_sized_lights_map_is_1024_px_unless_the_scene_sets_it():
    """SIZED_SHADOW_DEFAULTS (chosen on benchmarks/quality/sized_lights.md); a point light
    keeps render.shadows' 2048."""
    sizes = {}
    for radius in (0.0, 0.3):
        scene = box_scene(overrides=[f"lights[0].radius={radius}"])
        sizes[radius] = scene.world.lights[0].shadow.size
    assert sizes == {0.0: 2048, 0.3: 1024}
    chosen = box_scene(overrides=["render.shadows.size=4096"])
    assert chosen.world.lights[0].shadow.size == 4096


@pytest.mark.gl
def test_the_umbra_beside_two_boxes_under_a_rect_light_against_the_reference(gl):
    # benchmarks/quality/rect_umbra.py's room at 128x96: a 1 x 1 m rectangle light over a
    # Lambert floor with a short and a tall box. The floor's umbra (every one of the
    # reference's 64 samples a pixel blocked) gets under 0.6 % of the lit floor's light
    # (measured 0.42 %; 0.35 % at 256x192): a bound on what is left, not the goal of none
    # (docs/limitations.md). Without the soft shadow's fade where the light's centre is
    # hidden (shaders/lighting/soft_shadows.glsl), its one blocker depth widens the
    # penumbra beside a box's foot and the umbra gets 1.24 %. The shadowed floor within 5 %
    # and the open floor within 2 %.
    from quality_benchmarks import quality_module

    umbra = quality_module("rect_umbra")
    scene = scenerender.load(umbra.SCENE, ["render.size=[128,96]"])
    reference = render_reference(scene, 0, spp=SPP)
    found = umbra.floor_errors(reference, render_reference(scene, 0, spp=16), gpu_linear(scene, gl))
    assert found["umbra pixels"] > 100, found
    assert found["umbra leak %"] < 0.6, found
    assert abs(found["shadowed floor ratio"] - 1.0) < 0.05, found
    assert abs(found["open floor %"]) < 2.0, found


@pytest.mark.gl
@pytest.mark.parametrize("casters, within", [("solid", True), ("surface", False)])
def test_solid_casters_keep_the_cornell_box_floor_beside_the_tall_box_dark(gl, casters, within):
    # benchmarks/quality/scenes/cornell_box.yaml, direct light only, against the path
    # tracer's kept direct-only image: the floor in the boxes' shadow (mostly the umbra
    # beside the tall box's foot, scenerender/tools/bounce_regions.py) within 12 % of the
    # truth with render.shadows.casters: solid (measured -7.7 %); the soft shadow of the
    # nearest surface alone lets the light the box's side blocks through there (+125 %).
    from scenerender.tools.bounce_regions import bounce_regions

    quality = Path(__file__).resolve().parent.parent / "benchmarks" / "quality"
    scene_file = quality / "scenes" / "cornell_box.yaml"
    direct = np.load(quality / "references" / "cornell_box_direct.npy").astype(np.float64)
    objects = np.load(quality / "references" / "cornell_box_objects.npy")

    def render(overrides):
        return gpu_linear(scenerender.Scene.from_yaml(scene_file.read_text(), scene_file.parent, overrides), gl)

    normals = render(["render.mode=normals", "render.samples=1"]) * 2.0 - 1.0
    normals /= np.maximum(np.linalg.norm(normals, axis=2, keepdims=True), 1e-9)
    floor = bounce_regions(objects, normals, direct)["floor_in_shadow"]
    image = render([f"lights[0].shadows={{casters: {casters}}}"])
    error = image[floor].mean() / direct[floor].mean() - 1.0
    assert (abs(error) < 0.12) == within, f"casters {casters}: the floor in shadow {100 * error:+.1f} %"


SPOT_LIGHT = ("{type: spot, position: [0.9, 2.5, 0], direction: [-0.3, -1, 0], outer_angle: 70, radius: 0.3, "
              "attenuation: [0, 0, 1], intensity: 6, shadows: true}")


def pass_names(scene) -> list:
    world = scene.world
    return plan(world, world.settings.size, world.settings.samples).compiled.pass_names


SUN_LIGHT = "{type: directional, direction: [-0.5, -1, 0.2], angular_diameter: 8, intensity: 1.2, shadows: true}"


@pytest.mark.parametrize("light, applies", [(SPHERE_LIGHT, True), (RECT_LIGHT, True), (DISK_LIGHT, True),
                                            (SPOT_LIGHT, True), (SUN_LIGHT, False)],
                         ids=["sphere", "rect", "disk", "spot", "sun"])
def test_solid_casters_add_the_back_faces_where_they_apply(light, applies):
    """render.shadows.casters: solid adds a back-face shadow pass and its defines for a
    sized light seen in perspective, and nothing for a sun (its penumbra left as filtered)."""
    solid = box_scene(light, overrides=["render.shadows.casters=solid"])
    defines = SceneFeatures.of(solid.world, samples=4).lighting_defines()
    assert ("SOLID_CASTERS" in defines) == applies, defines
    assert any(name.startswith("shadow_back:") for name in pass_names(solid)) == applies
    assert not any(name.startswith("shadow_back:") for name in pass_names(box_scene(light)))


@pytest.mark.gl
def test_casters_surface_renders_the_bytes_of_an_unset_key(gl):
    """`casters: surface` is the default: the same programs and the same bytes as no key."""
    unset = box_scene(RECT_LIGHT)
    surface = box_scene(RECT_LIGHT, overrides=["render.shadows.casters=surface"])
    assert (SceneFeatures.of(unset.world, samples=4).lighting_defines()
            == SceneFeatures.of(surface.world, samples=4).lighting_defines())
    assert np.array_equal(gpu_pixels(unset, gl), gpu_pixels(surface, gl))


@pytest.mark.parametrize("light", [SPHERE_LIGHT, SPOT_LIGHT, RECT_LIGHT, DISK_LIGHT],
                         ids=["sphere", "spot", "rect", "disk"])
def test_solid_casters_keep_the_band_within_6_percent(gl, light):
    """The box under each sized light with render.shadows.casters: solid: the penumbra
    band within 6 % RMS and 3 % of its mean, the umbra within 1 % of the lit level
    (measured 5.0-5.4 % RMS, -1.5..+0.3 %; the filter alone reads 6.1-8.2 % RMS). Taking
    the receiver's whole bias at every point of the march (it hides a box's top from rays
    that graze its edge) fails the spot light (+15 %) and the rectangle (+3.6 %)."""
    scene = box_scene(light, overrides=["render.shadows.casters=solid"])
    errors = penumbra_errors(render_reference(box_scene(light), 0, spp=SPP), gpu_linear(scene, gl))
    assert errors["penumbra_pixels"] > 300
    assert errors["penumbra_rms"] < 6.0, errors
    assert abs(errors["penumbra_bias"]) < 3.0, errors
    assert abs(errors["umbra_leak"]) < 1.0, errors
    assert abs(errors["open_bias"]) < 2.0, errors
