"""The environment light (``type: environment``): its file reading, its spherical harmonics
and equirectangular mapping (no GL), the scene checks, and what the GPU draws with it: a
white furnace, the classic switch, rotation, animation without prefiltering again, and the
prefiltered lookups against the CPU's numbers."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import scenerender
from scenerender.cli import main
from scenerender.errors import UserError
from scenerender.scene.image_files import ImageError
from scenerender.world.environment_light import (
    cube_to_equirect, diffuse_radiance, equirect_directions, equirect_uv, project_sh, sample_cube, sample_equirect,
    sh_basis, texel_solid_angles, world_to_image,
)
from scenerender.world.environment_files import read_hdr, write_hdr

SIZE = 48


def sky(height: int = 64, width: int = 128, function=None) -> np.ndarray:
    """(H, W, 3) radiance function(direction) over an equirectangular image."""
    directions = equirect_directions(height, width)
    return np.asarray(function(directions), dtype=np.float32)


def scene_text(light: str = "{type: environment}", material: str = "{base_color: [1, 1, 1], roughness: 1}",
               shading: str = "pbr", extra: str = "") -> str:
    return f"""
render: {{size: [{SIZE}, {SIZE}], samples: 1, shading: {shading}, background: [0, 0, 0],
          output_transform: linear{extra}}}
camera: {{position: [0, 0, 5], target: [0, 0, 0], projection: orthographic, height: 2.4}}
lights: [{light}]
materials: {{m: {material}}}
objects:
  - {{mesh: {{primitive: sphere, radius: 1, segments: 64, rings: 32}}, material: m}}
"""


def linear_render(gl, text: str, folder, frames=(0,)) -> list[np.ndarray]:
    scene = scenerender.Scene.from_yaml(text, folder)
    with scenerender.Renderer(scene, gl=gl, want_linear=True) as renderer:
        return [renderer.render(i).linear[..., :3].astype(np.float64) for i in frames]


def disc(radius: float = 0.8) -> np.ndarray:
    """(SIZE, SIZE) bool: pixels well inside the sphere's silhouette (radius 1 of 1.2)."""
    y, x = (np.mgrid[0:SIZE, 0:SIZE] + 0.5) / SIZE * 2.4 - 1.2
    return x * x + y * y < radius * radius


# -- files -------------------------------------------------------------------------------------

def test_hdr_files_round_trip_within_rgbe_precision(tmp_path):
    linear = np.random.default_rng(1).uniform(0.0, 50.0, size=(5, 7, 3)).astype(np.float32)
    write_hdr(tmp_path / "e.hdr", linear)
    back = read_hdr(tmp_path / "e.hdr", 10**6)
    assert back.shape == (5, 7, 3)
    # 8-bit mantissas shared by the brightest channel: within 1/128 of it
    assert np.all(np.abs(back - linear) <= linear.max(axis=2, keepdims=True) / 128 + 1e-6)


def test_run_length_encoded_hdr_scanlines_are_read(tmp_path):
    width = 9
    row = bytes([2, 2, 0, width])
    # R: a run of 9 x 128; G: 9 literals; B: a run of 9 x 0; E: a run of 9 x 129 (scale 2^-7)
    row += bytes([128 + 9, 128]) + bytes([9]) + bytes(range(9)) + bytes([128 + 9, 0]) + bytes([128 + 9, 129])
    header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 9\n"
    (tmp_path / "rle.hdr").write_bytes(header + row + row)
    image = read_hdr(tmp_path / "rle.hdr", 10**6)
    assert image.shape == (2, 9, 3)
    assert np.allclose(image[..., 0], 128 / 128.0)  # 128 x 2^(129 - 136)
    assert np.allclose(image[1, :, 1], np.arange(9) / 128.0)
    assert np.all(image[..., 2] == 0)


@pytest.mark.parametrize("data, reason", [
    (b"P6 not an hdr", "not a Radiance HDR file"),
    (b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n" + bytes(10), "ends before its last pixel"),
    (b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 4 +X 4\n" + bytes(64), "orientation"),
])
def test_a_broken_hdr_file_is_an_image_error(tmp_path, data, reason):
    (tmp_path / "bad.hdr").write_bytes(data)
    with pytest.raises(ImageError, match=reason):
        read_hdr(tmp_path / "bad.hdr", 10**6)


# -- the mapping and the spherical harmonics (no GL) ---------------------------------------------

def test_the_equirectangular_mapping_puts_minus_z_in_the_middle_and_up_on_top():
    u, v = equirect_uv(np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]))
    assert u[:2] == pytest.approx([0.5, 0.75]) and v == pytest.approx([0.5, 0.5, 0.0, 1.0])
    directions = equirect_directions(8, 16)
    back_u, back_v = equirect_uv(directions)
    assert back_u[0] == pytest.approx((np.arange(16) + 0.5) / 16)
    assert back_v[:, 0] == pytest.approx((np.arange(8) + 0.5) / 8)
    assert texel_solid_angles(8, 16).sum() * 16 == pytest.approx(4 * np.pi)


def test_the_sh_basis_is_orthonormal_up_to_band_4():
    height, width = 256, 512
    basis = sh_basis(equirect_directions(height, width).reshape(-1, 3), 4)
    weights = np.broadcast_to(texel_solid_angles(height, width), (height, width)).reshape(-1, 1)
    gram = (basis * weights).T @ basis
    assert np.abs(gram - np.eye(25)).max() < 1e-3


@pytest.mark.parametrize("order, up, side", [(1, 0.5833, 0.25), (2, 0.6615, 0.2110), (4, 0.6654, 0.2124)])
def test_the_diffuse_term_of_a_sky_brighter_at_the_zenith(order, up, side):
    # radiance max(y, 0): a surface facing up receives 2 pi / 3, so reflects 2/3 (white
    # Lambert); facing down nothing; sideways 1/4 exactly (the 1/4 of band 0 and 1 alone).
    # The truncated series approaches them band by band.
    image = sky(function=lambda d: np.repeat(np.maximum(d[..., 1:2], 0.0), 3, axis=-1))
    normals = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    values = diffuse_radiance(project_sh(image, order), normals)[:, 0]
    assert values == pytest.approx([up, side], abs=2e-3)
    assert abs(2.0 / 3.0 - values[0]) <= abs(2.0 / 3.0 - 0.5833)


def test_a_uniform_environment_gives_its_own_radiance_to_every_direction():
    image = np.full((32, 64, 3), 0.7, np.float32)
    normals = equirect_directions(4, 8).reshape(-1, 3)
    assert diffuse_radiance(project_sh(image, 2), normals) == pytest.approx(np.full((32, 3), 0.7), abs=2e-3)


def test_a_skybox_becomes_an_equirectangular_image_facing_the_right_way():
    faces = np.zeros((6, 4, 4, 3), np.float32)
    for face in range(6):
        faces[face] = face + 1  # +X 1, -X 2, +Y 3, -Y 4, +Z 5, -Z 6
    axes = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    assert sample_cube(faces, axes)[:, 0] == pytest.approx([1, 2, 3, 4, 5, 6])
    image = cube_to_equirect(faces)
    assert sample_equirect(image, axes * 0.999 + 0.001)[:, 0] == pytest.approx([1, 2, 3, 4, 5, 6], abs=0.05)


def test_rotation_turns_the_image_about_plus_y():
    # turned 90 degrees counter-clockwise seen from above: what was at -Z now comes from -X
    to_image = world_to_image(90.0)
    assert to_image @ np.array([-1.0, 0.0, 0.0]) == pytest.approx([0.0, 0.0, -1.0])


# -- the scene file ------------------------------------------------------------------------------

def test_errors_name_the_key(tmp_path):
    (tmp_path / "broken.hdr").write_bytes(b"not an image")
    cases = {
        "lights: [{type: environment}]": "lights[0].image",  # no skybox for image: sky
        "lights: [{type: environment, image: e.txt}]": "lights[0].image",
        "lights: [{type: environment, image: broken.hdr}]": "lights[0].image",
        "lights: [{type: environment, image: broken.hdr}, {type: environment, image: broken.hdr}]": "lights[1].type",
        "lights: [{type: environment, image: broken.hdr, sh_order: 5}]": "lights[0].sh_order",
    }
    runner = CliRunner()
    for lights, key in cases.items():
        (tmp_path / "s.yaml").write_text(f"{lights}\nobjects: []\n")
        result = runner.invoke(main, ["validate", str(tmp_path / "s.yaml")])
        assert result.exit_code == 2, (lights, result.output)
        assert key in result.stderr and "s.yaml:1" in result.stderr, (lights, result.stderr)
        assert "Traceback" not in result.stderr


def test_an_environment_needs_no_gl_to_load(tmp_path):
    write_hdr(tmp_path / "e.hdr", sky(function=lambda d: np.ones(d.shape)))
    loaded = scenerender.Scene.from_yaml("lights: [{type: environment, image: e.hdr, intensity: 2}]\nobjects: []",
                                         tmp_path)
    environment = loaded.world.environment
    assert environment.image.shape == (64, 128, 3) and loaded.world.lights == []
    assert environment.state(0.0).scale == pytest.approx([2, 2, 2])
    assert environment.irradiance_map == pytest.approx(np.ones((32, 64, 3)), abs=1e-3)


# -- on the GPU -----------------------------------------------------------------------------------

def uniform_file(folder, value: float = 1.0) -> None:
    write_hdr(folder / "e.hdr", np.full((16, 32, 3), value, np.float32))


def test_white_furnace_a_rough_white_dielectric_disappears(gl, tmp_path):
    # a white, non-metal, fully rough sphere in a uniform white environment reflects what
    # reaches it; the split sum with the fitted hemisphere integrals gives 0.95-1.0 (the
    # BRDF itself loses 2-5 % at grazing angles, measured by the reference's furnace test)
    uniform_file(tmp_path)
    image = linear_render(gl, scene_text("{type: environment, image: e.hdr}"), tmp_path)[0]
    values = image[disc()]
    assert values.min() > 0.93 and values.max() < 1.02
    assert abs(values.mean() - 0.98) < 0.03
    assert np.ptp(values) < 0.06  # uniform: no seams, no poles


def test_a_metal_reflects_the_environment_around_its_reflection_direction(gl, tmp_path):
    # a mirror-like white metal in an environment bright (4) in the +Z hemisphere, dark
    # (0.25) in the -Z one: facing the camera (+Z) it reflects +Z, bright; the rim reflects
    # the directions behind it. Linear in intensity.
    write_hdr(tmp_path / "e.hdr", sky(function=lambda d: np.where(d[..., 2:3] > 0, 4.0, 0.25) * np.ones(3)))
    text = scene_text("{type: environment, image: e.hdr}", "{base_color: [1, 1, 1], metallic: 1, roughness: 0.05}")
    image = linear_render(gl, text, tmp_path)[0]
    centre = image[SIZE // 2 - 3:SIZE // 2 + 3, SIZE // 2 - 3:SIZE // 2 + 3].mean()
    assert centre == pytest.approx(4.0, rel=0.05)
    doubled = linear_render(gl, text.replace("image: e.hdr", "image: e.hdr, intensity: 2"), tmp_path)[0]
    assert doubled[disc()] == pytest.approx(2 * image[disc()], rel=1e-2, abs=1e-3)
    # turned 180 degrees, the dark half is in front
    turned = linear_render(gl, text.replace("image: e.hdr", "image: e.hdr, rotation: 180"), tmp_path)[0]
    assert turned[SIZE // 2, SIZE // 2].mean() == pytest.approx(0.25, rel=0.1)


def test_classic_materials_get_the_diffuse_term_only_when_asked(gl, tmp_path):
    uniform_file(tmp_path, 0.5)
    material = "{diffuse: [0.8, 0.4, 0.2], ambient: [1, 1, 1], specular: [0, 0, 0]}"
    without = linear_render(gl, scene_text("{type: environment, image: e.hdr}", material, "blinn_phong"), tmp_path)[0]
    assert without[disc()].max() == 0.0
    with_it = linear_render(gl, scene_text("{type: environment, image: e.hdr, classic: true}", material,
                                           "blinn_phong"), tmp_path)[0]
    # a uniform environment of 0.5: Ka x base x 0.5 everywhere
    assert with_it[disc()] == pytest.approx(np.broadcast_to([0.4, 0.2, 0.1], with_it[disc()].shape), abs=4e-3)


def test_the_diffuse_lookup_matches_the_cpu_spherical_harmonics(gl, tmp_path):
    # a rough dielectric under a sky brighter at the zenith: its top is lit, its bottom not,
    # as the CPU's diffuse term says (times the material's diffuse weight)
    image = sky(function=lambda d: np.repeat(np.maximum(d[..., 1:2], 0.0), 3, axis=-1) * 2.0)
    write_hdr(tmp_path / "e.hdr", image)
    text = scene_text("{type: environment, image: e.hdr, classic: true}", "{diffuse: [1, 1, 1], specular: [0, 0, 0]}",
                      "blinn_phong")
    frame = linear_render(gl, text, tmp_path)[0]
    order = scenerender.Scene.from_yaml(text, tmp_path).world.environment.sh_order
    expected = diffuse_radiance(project_sh(image, order), np.array([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0],
                                                                    [0.0, 0.0, 1.0]]))
    top, bottom, centre = frame[SIZE // 2 - 19, SIZE // 2], frame[SIZE // 2 + 19, SIZE // 2], frame[SIZE // 2, SIZE // 2]
    assert centre == pytest.approx(expected[2], abs=0.02)
    assert top.mean() > 0.85 * expected[0].mean() and bottom.mean() < 0.2 * expected[0].mean()


def test_an_animated_environment_is_prefiltered_once(gl, tmp_path):
    uniform_file(tmp_path)
    text = scene_text("{type: environment, image: e.hdr, intensity: {keys: [[0, 1], [1, 3]]}}") + "output: {fps: 24}\n"
    scene = scenerender.Scene.from_yaml(text, tmp_path)
    with scenerender.Renderer(scene, gl=gl, want_linear=True, profile=True) as renderer:
        frames = [renderer.render(i).linear[..., :3] for i in (0, 12, 24)]
        runs = renderer.timings
    assert len(runs["environment_prefilter"]) == 1 and len(runs["opaque"]) == 3
    means = [float(f[disc()].mean()) for f in frames]
    assert means[1] == pytest.approx(2 * means[0], rel=0.02) and means[2] == pytest.approx(3 * means[0], rel=0.02)


def test_no_environment_pass_where_no_material_takes_its_light(tmp_path):
    uniform_file(tmp_path)
    text = scene_text("{type: environment, image: e.hdr}", "{diffuse: [1, 1, 1]}", "blinn_phong")
    result = CliRunner().invoke(main, ["graph", str(_write(tmp_path, text))])
    assert result.exit_code == 0, result.output
    assert "environment_prefilter" not in result.output
    result = CliRunner().invoke(main, ["graph", str(_write(tmp_path, text.replace("blinn_phong", "pbr")))])
    assert "environment_prefilter  static" in result.output


def _write(folder, text: str):
    path = folder / "scene.yaml"
    path.write_text(text)
    return path


def test_a_missing_environment_file_is_exit_2_with_its_key(tmp_path):
    (tmp_path / "s.yaml").write_text("lights: [{type: environment, image: nowhere.hdr}]\nobjects: []\n")
    result = CliRunner().invoke(main, ["render", str(tmp_path / "s.yaml"), "-o", str(tmp_path / "out.png")])
    assert result.exit_code == 2 and "lights[0].image" in result.stderr
    assert not (tmp_path / "out.png").exists()


def test_user_error_is_what_reading_raises(tmp_path):
    (tmp_path / "e.hdr").write_bytes(b"#?RADIANCE\n\n-Y 1 +X 1\n")
    with pytest.raises(UserError):
        read_hdr(tmp_path / "e.hdr", 10**6)


def test_an_exr_environment_is_read_as_linear_light(tmp_path):
    from scenerender.sinks.images import write_exr

    image = sky(16, 32, lambda d: np.stack([d[..., 0] + 2, d[..., 1] + 2, np.full(d.shape[:-1], 40.0)], axis=-1))
    write_exr(tmp_path / "e.exr", image)
    loaded = scenerender.Scene.from_yaml("lights: [{type: environment, image: e.exr}]\nobjects: []", tmp_path)
    assert loaded.world.environment.image == pytest.approx(image, rel=1e-6)  # floats above 1 kept


def test_image_sky_is_the_skybox_resampled_into_linear_light():
    loaded = scenerender.Scene.from_yaml("render: {skybox: assets/skybox/day}\nlights: [{type: environment}]\n"
                                         "objects: []", "scenes")
    image = loaded.world.environment.image
    assert image.shape == (512, 1024, 3) and image.max() <= 1.0
    # the day sky is blue above and grey-green below
    up, down = image[:64].mean(axis=(0, 1)), image[-64:].mean(axis=(0, 1))
    assert up[2] > up[0] and down[2] < up[2]


def test_the_footprint_option_spreads_a_sub_pixel_sun_over_what_the_pixel_covers(gl, tmp_path):
    # a sun 2 degrees across (radiance 2000) over a dim sky, reflected by a smooth metal ball
    # 48 px across: a pixel sees about 5 degrees of reflected directions, so the exact
    # lookup takes the sun at full radiance where a pixel's centre reflects it, or misses
    # it. The truth is the same ball drawn 8 times larger, each 8 x 8 block averaged; the
    # footprint option comes closer to it in the sun's light and spreads it over more pixels
    sun = np.array([0.3, 0.4, 1.0]) / np.linalg.norm([0.3, 0.4, 1.0])
    write_hdr(tmp_path / "e.hdr", sky(256, 512, lambda d: np.where(d @ sun > np.cos(np.radians(1.0)), 2000.0,
                                                                   0.1)[..., None] * np.ones(3)))
    text = scene_text("{type: environment, image: e.hdr, prefilter_size: 512}",
                      "{base_color: [1, 1, 1], metallic: 1, roughness: 0}")
    fine = linear_render(gl, text.replace(f"size: [{SIZE}, {SIZE}]", f"size: [{SIZE * 8}, {SIZE * 8}]"), tmp_path)[0]
    truth = fine.reshape(SIZE, 8, SIZE, 8, 3).mean(axis=(1, 3))[disc(0.95)].sum(axis=1)
    exact = linear_render(gl, text, tmp_path)[0][disc(0.95)].sum(axis=1)
    spread = linear_render(gl, text.replace("prefilter_size: 512", "prefilter_size: 512, footprint: true"),
                           tmp_path)[0][disc(0.95)].sum(axis=1)
    sunlit = lambda values: np.sort(values)[-12:].sum()  # the brightest pixels: the sun's
    # measured: truth 492, exact 3.6 (no pixel centre reflects the sun), footprint 397
    assert abs(sunlit(spread) - sunlit(truth)) < abs(sunlit(exact) - sunlit(truth))
    assert (spread > 0.9).sum() > (exact > 0.9).sum()  # 54 pixels against 0


# -- against the reference ------------------------------------------------------------------------

QUALITY_SCENE = Path(__file__).resolve().parent.parent / "benchmarks" / "quality" / "scenes" / "environment.yaml"


@pytest.fixture(scope="module")
def environment_reference():
    """The environment accuracy scene at 160x120 by the reference renderer (4x4 samples a
    pixel, 8 directions each: 128 a pixel; its noise in a sphere's mean is under 1 %)."""
    from scenerender.raytrace.render import render_reference

    scene = scenerender.load(QUALITY_SCENE, ["render.size=[160,120]"])
    return render_reference(scene, 0, spp=4, environment_samples=8)


def sphere_errors(gl, reference, overrides=()) -> dict:
    """{sphere name: (3,) relative error of the GPU's mean linear colour over the sphere's
    pixels (silhouettes left out) against the reference's}."""
    scene = scenerender.load(QUALITY_SCENE, ["render.size=[160,120]", *overrides])
    with scenerender.Renderer(scene, gl=gl, want_linear=True) as renderer:
        linear = renderer.render(0).linear[..., :3].astype(np.float64)
    errors = {}
    for index, obj in enumerate(scene.world.objects):
        inside = (reference.object == index) & ~reference.mixed
        truth = reference.linear[inside].mean(axis=0)
        errors[obj.name] = linear[inside].mean(axis=0) / truth - 1.0
    return errors


@pytest.mark.gl
def test_the_gpu_environment_light_against_the_reference(gl, environment_reference):
    # each sphere's mean colour within 15 %; measured (red, green, blue), with the
    # environment's visibility (its default): silver 0.3 within 2.2 %, copper 0.55 6.3 %,
    # aluminium 0.8 -13 % (the split sum's N = V = R prefilter under a sun), the dielectrics
    # within 5.3 % (6.5 % without visibility: the neighbours' occlusion, which the reference
    # has, is 3-6 % of their light). Gold 0.1 is +92 %: a sun reflection smaller than a
    # pixel, taken at the pixel's centre; the footprint option brings it to +36 %
    errors = sphere_errors(gl, environment_reference)
    for name, error in errors.items():
        if name != "gold 0.1":
            assert np.abs(error).max() < 0.15, (name, error)
    assert errors["gold 0.1"].max() > 0.5
    spread = sphere_errors(gl, environment_reference, ["lights[0].footprint=true"])
    assert np.abs(spread["gold 0.1"]).max() < 0.5 * errors["gold 0.1"].max()


# -- the image as the background ---------------------------------------------------------------

def _background_text(extra: str, samples: int) -> str:
    return f"""
render: {{size: [32, 24], samples: {samples}, background: [0, 0, 0], output_transform: linear}}
camera: {{position: [0, 0, 0], target: [0, 0, -1], fov: 30}}
lights: [{{type: environment, image: e.hdr, background: true, intensity: 2{extra}}}]
objects:
  - {{mesh: {{primitive: box, size: 0.1}}, position: [0, -50, 0]}}
"""


@pytest.mark.parametrize("samples", [1, 4])
def test_background_true_draws_the_image_behind_the_scene_turned_by_rotation(gl, tmp_path, samples):
    # the image: 0.25 towards -Z, 0.75 towards +Z, times intensity 2; the camera looks
    # down -Z; turned 180 degrees the +Z half is in front (single-sampled: the skybox pass;
    # with MSAA: the resolve adds it behind the samples)
    write_hdr(tmp_path / "e.hdr", sky(function=lambda d: np.where(d[..., 2:3] > 0, 0.75, 0.25) * np.ones(3)))
    front = linear_render(gl, _background_text("", samples), tmp_path)[0]
    turned = linear_render(gl, _background_text(", rotation: 180", samples), tmp_path)[0]
    assert front == pytest.approx(0.5, abs=2e-3)
    assert turned == pytest.approx(1.5, abs=2e-3)


def test_background_false_draws_no_sky(tmp_path):
    uniform_file(tmp_path)
    text = scene_text("{type: environment, image: e.hdr}")
    result = CliRunner().invoke(main, ["graph", str(_write(tmp_path, text))])
    assert "skybox" not in result.output and "sky behind" not in result.output
    drawn = text.replace("image: e.hdr}", "image: e.hdr, background: true}")
    result = CliRunner().invoke(main, ["graph", str(_write(tmp_path, drawn))])
    assert "skybox" in result.output
