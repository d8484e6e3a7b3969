"""Depth of field (camera.aperture, focus_distance, sensor_width): a thin lens sampled
over its disc. A bright point out of focus renders a disc the thin lens's circle of
confusion wide; the focus plane stays as sharp as the pinhole's; the lens's maths; an
unset aperture renders the bytes of a scene without the keys."""
from __future__ import annotations

import math

import numpy as np
import pytest

import scenerender
from scenerender.colorspace import srgb_decode
from scenerender.errors import SceneErrors, UserError
from scenerender.raytrace import render_reference
from scenerender.world.camera import CameraState, perspective
from scenerender.rendering.renderer import plan
from scenerender.world.lens import Film, lens_radius, through_lens
from lens_points import COLUMNS, FOV, HEIGHT, WIDTH, disc, points_scene, thin_lens_coc_px

def _points_scene(depths, aperture, focus, samples=256, radius_px=0.5) -> str:
    return points_scene(depths, aperture, focus, f", film_samples: {samples}", radius_px)


def _render(gl, text: str) -> np.ndarray:
    with scenerender.Renderer(scenerender.Scene.from_yaml(text, "."), gl=gl) as renderer:
        return srgb_decode(renderer.render(0).pixels[..., 0] / 255.0)


def _spread(light: np.ndarray, column: int) -> float:
    """The variance (px^2) of where the light falls, horizontally, in the 40 px band
    around ``column``."""
    band = light[:, column - 20:column + 20]
    x = np.arange(band.shape[1])[None, :]
    mean = (band * x).sum() / band.sum()
    return float((band * (x - mean) ** 2).sum() / band.sum())


def test_a_point_out_of_focus_is_a_disc_the_circle_of_confusion_wide(gl):
    """Three points at 0.25, 0.35 and 1.5 (focus 0.5, f/1): each disc's diameter, from its
    horizontal spread (a uniform disc of diameter D has variance D^2 / 16), less the
    point's own pinhole image, within 10 % of the thin-lens circle of confusion."""
    depths, focus, aperture = (0.25, 0.35, 1.5), 0.5, 1.0
    sharp = _render(gl, _points_scene(depths, None, None))
    blurred = _render(gl, _points_scene(depths, aperture, focus))
    for column, depth in zip(COLUMNS, depths):
        expected = thin_lens_coc_px(depth, focus, aperture)
        diameter = 4.0 * math.sqrt(_spread(blurred, column) - _spread(sharp, column))
        assert expected > 4.0
        assert diameter == pytest.approx(expected, rel=0.10), (depth, diameter, expected)


@pytest.mark.parametrize("samples", [8, 16])
def test_few_lens_samples_give_the_thin_lens_disc_centred(gl, samples):
    """Points at 0.3 and 1.5 (focus 0.5) at f/0.5 and f/1 (discs of 15.2 and 7.6 px): with
    8 and 16 sub-frames each disc's diameter, from its second moment about its centroid
    (a uniform disc of diameter D has D^2 / 8) less the pinhole image's, within 3 % of the
    thin lens's, and its centroid within 0.25 px of the pinhole image's. Measured: 0.990 to
    1.009 of it, 0.15 px off at most; the Halton points these replaced gave 0.87 to 0.92,
    up to 1.0 px off."""
    depths, focus = (0.3, 1.5, 0.3), 0.5
    sharp = _render(gl, _points_scene(depths, None, None, radius_px=1.5))
    for aperture in (0.5, 1.0):
        blurred = _render(gl, _points_scene(depths, aperture, focus, samples=samples, radius_px=1.5))
        for column, depth in zip(COLUMNS[:2], depths):
            sx, sy, sharp_moment = disc(sharp, column)
            bx, by, moment = disc(blurred, column)
            diameter = math.sqrt(8.0 * (moment - sharp_moment))
            expected = thin_lens_coc_px(depth, focus, aperture)
            assert diameter == pytest.approx(expected, rel=0.03), (aperture, depth, diameter, expected)
            assert math.hypot(bx - sx, by - sy) < 0.25, (aperture, depth, bx - sx, by - sy)


def test_the_focus_plane_is_as_sharp_as_the_pinhole(gl):
    depths = (0.5, 0.5, 0.5)
    sharp = _render(gl, _points_scene(depths, None, None))
    focused = _render(gl, _points_scene(depths, 1.0, 0.5, samples=16))
    for column in COLUMNS:
        assert _spread(focused, column) == pytest.approx(_spread(sharp, column), abs=0.05)
    assert np.abs(focused - sharp).max() < 0.02


def test_unset_aperture_renders_the_bytes_of_a_scene_without_the_keys(gl):
    depths = (0.25, 0.5, 1.5)
    plain = _render(gl, _points_scene(depths, None, None))
    text = _points_scene(depths, None, None).replace("far: 10}", "far: 10, focus_distance: 0.3, sensor_width: 24}")
    assert "focus_distance" in text
    assert np.array_equal(_render(gl, text), plain)
    gather = text.replace("film_samples: 256}", "film_samples: 256, depth_of_field: gather}")
    assert "gather" in gather and np.array_equal(_render(gl, gather), plain)  # no aperture: no lens pass


def test_the_lens_keeps_the_focus_plane_and_moves_the_eye_in_the_view_plane():
    camera = CameraState(np.array([1.0, 2.0, 3.0]), np.eye(3), perspective(40.0, 4 / 3, 0.1, 100.0), 0.1, 100.0,
                         40.0, 4 / 3, False)
    moved = through_lens(camera, (0.6, -0.8), 0.05, 4.0)
    np.testing.assert_allclose(moved.position, [1.03, 1.96, 3.0])
    for point in ([0.3, -0.2, -1.0], [-1.5, 0.7, -1.0]):  # on the focus plane, 4 in front
        world = camera.position + np.array(point) * 4.0
        before = camera.projection @ np.append(world - camera.position, 1.0)
        after = moved.projection @ np.append(world - moved.position, 1.0)
        np.testing.assert_allclose(after[:2] / after[3], before[:2] / before[3], atol=1e-12)
    # 36 mm film, 40 degrees vertical at 4:3; focused at 4: f = v S / (v + S), radius f / 2N
    v = 0.036 / (2 * math.tan(math.radians(20)) * 4 / 3)
    assert lens_radius(camera, 2.0, 4.0, 36.0) == pytest.approx(v * 4 / (v + 4) / 4.0)


def test_an_aperture_with_yaw_and_pitch_needs_a_focus_distance():
    with pytest.raises(SceneErrors, match=r"camera\.aperture: an aperture with yaw/pitch needs a focus_distance"):
        scenerender.Scene.from_yaml("camera: {position: [0, 0, 5], yaw: -90, aperture: 2}\nobjects: []\n", ".")
    with pytest.raises(SceneErrors, match="depth of field"):
        scenerender.Scene.from_yaml("camera: {projection: orthographic, aperture: 2}\nobjects: []\n", ".")


def test_the_reference_draws_the_same_circles_of_confusion():
    """The CPU reference (each ray from its own random point of the lens, through the
    focus plane) against the same thin-lens diameters, within 10 %."""
    depths, focus, aperture = (0.25, 0.35, 1.5), 0.5, 1.0
    # larger points (3 px across) than on the GPU, so that enough random rays find them
    sharp = reference_light(_points_scene(depths, None, None, radius_px=1.5))
    blurred = reference_light(_points_scene(depths, aperture, focus, radius_px=1.5))
    for column, depth in zip(COLUMNS, depths):
        diameter = 4.0 * math.sqrt(_spread(blurred, column) - _spread(sharp, column))
        assert diameter == pytest.approx(thin_lens_coc_px(depth, focus, aperture), rel=0.10), depth


def reference_light(text: str) -> np.ndarray:
    return render_reference(scenerender.Scene.from_yaml(text, "."), 0, spp=6).linear[..., 0].astype(np.float64)


def test_focus_on_an_object_is_focus_at_its_distance(gl):
    """`focus: <object>` renders the bytes of `focus_distance` set to the distance of the
    object's centre along the view axis (here 0.35, the middle point)."""
    depths = (0.25, 0.35, 1.5)
    named = _points_scene(depths, 1.0, 0.5, samples=8).replace("focus_distance: 0.5", "focus: middle")
    named = named.replace("  - {mesh: {primitive: sphere", "  - {name: middle, mesh: {primitive: sphere", 2)
    named = named.replace("  - {name: middle, mesh", "  - {name: first, mesh", 1)
    by_distance = _points_scene(depths, 1.0, 0.35, samples=8)
    assert np.array_equal(_render(gl, named), _render(gl, by_distance))


def test_focus_on_a_missing_object_names_the_key(tmp_path):
    path = tmp_path / "scene.yaml"
    path.write_text("camera: {aperture: 2, focus: crate}\nobjects:\n  - {name: ball, mesh: {primitive: sphere}}\n")
    with pytest.raises(UserError, match="no object is named 'crate'") as error:
        scenerender.load(path)
    assert "scene.yaml:1" in str(error.value) and "camera.focus" in str(error.value)


# -- the gather blur (render.depth_of_field: gather) ----------------------------------------

def _edge_scene(method: str, aperture=1.0) -> str:
    """An unlit white square 1.5 in front of the camera (focus 0.5), its left edge on the
    middle column, against black at infinity."""
    half = 0.6
    lens = f", aperture: {aperture}, focus_distance: 0.5" if aperture is not None else ""
    return (f"render: {{size: [{WIDTH}, {HEIGHT}], samples: 4, background: [0, 0, 0], depth_of_field: {method}, "
            "film_samples: 64}\n"
            f"camera: {{position: [0, 0, 0], target: [0, 0, -1], fov: {FOV}{lens}}}\n"
            "lights: []\nobjects:\n"
            f"  - {{mesh: {{primitive: box, size: [{2 * half}, {2 * half}, 0.01]}}, position: [{half}, 0, -1.5], "
            "material: {diffuse: [1, 1, 1], unlit: true}}\n")


def _edge_diameter(light: np.ndarray) -> float:
    """The width of the blur across the square's left edge, as the diameter of the disc
    that blurs a straight edge so (its rise has standard deviation diameter / 4)."""
    rise = np.clip(np.diff(light[HEIGHT // 2, 50:110]), 0.0, None)
    x = np.arange(len(rise))
    mean = (x * rise).sum() / rise.sum()
    return 4.0 * math.sqrt(((x - mean) ** 2 * rise).sum() / rise.sum())


def test_the_gather_blurs_an_edge_by_about_the_circle_of_confusion(gl):
    """The square's edge at 1.5 (focus 0.5, f/1): blurred across about the thin-lens
    circle of confusion, within 15 % (the gather is approximate at edges between near and
    far), as the sub-frames blur it within 10 %."""
    expected = thin_lens_coc_px(1.5, 0.5, 1.0)
    sharp = _edge_diameter(_render(gl, _edge_scene("gather", None)))
    for method, tolerance in (("gather", 0.15), ("sub_frames", 0.10)):
        diameter = math.sqrt(_edge_diameter(_render(gl, _edge_scene(method))) ** 2 - sharp ** 2)
        print(f"{method}: edge blurred over {diameter:.2f} px, thin lens {expected:.2f} px")
        assert diameter == pytest.approx(expected, rel=tolerance), (method, diameter, expected)


@pytest.mark.parametrize("depths", [(0.3, 1.5, 0.5), (0.35, 1.0, 0.5)])
def test_the_gather_spreads_each_point_by_its_own_circle(gl, depths):
    """Points 3 px across in front of black at infinity, focus 0.5, f/0.5 and f/1: the near
    and the far one blur into discs within 10 % of the thin lens's diameter (from the
    second moment, as above), the one at the focus stays sharp (its spread grows by a disc
    of at most 2 px). The points' edge pixels hold their light but the background's depth;
    taken for the background, they spread it over the background's circle: measured
    before, the far discs 1.10 to 1.25 of the thin lens's, the sharp point's halo 5 to 10 px."""
    sharp = _render(gl, _points_scene(depths, None, None, radius_px=1.5))
    for aperture in (0.5, 1.0):
        text = _points_scene(depths, aperture, 0.5, samples=64, radius_px=1.5)
        blurred = _render(gl, text.replace("film_samples: 64}", "film_samples: 64, depth_of_field: gather}"))
        for column, depth in zip(COLUMNS, depths):
            growth = math.sqrt(max(8.0 * (disc(blurred, column)[2] - disc(sharp, column)[2]), 0.0))
            if depth == 0.5:
                assert growth <= 2.0, (aperture, growth)
            else:
                expected = thin_lens_coc_px(depth, 0.5, aperture)
                assert growth == pytest.approx(expected, rel=0.10), (aperture, depth, growth, expected)


def test_the_gather_is_two_passes_on_the_depth_prepass_and_no_sub_frames(gl):
    world = scenerender.Scene.from_yaml(_edge_scene("gather"), ".").world
    compiled = plan(world, world.settings.size, 4).compiled
    assert {"gbuffer", "lens_depth", "depth_of_field"} <= set(compiled.pass_names)
    assert "lens" in [name for _, name, _ in compiled.inputs()]
    assert Film.of_world(world) is None
    exact = scenerender.Scene.from_yaml(_edge_scene("sub_frames"), ".").world
    assert not {"lens_depth", "depth_of_field"} & set(plan(exact, exact.settings.size, 4).compiled.pass_names)
    assert Film.of_world(exact) is not None
