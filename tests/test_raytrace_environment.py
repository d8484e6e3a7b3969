"""The environment light in the CPU reference (scenerender/raytrace/environment_sampling.py): the
white furnace, a Lambert plane under a sky of known irradiance, the image's rotation, and
the importance sampler against a brute-force estimate of the same integral. Small images,
an orthographic camera, a few seconds each."""
from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

import scenerender
from scenerender import cli
from scenerender.errors import UserError
from scenerender.raytrace import environment_sampling as environment, render_reference, shading
from scenerender.world.environment_light import (
    EnvironmentState,
    equirect_directions,
    texel_solid_angles,
    world_to_image,
)
from scenerender.world.environment_files import write_hdr

SIZE = 48
SPHERE = """
render: {{size: [{size}, {size}], background: {background}, shading: pbr}}
camera: {{position: [0, 0, 6], target: [0, 0, 0], projection: orthographic, height: 2.4}}
lights: [{light}]
objects:
  - mesh: {{primitive: sphere, radius: 1, segments: 128, rings: 64}}
    material: {material}
"""


def sphere_scene(folder, light: str, material: str, background="[1, 1, 1]") -> scenerender.Scene:
    text = SPHERE.format(size=SIZE, background=background, light=light, material=material)
    return scenerender.Scene.from_yaml(text, str(folder))


def sphere_radius_map() -> np.ndarray:
    """(SIZE, SIZE) distance of each pixel centre from the sphere's centre, in radii."""
    ys, xs = np.mgrid[0:SIZE, 0:SIZE]
    return np.hypot(xs + 0.5 - SIZE / 2, ys + 0.5 - SIZE / 2) / (SIZE / 2.4)


@pytest.mark.parametrize("roughness", [1.0, 0.5])
def test_white_furnace_a_white_dielectric_reflects_the_brdf_s_energy(tmp_path, roughness):
    # a white, non-metal sphere in a uniform white environment (a constant 1.0 .hdr, 256
    # directions a sample, 2x2 samples a pixel) against the same sphere under a white
    # ambient light by the GPU's formula: the BRDF's hemisphere integral, fitted within
    # 0.007 (scenerender.raytrace.ambient_fit). Inside 0.9 radii, away from edges (1020
    # pixels): the mean within 1 % of the integral's, every pixel within 3 % of its own;
    # roughness 1 is uniform, every pixel within 3 % of the mean, the mean within 0.01 of
    # 0.977 (measured at 48x48, roughness 1 / 0.5: mean ratio 0.9999 / 0.9998, pixels
    # 0.985..1.013 / 0.980..1.017 of the integral; mean 0.975 / 1.006; at roughness 1 every
    # pixel within 1.6 % of the mean). A GGX pdf without the reflection's Jacobian gives a
    # mean ratio of 0.75, one without the mixture (the cosine pdf only) 0.90 at roughness 1
    write_hdr(tmp_path / "white.hdr", np.ones((8, 16, 3)))
    material = f"{{base_color: [1, 1, 1], metallic: 0, roughness: {roughness}}}"
    lit = render_reference(sphere_scene(tmp_path, "{type: environment, image: white.hdr}", material), 0, spp=2,
                           environment_samples=256)
    formula = render_reference(sphere_scene(tmp_path, "{type: ambient, color: [1, 1, 1]}", material), 0, spp=2)
    inner = (lit.object == 0) & ~lit.mixed & (sphere_radius_map() < 0.9)
    assert inner.sum() > 1000
    values, expected = lit.linear[inner], formula.linear[inner]
    assert abs(values.mean() / expected.mean() - 1.0) < 0.01
    assert np.abs(values / expected - 1.0).max() < 0.03
    if roughness == 1.0:
        assert np.abs(values / values.mean() - 1.0).max() < 0.03
        assert abs(values.mean() - 0.977) < 0.01
    again = render_reference(sphere_scene(tmp_path, "{type: environment, image: white.hdr}", material), 0, spp=2,
                             environment_samples=256)
    assert np.array_equal(again.linear, lit.linear)  # seeded per frame


PLANE = """
render: {{size: [32, 32], background: [0, 0, 0], shading: phong}}
camera: {{position: [0, 10, 0], target: [0, 0, 0], up: [0, 0, -1], projection: orthographic, height: 4}}
lights: [{{type: environment, image: sky.hdr, classic: {classic}}}]
objects:
  - mesh: {{primitive: plane, size: 8}}
    material: {{diffuse: [0.8, 0.6, 0.4], specular: [1, 1, 1], shininess: 10}}
"""


def upper_sky(height: int = 64) -> np.ndarray:
    """(H, 2H, 3) equirectangular radiance max(y, 0): brightest at the zenith, black below."""
    y = equirect_directions(height, 2 * height)[..., 1]
    return np.repeat(np.maximum(y, 0.0)[..., None], 3, axis=2)


@pytest.mark.parametrize("classic", [True, False])
def test_a_lambert_plane_under_a_sky_reflects_its_irradiance(tmp_path, classic):
    # radiance max(y, 0) gives an upward plane the irradiance 2 pi / 3, so a Lambert
    # surface reflects base * 2 / 3 (the specular colour does not count: the environment
    # lights classic materials' diffuse part only); 64 directions a sample, 2x2 samples a
    # pixel: the mean within 1 %, every pixel within 3 % (measured: mean -0.27 %, pixels
    # within 0.96 %). Without classic: true, Phong materials get nothing from it.
    write_hdr(tmp_path / "sky.hdr", upper_sky())
    scene = scenerender.Scene.from_yaml(PLANE.format(classic=str(classic).lower()), str(tmp_path))
    ref = render_reference(scene, 0, spp=2, environment_samples=64)
    if not classic:
        assert np.all(ref.linear == 0.0)
        return
    expected = np.array([0.8, 0.6, 0.4]) * 2.0 / 3.0
    ratio = ref.linear.reshape(-1, 3) / expected
    assert np.all(np.abs(ratio.mean(axis=0) - 1.0) < 0.01)
    assert np.abs(ratio - 1.0).max() < 0.03


def patch_image(centre_u: float, width: int = 64) -> np.ndarray:
    """(W / 2, W, 3) a dim grey environment with one bright square patch on the horizon at
    ``centre_u``, 4 texels wide and high."""
    image = np.full((width // 2, width, 3), 0.05)
    column = int(centre_u * width)
    image[width // 4 - 2:width // 4 + 2, column - 2:column + 2] = 20.0
    return image


def light_centre(frame: np.ndarray) -> np.ndarray:
    """(x, y) in pixels of the brightness-weighted centre of a frame (H, W, 3)."""
    brightness = frame.mean(axis=2)
    ys, xs = np.mgrid[0:brightness.shape[0], 0:brightness.shape[1]]
    return np.array([np.sum(brightness * xs), np.sum(brightness * ys)]) / brightness.sum() + 0.5


def test_rotating_the_environment_moves_a_metal_sphere_s_reflection(tmp_path):
    # the patch sits at the image's centre, straight down -Z. Turned 90 degrees about +Y
    # (counter-clockwise seen from above) it comes from -X: a mirror-like sphere seen from
    # +Z shows it where the normal halves -X and +Z, at x = -0.71 radii on the middle row
    # (pixel 9.9, 24: the brightest within 2 pixels). The image turned beforehand (its
    # columns moved a quarter) renders the same frame up to the noise of the image
    # sampler's picks (which texel a random number picks depends on the texels' order):
    # total light within 1 %, its centre within 0.3 pixels (measured: 0.38 % and 0.011
    # pixels, at 13.2, 24.0). Unturned, the patch is behind the sphere: its reflection
    # rings the rim, its centre within 1.5 pixels of the middle, dark where the turned
    # one is brightest
    write_hdr(tmp_path / "patch.hdr", patch_image(0.5))
    write_hdr(tmp_path / "turned.hdr", np.roll(patch_image(0.5), -16, axis=1))
    material = "{base_color: [1, 1, 1], metallic: 1, roughness: 0.2}"
    frames = {name: render_reference(sphere_scene(tmp_path, light, material, "[0, 0, 0]"), 0, spp=2,
                                     environment_samples=16).linear
              for name, light in (("still", "{type: environment, image: patch.hdr}"),
                                  ("rotated", "{type: environment, image: patch.hdr, rotation: 90}"),
                                  ("turned", "{type: environment, image: turned.hdr}"))}
    rotated, turned = frames["rotated"], frames["turned"]
    assert abs(rotated.sum() / turned.sum() - 1.0) < 0.01
    assert np.abs(light_centre(rotated) - light_centre(turned)).max() < 0.3
    assert light_centre(rotated)[0] < SIZE / 2 - 8
    brightness = rotated.mean(axis=2)
    y, x = np.unravel_index(np.argmax(brightness), brightness.shape)
    expected_x = SIZE / 2 - 0.71 * SIZE / 2.4
    assert abs(x + 0.5 - expected_x) < 2.0 and abs(y + 0.5 - SIZE / 2) < 2.0
    assert np.abs(light_centre(frames["still"]) - SIZE / 2).max() < 1.5
    assert frames["still"][y, x].mean() < 0.05 * brightness[y, x]


def sky_image(height: int = 64, sun: float = 200.0) -> np.ndarray:
    """(H, 2H, 3) a smooth sky with a bright lobe (radiance 20) 40 degrees from the zenith
    and a small sun (radiance ``sun`` at its centre, about 3 degrees across) 25 degrees up."""
    l = equirect_directions(height, 2 * height).reshape(-1, 3)
    lobe = 20.0 * np.exp(-np.sum((l - np.array([0.6, 0.64, 0.48])) ** 2, axis=1) / 0.02)
    sun = sun * np.exp(-np.sum((l - np.array([-0.82, 0.42, -0.38])) ** 2, axis=1) / 0.001)
    sky = np.stack([np.maximum(l[:, 1], 0.0) + lobe + sun, 0.5 + 0.5 * lobe + 0.8 * sun,
                    0.2 * np.abs(l[:, 0]) + 0.5 * sun], axis=1)
    return sky.reshape(height, 2 * height, 3)


def reflected_sky(image, state, normal, view, base, metallic: float, roughness: float):
    """reflected(rows, l) for environment.gather at points all alike (normal, view and
    base (3,)): f L (N.l) of the pbr model."""
    def reflected(rows, l):
        count = len(l)
        return shading.pbr_direct_term(np.tile(normal, (count, 1)), l, np.tile(view, (count, 1)),
                                       state.radiance(image, l), np.tile(base, (count, 1)),
                                       np.full(count, metallic), np.full(count, roughness)) / np.pi
    return reflected


def mean_and_error(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(3,) mean and (3,) standard error of (N, 3) independent estimates."""
    return values.mean(axis=0), values.std(axis=0) / np.sqrt(len(values))


@pytest.mark.parametrize("roughness,metallic,from_image,sun", [(0.3, 0.0, True, 200.0), (0.7, 0.0, True, 200.0),
                                                               (0.35, 1.0, True, 200.0), (0.3, 0.0, False, 0.0)])
def test_the_sampler_is_unbiased(roughness, metallic, from_image, sun):
    # the integral of f L (N.l) for one point, view 32 degrees off the normal, under
    # sky_image turned 30 degrees (with its sun where the image strategy is on, without
    # where it is off: the cosine and GGX alone rarely find a sun): 200,000 directions by
    # the MIS sampler against the integral over a 2048 x 512 grid of the upper hemisphere
    # (the same to 0.001 % on a grid twice as fine), 8 points of 4 directions a pixel, the
    # pixel's 32 picks stratified. They agree within 4 standard errors (of the pixels'
    # means) plus 0.2 %, a bound within 2.5 % per channel (measured: 0.07 to 2.3 standard
    # errors, 0.88 % at most, the last case's heavy tail; bounds 0.52 to 1.77 %; over ten
    # seeds, 2,000,000 directions, the first case within 0.04 %, the last over thirty
    # within 0.07 %). A GGX pdf without the reflection's Jacobian 1 / (4 v.h) is 5.7 to
    # 50 % out (46 to 1359 standard errors); an image pdf without the 1 / sin(theta) from
    # (u, v) to solid angle 2.2 to 14 %
    rng = np.random.default_rng(7)
    image = sky_image(sun=sun)
    state = EnvironmentState(np.ones(3), world_to_image(30.0))
    normal, view = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.53, 0.848])
    pixels, points, samples = 6250, 8, 4  # 200,000 directions, each pixel's 32 stratified
    count = pixels * points
    n, v = np.tile(normal, (count, 1)), np.tile(view, (count, 1))
    base, m, r = np.tile([0.8, 0.5, 0.3], (count, 1)), np.full(count, metallic), np.full(count, roughness)
    reflected = reflected_sky(image, state, normal, view, base[0], metallic, roughness)
    choice = environment.ggx_choice(np.sum(n * v, axis=1), base, m)
    sampler = environment.ImageSampler(image, state.scale, state.to_image) if from_image else None
    strata = environment.pixel_strata(rng, pixels, points, samples)
    estimates = environment.gather(n, v, shading.pbr_alpha(r), choice, samples, rng, reflected,
                                   lambda rows, l: np.ones(len(rows), bool), sampler, strata)
    mis, mis_error = mean_and_error(estimates.reshape(pixels, points, 3).mean(axis=1))
    directions = equirect_directions(1024, 2048)[:512].reshape(-1, 3)  # texel centres of the upper half
    solid_angles = np.repeat(texel_solid_angles(1024, 2048)[:512], 2048, axis=0)
    exact = np.zeros(3)
    for part in np.array_split(np.arange(len(directions)), 8):
        rows = np.arange(len(part))
        exact += np.sum(reflected(rows, directions[part]) * solid_angles[part], axis=0)
    bound = 4.0 * mis_error + 0.002 * exact
    assert np.all(bound < 0.025 * exact)
    assert np.all(np.abs(mis - exact) < bound), (mis, exact, bound)


def test_the_image_sampler_s_density_is_the_one_it_draws():
    # 1 / pdf averaged over its own draws is the sphere's 4 pi (a texel drawn more often
    # than its pdf says would pull it off), and pdf averaged over uniform directions times
    # 4 pi is 1 (measured: 0.12 % and 0.89 % off); its image share is high for this sky
    # (a sun: 0.47) and none for a uniform one
    rng = np.random.default_rng(11)
    image = sky_image() + 0.01
    sampler = environment.ImageSampler(image, np.array([1.0, 0.8, 0.6]), world_to_image(-70.0))
    drawn = sampler.draw(*rng.random((3, 400_000)))
    assert np.allclose(np.linalg.norm(drawn, axis=1), 1.0)
    assert abs(np.mean(1.0 / sampler.pdf(drawn)) / (4.0 * np.pi) - 1.0) < 0.01
    uniform = rng.normal(size=(400_000, 3))
    uniform /= np.linalg.norm(uniform, axis=1, keepdims=True)
    assert abs(np.mean(sampler.pdf(uniform)) * 4.0 * np.pi - 1.0) < 0.02
    assert sampler.choice > 0.4
    assert environment.ImageSampler(np.ones((8, 16, 3)), np.ones(3), np.eye(3)).choice == 0.0


def test_environment_samples_must_be_positive(tmp_path):
    write_hdr(tmp_path / "white.hdr", np.ones((8, 16, 3)))
    scene = sphere_scene(tmp_path, "{type: environment, image: white.hdr}", "{base_color: [1, 1, 1]}")
    with pytest.raises(UserError):
        render_reference(scene, 0, spp=1, environment_samples=0)


def test_the_reference_command_takes_environment_samples(tmp_path):
    write_hdr(tmp_path / "patch.hdr", patch_image(0.5))
    scene = tmp_path / "s.yaml"
    scene.write_text(SPHERE.format(size=24, background="[0, 0, 0]", light="{type: environment, image: patch.hdr}",
                                   material="{base_color: [1, 1, 1], metallic: 0, roughness: 0.6}"))
    written = {}
    for samples in ("1", "16"):
        folder = tmp_path / samples
        result = CliRunner().invoke(cli.main, ["reference", str(scene), "-o", str(folder), "--spp", "1",
                                               "--environment-samples", samples])
        assert result.exit_code == 0, result.output
        written[samples] = (folder / "frame_0000.png").read_bytes()
    assert written["1"] != written["16"]
    refused = CliRunner().invoke(cli.main, ["reference", str(scene), "--environment-samples", "0"])
    assert refused.exit_code == 2
