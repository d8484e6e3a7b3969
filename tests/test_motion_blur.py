"""Motion blur (camera.shutter): sub-frames spread over the open shutter, averaged in
linear light. A box moving 40 px a frame smears over 20 px at shutter 0.5; the default
sub-frame count matches 64 instants of the same interval; shutter 0 is the image of a
scene without the key; the sub-frame times and the graph's caching."""
from __future__ import annotations

import numpy as np
import pytest

import scenerender
from scenerender.colorspace import srgb_decode, srgb_encode
from scenerender.raytrace import render_reference
from scenerender.world.lens import film_samples, lens_points, shutter_times

# 10 px a unit (orthographic, 12 units tall in 120 px); the unlit box is 20 px wide and
# moves 8 units (80 px) in 0.2 s: 40 px a frame at 10 frames a second.
MOVING_BOX = """
render: {{size: [160, 120], samples: 4, background: [0, 0, 0], shading: unlit}}
output: {{fps: {fps}, duration: 0.2}}
camera: {{position: [0, 0, 10], target: [0, 0, 0], projection: orthographic, height: 12, shutter: {shutter}}}
lights: []
objects:
  - mesh: {{primitive: box, size: [2, 2, 2]}}
    position: {{keys: [[0, [-4, 0, 0]], [{end}, [4, 0, 0]]]}}
    material: {{diffuse: [1, 1, 1]}}
"""


def _render(gl, frame: int, shutter=0.5, fps=10, overrides=(), slower=1) -> np.ndarray:
    """``slower``: the box's keys stretched in time that many times (a frame then shows
    the instant index / (fps * slower) of the box's own motion)."""
    text = MOVING_BOX.format(shutter=shutter, fps=fps, end=0.2 * slower)
    scene = scenerender.Scene.from_yaml(text, ".", list(overrides))
    with scenerender.Renderer(scene, gl=gl) as renderer:
        return renderer.render(frame).pixels


def _edge_width(pixels: np.ndarray) -> float:
    """How wide the box's left edge is spread, in pixels: sqrt(12) times the standard
    deviation of where the coverage rises along the middle row (a ramp of width L has a
    uniform rise, standard deviation L / sqrt(12))."""
    coverage = srgb_decode(pixels[60, :, 0] / 255.0)
    rise = np.clip(np.diff(coverage[:80]), 0.0, None)
    x = np.arange(len(rise)) + 0.5
    mean = (x * rise).sum() / rise.sum()
    return float(np.sqrt(12.0 * ((x - mean) ** 2 * rise).sum() / rise.sum()))


def test_a_box_moving_40_px_a_frame_smears_over_20_px_at_shutter_half(gl):
    sharp = _edge_width(_render(gl, 1, shutter=0.0))
    blurred = _edge_width(_render(gl, 1))
    smear = np.sqrt(blurred ** 2 - sharp ** 2)  # less the pixel's own edge (antialiasing)
    assert sharp < 2.0
    assert smear == pytest.approx(20.0, abs=1.0), (sharp, blurred)
    quarter = np.sqrt(_edge_width(_render(gl, 1, shutter=0.25)) ** 2 - sharp ** 2)
    assert quarter == pytest.approx(10.0, abs=1.0)


def test_the_default_sub_frames_match_64_instants_of_the_interval_within_1_percent(gl):
    """The frame at 10 fps with the default sub-frames against the mean of 64 instants
    rendered as frames of the box moving 128 times slower over the same half-frame
    interval (each frame is then an instant, shutter 0): the time integral by another road. RMSE under 1 % of white."""
    blurred = _render(gl, 1).astype(np.float64)
    instants = [srgb_decode(_render(gl, 128 - 32 + k, shutter=0.0, slower=128) / 255.0) for k in range(64)]
    # the instants open each of 64 slices of the interval, half a slice (0.16 px) early
    reference = np.rint(srgb_encode(np.clip(np.mean(instants, axis=0), 0.0, 1.0)) * 255.0)
    rmse = np.sqrt(np.mean((blurred - reference) ** 2)) / 255.0
    assert rmse < 0.01, rmse


def test_shutter_0_renders_the_bytes_of_a_scene_without_the_key(gl):
    plain = _render(gl, 1, overrides=["camera.shutter=0"])
    text = MOVING_BOX.format(shutter=0, fps=10, end=0.2).replace(", shutter: 0}", "}")
    assert "shutter" not in text
    with scenerender.Renderer(scenerender.Scene.from_yaml(text, "."), gl=gl, profile=True) as renderer:
        assert np.array_equal(renderer.render(1).pixels, plain)
        assert len(renderer.timings["opaque"]) == 1  # one instant, no sub-frames
    assert not np.array_equal(_render(gl, 1), plain)


def test_sub_frame_times_are_stratified_over_the_shutter_centred_on_the_frame():
    """One time in each of 16 equal slices of the open interval, centred on the frame's
    time, spread by 16 / sqrt(16^2 - 1) about it (shutter_times: the interval's variance)."""
    samples = film_samples(16, 0.05, lens=False)
    offsets = sorted(s.time_offset for s in samples)
    middles = (np.arange(16) + 0.5) / 16 * 0.05 - 0.025
    np.testing.assert_allclose(offsets, middles * 16 / np.sqrt(255), rtol=1e-12)
    assert all(k / 16 * 0.05 - 0.025 < t < (k + 1) / 16 * 0.05 - 0.025 for k, t in enumerate(offsets))
    assert all(s.lens is None for s in samples)
    assert [s.time_offset for s in samples] != offsets  # not in time order: decoupled from the lens points


@pytest.mark.parametrize("count", range(1, 65))
def test_the_shutter_times_have_the_open_interval_s_mean_and_variance(count):
    """Mean 0 (the frame's time) and variance 1/12 (a uniform interval's) of the open
    interval, exactly; inside it. One time cannot have the variance: it is the centre."""
    times = shutter_times(count)
    assert times.shape == (count,) and np.all(np.abs(times) < 0.5)
    assert abs(times.mean()) < 1e-15
    assert np.mean(times ** 2) == (0.0 if count == 1 else pytest.approx(1.0 / 12.0, rel=1e-12))


@pytest.mark.parametrize("count", range(1, 65))
def test_the_lens_points_have_the_disc_s_centroid_and_second_moment(count):
    """Centroid (0, 0), E[x^2] = E[y^2] = 1/4 and E[xy] = 0 (a uniform unit disc's), exactly,
    every point inside the disc. One point is the centre; two cannot be isotropic, so they
    keep only the mean squared radius (1/2)."""
    points = lens_points(count)
    assert points.shape == (count, 2) and np.all(np.hypot(points[:, 0], points[:, 1]) < 1.0)
    np.testing.assert_allclose(points.mean(axis=0), 0.0, atol=1e-15)
    moments = points.T @ points / count
    if count == 1:
        np.testing.assert_array_equal(points, 0.0)
    elif count == 2:
        assert np.trace(moments) == pytest.approx(0.5, rel=1e-12)
    else:
        np.testing.assert_allclose(moments, np.eye(2) / 4.0, atol=1e-14)
    filmed = np.array([s.lens for s in film_samples(count, 0.0, lens=True)])
    np.testing.assert_array_equal(filmed, points)


def test_the_lens_points_stay_inside_the_disc_at_every_allowed_count():
    """render.film_samples allows up to 1024: the stretch that makes the points isotropic
    never carries one out of the lens (largest radius 0.9993)."""
    largest = max(float(np.hypot(*lens_points(count).T).max()) for count in range(1, 1025))
    assert largest < 1.0, largest


def test_static_passes_run_once_across_sub_frames(gl):
    """A still box and light filmed by a panning camera: the light's shadow map is drawn on
    the first sub-frame only, the shading on all 16."""
    text = MOVING_BOX.format(shutter=0.5, fps=10, end=0.2)
    text = text.replace("lights: []", "lights: [{type: point, position: [0, 5, 5], shadows: true}]")
    text = text.replace("shading: unlit", "shading: phong").replace(
        "{keys: [[0, [-4, 0, 0]], [0.2, [4, 0, 0]]]}", "[0, 0, 0]").replace(
        "position: [0, 0, 10]", "position: {keys: [[0, [-1, 0, 10]], [0.2, [1, 0, 10]]]}")
    with scenerender.Renderer(scenerender.Scene.from_yaml(text, "."), gl=gl, profile=True) as renderer:
        renderer.render(1)
        assert len(renderer.timings["opaque"]) == 16
        assert len(renderer.timings["shadow:point0"]) == 1


def test_the_reference_integrates_the_shutter_too(gl):
    """The CPU reference (16 instants drawn at random over the open shutter) smears the
    box over the same 20 px, and the GPU's frame at the default sub-frames is within 2 %
    RMSE of it: within 1 % (0.57 % measured)."""
    sharp = _edge_width(_reference(0.0))
    blurred = _reference(0.5)
    assert np.sqrt(_edge_width(blurred) ** 2 - sharp ** 2) == pytest.approx(20.0, abs=1.0)
    rmse = np.sqrt(np.mean((_render(gl, 1).astype(float) - blurred) ** 2)) / 255.0
    print(f"GPU against the reference: RMSE {rmse:.4f}")
    assert rmse < 0.01, rmse


def _reference(shutter: float) -> np.ndarray:
    scene = scenerender.Scene.from_yaml(MOVING_BOX.format(shutter=shutter, fps=10, end=0.2), ".")
    return render_reference(scene, 1, spp=2, shutter_samples=16).pixels


def test_the_graph_command_names_the_sub_frames_and_plans_their_linear_readback():
    from scenerender.run.graph_report import graph_report

    scene = scenerender.Scene.from_yaml(MOVING_BOX.format(shutter=0.5, fps=10, end=0.2), ".")
    report = graph_report(scene)
    assert report.header("box").endswith(", 16 sub-frames a frame (shutter 0.5)")
    readback = report.compiled.node("readback").render_pass
    assert readback.linear is not None
    still = graph_report(scenerender.Scene.from_yaml(MOVING_BOX.format(shutter=0, fps=10, end=0.2), "."))
    assert "sub-frames" not in still.header("box") and still.compiled.node("readback").render_pass.linear is None
