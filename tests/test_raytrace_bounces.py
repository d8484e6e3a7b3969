"""The reference's path tracing (``bounces``) against analytic answers.

- A white furnace: a closed box of albedo a whose walls all emit Le sees Le / (1 - a)
  everywhere (Le (1 + a + ... + a^B) after B bounces: exact for one and two bounces,
  where no path ends at random).
- Inside a closed sphere of radius R and albedo a every point sees every area element
  of the wall at the same form factor dA / (4 pi R^2), so from the first bounce on the
  light is uniform: L(x) = L_direct(x) + a / (1 - a) mean(L_direct). For a point light
  (attenuation 1 / d^2) of intensity I anywhere inside, mean(L_direct) = a I / R^2; for a
  rect light of area A, a I A / (4 pi R^2) (its radiance is I / pi, and each of its
  points sends pi into the sphere).
- A sun straight down on a wide floor of albedo a_f: a vertical wall of albedo a_w, which
  the sun grazes, sees the floor lit to a_f I over half its hemisphere: a_w a_f I / 2
  after one bounce. The same with a uniform environment of radiance E in place of the sun
  (the floor then a_f E): the environment's light at the bounce.
- A pbr surface inside an enclosure that only emits Le (unlit walls end a path): one
  bounce gives Le times the BRDF's directional albedo, integrated here on a fine grid.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import scenerender
from scenerender.cli import main
from scenerender.raytrace import render_reference, shading
from scenerender.world.environment_files import write_hdr

ROOT = Path(__file__).resolve().parent.parent
CORNELL = ROOT / "benchmarks" / "quality" / "scenes" / "cornell_box.yaml"
REFERENCES = ROOT / "benchmarks" / "quality" / "references"


def load(text: str) -> scenerender.Scene:
    return scenerender.Scene.from_yaml(text, ".")


def furnace(albedo, emission) -> scenerender.Scene:
    return load(f"""
render: {{size: [32, 32], background: [0, 0, 0], shading: blinn_phong}}
camera: {{position: [0.1, 0.2, 0.3], target: [0.4, 0, -1], fov: 100}}
lights: []
objects:
  - mesh: {{primitive: box, size: 2}}
    material: {{diffuse: {list(albedo)}, specular: [0, 0, 0], emissive: {list(emission)}}}
""")


def test_one_and_two_bounces_in_a_furnace_are_exact():
    a, le = 0.6, 0.25
    scene = furnace([a] * 3, [le] * 3)
    for bounces, expected in ((0, le), (1, le * (1 + a)), (2, le * (1 + a + a * a))):
        linear = render_reference(scene, 0, spp=1, bounces=bounces).linear
        np.testing.assert_allclose(linear, expected, rtol=1e-5)


def test_a_white_furnace_converges_to_le_over_one_minus_albedo():
    # per channel: each albedo's own geometric series, whatever the roulette (which follows
    # the largest channel) does; 32 x 32 pixels x 16 paths, 64 bounces (a^65 < 1e-9)
    albedo, le = np.array([0.3, 0.6, 0.85]), 0.1
    scene = furnace(albedo.tolist(), [le] * 3)
    linear = render_reference(scene, 0, spp=4, bounces=64).linear
    expected = le / (1.0 - albedo)
    # 16384 paths: the mean's standard error is under 0.3 % (measured 0.1-0.3 %)
    np.testing.assert_allclose(linear.mean(axis=(0, 1)), expected, rtol=0.01)
    # and no pixel is far off: 16 paths a pixel
    assert np.abs(linear / expected - 1.0).mean() < 0.15


def sphere_room(light: str, albedo: float) -> scenerender.Scene:
    return load(f"""
render: {{size: [48, 48], background: [0, 0, 0], shading: blinn_phong}}
camera: {{position: [0, 0, 0.5], target: [0, -0.5, -2], fov: 90}}
lights:
  - {light}
objects:
  - mesh: {{primitive: sphere, radius: 2, segments: 96}}
    material: {{diffuse: [{albedo}, {albedo}, {albedo}], specular: [0, 0, 0]}}
""")


@pytest.mark.parametrize("light, mean_direct", [
    ("{type: point, position: [0.3, 0.5, -0.4], attenuation: [0, 0, 1], intensity: 2, shadows: true}",
     lambda a: a * 2 / 4.0),
    ("{type: rect, position: [0.2, 1.0, 0], direction: [0.3, -1, 0.2], width: 0.6, height: 0.4, intensity: 5,"
     " shadows: true}",
     lambda a: a * 5 * 0.24 / (4 * np.pi * 4.0)),
])
def test_inside_a_sphere_the_bounced_light_is_uniform_and_analytic(light, mean_direct):
    a = 0.5
    scene = sphere_room(light, a)
    direct = render_reference(scene, 0, spp=4).linear
    full = render_reference(scene, 0, spp=4, bounces=32).linear
    expected = a / (1.0 - a) * mean_direct(a)
    bounced = (full - direct).mean(axis=2)
    # the tessellated sphere is within 0.1 % of the analytic one; 36864 paths
    assert bounced.mean() == pytest.approx(expected, rel=0.02)
    # uniform: the image's quarters agree (each 9216 paths)
    quarters = [bounced[:24, :24], bounced[:24, 24:], bounced[24:, :24], bounced[24:, 24:]]
    for quarter in quarters:
        assert quarter.mean() == pytest.approx(expected, rel=0.04)


def test_sunlight_bounced_off_the_floor_lights_a_wall():
    a_floor, a_wall, intensity = 0.8, 0.5, 2.0
    scene = load(f"""
render: {{size: [32, 32], background: [0, 0, 0], shading: blinn_phong}}
camera: {{position: [0, 1, 3], target: [0, 1, 0], projection: orthographic, height: 0.4}}
lights:
  - {{type: directional, direction: [0, -1, 0], intensity: {intensity}, shadows: true}}
objects:
  - mesh: {{primitive: plane, size: 400}}
    material: {{diffuse: [{a_floor}, {a_floor}, {a_floor}], specular: [0, 0, 0]}}
  - mesh: {{primitive: plane, size: [40, 2]}}
    position: [0, 1, 0]
    rotation: [90, 0, 0]
    material: {{diffuse: [{a_wall}, {a_wall}, {a_wall}], specular: [0, 0, 0]}}
""")
    direct = render_reference(scene, 0, spp=4).linear
    assert np.abs(direct).max() < 1e-9  # the sun grazes the wall
    wall = render_reference(scene, 0, spp=4, bounces=1).linear
    # the floor out to 200 m leaves out 0.25 % of the half hemisphere at 1 m up
    np.testing.assert_allclose(wall.mean(axis=(0, 1)), a_wall * a_floor * intensity / 2, rtol=0.02)


def test_sky_light_bounced_off_the_floor_lights_a_panel(tmp_path):
    # a small panel (0.4 m) 1 m over a wide Lambert floor under a uniform environment of
    # radiance 1 (classic: lights Blinn-Phong): the floor shines a_f (less the panel's
    # own shadow of the sky, under 1 %), which one bounce brings to the panel as a_w a_f / 2
    a_floor, a_wall = 0.8, 0.5
    write_hdr(tmp_path / "white.hdr", np.ones((8, 16, 3)))
    scene = scenerender.Scene.from_yaml(f"""
render: {{size: [16, 16], background: [0, 0, 0], shading: blinn_phong}}
camera: {{position: [0, 1, 3], target: [0, 1, 0], projection: orthographic, height: 0.3}}
lights:
  - {{type: environment, image: white.hdr, classic: true}}
objects:
  - mesh: {{primitive: plane, size: 400}}
    material: {{diffuse: [{a_floor}, {a_floor}, {a_floor}], specular: [0, 0, 0]}}
  - mesh: {{primitive: plane, size: 0.4}}
    position: [0, 1, 0]
    rotation: [90, 0, 0]
    material: {{diffuse: [{a_wall}, {a_wall}, {a_wall}], specular: [0, 0, 0]}}
""", str(tmp_path))
    direct = render_reference(scene, 0, spp=4, environment_samples=16).linear
    full = render_reference(scene, 0, spp=4, environment_samples=16, bounces=1).linear
    assert direct.mean() == pytest.approx(a_wall / 2, rel=0.02)  # the sky's upper half
    assert (full - direct).mean() == pytest.approx(a_wall * a_floor / 2, rel=0.03)


def directional_albedo(view_angle: float, base, metallic: float, roughness: float) -> np.ndarray:
    """(3,) the integral over the hemisphere of f(l, v) (N.l) for a view ``view_angle``
    degrees from the normal (+Y): midpoints of 1600 x 1600 cells even in N.l and azimuth."""
    count = 1600
    cos = (np.arange(count) + 0.5) / count
    azimuth = (np.arange(count) + 0.5) / count * 2 * np.pi
    c, a = (grid.ravel() for grid in np.meshgrid(cos, azimuth))
    sin = np.sqrt(1 - c * c)
    l = np.stack([sin * np.cos(a), c, sin * np.sin(a)], axis=1)
    v = np.broadcast_to([np.sin(np.radians(view_angle)), np.cos(np.radians(view_angle)), 0.0], l.shape)
    n = np.broadcast_to([0.0, 1.0, 0.0], l.shape)
    ones = np.ones((len(l), 1))
    term = shading.pbr_direct_term(n, l, v, np.ones_like(l), ones * base, ones[:, 0] * metallic,
                                   ones[:, 0] * roughness) / np.pi
    return term.sum(axis=0) * (1.0 / count) * (2 * np.pi / count)


@pytest.mark.parametrize("base, metallic, roughness, view_angle", [
    ([0.8, 0.8, 0.8], 0.0, 0.3, 60.0),
    ([0.9, 0.6, 0.3], 1.0, 0.5, 30.0),
    ([0.5, 0.5, 0.5], 0.0, 1.0, 75.0),
])
def test_a_pbr_surface_reflects_its_directional_albedo(base, metallic, roughness, view_angle):
    emission = 0.5
    angle = np.radians(view_angle)
    eye = [round(float(5 * np.sin(angle)), 6), round(float(5 * np.cos(angle)), 6), 0]
    scene = load(f"""
render: {{size: [24, 24], background: [0, 0, 0], shading: pbr}}
camera: {{position: {eye}, target: [0, 0, 0], fov: 2}}
lights: []
objects:
  - mesh: {{primitive: box, size: 30}}
    material: {{base_color: [0, 0, 0], emissive: [{emission}, {emission}, {emission}], unlit: true}}
  - mesh: {{primitive: plane, size: 2}}
    material: {{base_color: {base}, metallic: {metallic}, roughness: {roughness}}}
""")
    linear = render_reference(scene, 0, spp=4, bounces=1).linear
    expected = emission * directional_albedo(view_angle, np.array(base), metallic, roughness)
    # 2304 paths drawn from the BRDF (cosine and GGX mixed): the mean within 2 %
    np.testing.assert_allclose(linear.mean(axis=(0, 1)), expected, rtol=0.02)


def test_bounces_keep_the_direct_light_and_its_records():
    scene = scenerender.load(CORNELL)
    direct = render_reference(scene, 0, spp=1, size=(32, 32))
    full = render_reference(scene, 0, spp=1, size=(32, 32), bounces=4)
    # the paths draw their own random numbers: the direct part draws what it drew
    for key in ("shadow", "blocked", "object", "mixed"):
        np.testing.assert_array_equal(getattr(full, key), getattr(direct, key))
    assert np.all(full.linear >= direct.linear)
    assert (full.linear > direct.linear).mean() > 0.9  # one path a pixel: a few meet only shadow
    again = render_reference(scene, 0, spp=1, size=(32, 32), bounces=4)
    np.testing.assert_array_equal(again.linear, full.linear)  # seeded


def test_unlit_surfaces_reflect_nothing_and_give_their_emission():
    # an unlit floor under a lit white ceiling: the ceiling's bounce light is the floor's
    # emission only (its unlit colour is not light)
    text = """
render: {size: [16, 16], background: [0, 0, 0], shading: blinn_phong}
camera: {position: [0, 1, 0], target: [0, 2, 0], up: [0, 0, -1], fov: 10}
lights: []
objects:
  - mesh: {primitive: plane, size: 400}
    material: {diffuse: [0.9, 0.9, 0.9], emissive: [EMISSION, EMISSION, EMISSION], unlit: true}
  - mesh: {primitive: plane, size: 400}
    position: [0, 2, 0]
    material: {diffuse: [0.5, 0.5, 0.5], specular: [0, 0, 0]}
"""
    dark = render_reference(load(text.replace("EMISSION", "0")), 0, spp=2, bounces=8).linear
    assert np.abs(dark).max() == 0.0
    lit = render_reference(load(text.replace("EMISSION", "0.4")), 0, spp=2, bounces=8).linear
    # 0.5 x 0.4: the floor, 2 m below and 200 m wide, fills the ceiling's hemisphere (to 0.01 %)
    assert lit.mean() == pytest.approx(0.5 * 0.4, rel=0.01)


def test_the_cornell_box_reference_is_kept_and_current():
    """The kept reference (benchmarks/quality/cornell_reference.py) against a fresh one of
    16 paths a pixel, object by object; and what bounced light does there."""
    kept = np.load(REFERENCES / "cornell_box_bounces16.npy")
    kept_direct = np.load(REFERENCES / "cornell_box_direct.npy")
    objects = np.load(REFERENCES / "cornell_box_objects.npy")
    scene = scenerender.load(CORNELL)
    fresh = render_reference(scene, 0, spp=4, bounces=16)
    assert (fresh.object == objects).mean() > 0.99  # the middle sample's object: edges differ
    names = [obj.name for obj in scene.world.spec.objects]
    for index, name in enumerate(names):
        mask = (objects == index) & (fresh.object == index) & ~fresh.mixed
        if name == "front_wall":  # behind the camera
            assert not mask.any()
            continue
        # 16 paths a pixel over 1400-3000 pixels: each object's mean within 3 % (its noise: under 0.5 %)
        np.testing.assert_allclose(fresh.linear[mask].mean(axis=0), kept[mask].mean(axis=0), rtol=0.03,
                                   err_msg=name)
    luminance = kept.mean(axis=2)
    ceiling = (objects == names.index("ceiling")) & ~fresh.mixed
    assert kept_direct[ceiling].max() == 0.0  # no direct light reaches it
    assert luminance[ceiling].mean() > 0.25 * luminance[objects == names.index("floor")].mean()
    assert np.all(kept >= kept_direct)  # the same direct light, plus what bounced


def test_the_reference_command_takes_bounces(tmp_path):
    runner = CliRunner()
    result = runner.invoke(main, ["reference", str(CORNELL), "-o", str(tmp_path / "ref"), "--spp", "1",
                                  "--bounces", "-1"])
    assert result.exit_code == 2
    assert "bounces must be 0..1024, got -1" in result.output
    assert not (tmp_path / "ref").exists()
    assert "--bounces" in runner.invoke(main, ["reference", "--help"]).output
