"""Motion blur along a velocity buffer (render.motion_blur: velocity): the box of
test_motion_blur.py, moving 40 px a frame, smears over 20 px at shutter 0.5 as with the
sub-frames; its frame is near the reference's and the sub-frames'; the motion each pixel
is blurred along is the screen motion over the open shutter, from the object's and from
the camera's keys; unset, or with the shutter at 0, the graph and the bytes are as before."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from scipy import ndimage

import scenerender
from scenerender.colorspace import srgb_decode
from scenerender.raytrace import render_reference
from scenerender.run.graph_report import graph_report
from scenerender.world.frame import FrameEvaluator
from scenerender.world.motion import translation, world_to_clip

from test_motion_blur import MOVING_BOX, _edge_width

SCENES = Path(__file__).resolve().parent.parent / "scenes"

VELOCITY = "render.motion_blur=velocity"
VELOCITY_PASSES = {"velocity", "velocity_tiles", "velocity_neighbours", "motion_blur"}
# the box still, the camera panning 8 units (80 px) in 0.2 s the other way: on screen the
# same 40 px a frame
PANNING = MOVING_BOX.replace("{{keys: [[0, [-4, 0, 0]], [{end}, [4, 0, 0]]]}}", "[0, 0, 0]").replace(
    "position: [0, 0, 10], target: [0, 0, 0]",
    "position: {{keys: [[0, [4, 0, 10]], [{end}, [-4, 0, 10]]]}}, target: {{keys: [[0, [4, 0, 0]], [{end}, [-4, 0, 0]]]}}")


def _scene(shutter=0.5, overrides=(VELOCITY,), text=MOVING_BOX):
    return scenerender.Scene.from_yaml(text.format(shutter=shutter, fps=10, end=0.2), ".", list(overrides))


def _render(gl, shutter=0.5, overrides=(VELOCITY,), text=MOVING_BOX, profile=False):
    with scenerender.Renderer(_scene(shutter, overrides, text), gl=gl, profile=profile) as renderer:
        pixels = renderer.render(1).pixels
        return (pixels, renderer.timings) if profile else pixels


def _smear(gl, shutter, text=MOVING_BOX) -> float:
    """The edge's spread less the unblurred edge's (pixels; test_motion_blur._edge_width)."""
    sharp = _edge_width(_render(gl, 0.0, text=text))
    return float(np.sqrt(_edge_width(_render(gl, shutter, text=text)) ** 2 - sharp ** 2))


def test_a_box_moving_40_px_a_frame_smears_over_20_px_at_shutter_half(gl):
    """Within 2 px (the edge's own ramp is measured over 80 columns, which at this box's
    width end where the triangle's fall begins); 19.5 and 10.1 px measured."""
    assert _smear(gl, 0.5) == pytest.approx(20.0, abs=2.0)
    assert _smear(gl, 0.25) == pytest.approx(10.0, abs=2.0)


def _shifted_box(width_px: int, shift_px: float) -> str:
    """MOVING_BOX ``width_px`` wide and tall, moved ``shift_px`` right and up, so that at a
    fractional shift its edges at the frame's time cut pixels (the colour's edge pixels
    then mix the box and the background, the velocity image's hold one of them)."""
    shift = shift_px / 10.0
    keys = f"[[0, [{shift - 4}, {shift}, 0]], [{{end}}, [{shift + 4}, {shift}, 0]]]"
    return MOVING_BOX.replace("size: [2, 2, 2]", f"size: [{width_px / 10}, {width_px / 10}, 2]").replace(
        "[[0, [-4, 0, 0]], [{end}, [4, 0, 0]]]", keys)


def _ramp_width(pixels: np.ndarray, columns: slice) -> float:
    """sqrt(12) times the standard deviation of where the linear coverage changes along
    the middle row over ``columns`` (a ramp of width L: L / sqrt(12)), in pixels."""
    change = np.abs(np.diff(srgb_decode(pixels[60, columns, 0] / 255.0)))
    x = np.arange(len(change)) + 0.5
    mean = (x * change).sum() / change.sum()
    return float(np.sqrt(12.0 * ((x - mean) ** 2 * change).sum() / change.sum()))


@pytest.mark.parametrize("shift_px", [0.0, 0.25, 0.5])
def test_a_wide_box_s_smear_is_its_motion_over_the_shutter_within_a_pixel(gl, shift_px):
    """A box 40 px wide moving 40 px a frame, shutter 0.5: both edges ramp over 20 px
    (less the unblurred edge's own width), 20 +- 1 at whole and fractional positions.
    Measured 19.3 to 20.1 (the sub-frames: 20.3); before the taps reached the path's last
    half pixel, 18.5 to 19.4."""
    text = _shifted_box(40, shift_px)
    sharp, blurred = _render(gl, 0.0, text=text), _render(gl, text=text)
    for columns in (slice(30, 80), slice(80, 130)):
        smear = np.sqrt(_ramp_width(blurred, columns) ** 2 - _ramp_width(sharp, columns) ** 2)
        assert smear == pytest.approx(20.0, abs=1.0), (columns, smear)


@pytest.mark.parametrize("shift_px", [0.0, 0.25, 0.5])
def test_no_seam_along_the_instant_s_edges(gl, shift_px):
    """The box of test_motion_blur (20 px, 40 px a frame, shutter 0.5) and one 10 px wide,
    cutting pixels at the frame's time: no pixel of the velocity blur brighter than the
    64 sub-frames' brightest pixel around it (3 x 3) by more than 2 levels. The blur read
    edge pixels as the still background and kept their share of the box unblurred: 11 to
    34 levels over (a seam along the box's instant edges)."""
    for width in (20, 10):
        text = _shifted_box(width, shift_px)
        velocity = _render(gl, text=text)[..., 0].astype(int)
        sub_frames = _render(gl, overrides=("render.film_samples=64",), text=text)[..., 0].astype(int)
        excess = velocity - ndimage.maximum_filter(sub_frames, size=3)
        assert excess.max() <= 2, (width, excess.max(), np.unravel_index(np.argmax(excess), excess.shape))


def test_a_panning_camera_smears_a_still_box_the_same(gl):
    assert _smear(gl, 0.5, PANNING) == pytest.approx(20.0, abs=2.0)


def test_the_motion_is_the_screen_motion_over_the_open_shutter():
    """The box's centre, shown at pixel x 80 at the frame's time, is 10 px to the left at
    the shutter's opening and 10 px to the right at its closing (40 px a frame, shutter
    0.5), in float64; for the panning camera too."""
    for text in (MOVING_BOX, PANNING):
        world = _scene(text=text).world
        frame = FrameEvaluator(world, (160, 120), None).evaluate(1, 0.1)
        centre = np.append(-frame.camera.position, 1.0)  # the world origin, camera-relative
        xs = []
        for matrix in (frame.motion.open[0], frame.motion.close[0]):
            clip = matrix @ centre
            xs.append((clip[0] / clip[3] + 1.0) * 80.0)
        now = world_to_clip(frame.camera) @ np.array([0.0, 0.0, 0.0, 1.0])
        assert (now[0] / now[3] + 1.0) * 80.0 == pytest.approx(80.0)
        np.testing.assert_allclose(xs, [70.0, 90.0], atol=1e-9)


def test_error_against_the_reference_and_the_sub_frames(gl):
    """RMSE (of 255) of the velocity frame against the CPU reference over the shutter and
    against the default 16 sub-frames: under 1.5 % each (measured 0.95 % and 0.58 %); the
    sub-frames are at 0.57 % of the reference (test_motion_blur)."""
    velocity = _render(gl).astype(np.float64)
    sub_frames = _render(gl, overrides=()).astype(np.float64)
    reference = render_reference(_scene(overrides=()), 1, spp=2, shutter_samples=16).pixels.astype(np.float64)
    to_reference = np.sqrt(np.mean((velocity - reference) ** 2)) / 255.0
    to_sub_frames = np.sqrt(np.mean((velocity - sub_frames) ** 2)) / 255.0
    print(f"velocity against the reference {to_reference:.4f}, against the sub-frames {to_sub_frames:.4f}")
    assert to_reference < 0.015 and to_sub_frames < 0.015, (to_reference, to_sub_frames)
    still = _render(gl, 0.0).astype(np.float64)
    assert np.sqrt(np.mean((still - reference) ** 2)) / 255.0 > 2 * to_reference  # the blur is what brings it near


def test_one_instant_a_frame_and_the_passes_only_where_the_shutter_is_open(gl):
    pixels, timings = _render(gl, profile=True)
    assert len(timings["opaque"]) == 1  # no sub-frames
    assert VELOCITY_PASSES <= set(timings)
    assert VELOCITY_PASSES <= set(graph_report(_scene()).compiled.pass_names)
    for closed in (_scene(0.0), _scene(overrides=())):
        assert not VELOCITY_PASSES & set(graph_report(closed).compiled.pass_names)


def test_unset_renders_the_bytes_it_rendered_before(gl):
    """Shutter 0 with the velocity setting: the bytes of the scene without either key; the
    setting left out: the bytes of the sub-frames named."""
    text = MOVING_BOX.format(shutter=0, fps=10, end=0.2).replace(", shutter: 0}", "}")
    with scenerender.Renderer(scenerender.Scene.from_yaml(text, "."), gl=gl) as renderer:
        plain = renderer.render(1).pixels
    assert np.array_equal(_render(gl, 0.0), plain)
    assert np.array_equal(_render(gl, overrides=()), _render(gl, overrides=("render.motion_blur=sub_frames",)))


def test_a_still_shot_keeps_its_motion_cached_and_draws_what_a_fresh_frame_draws(gl):
    """The box and the camera still, the box's colour animated: the motion (none) and the
    velocity passes are static, drawn on the first frame only; the blurred frames equal
    frames drawn from scratch."""
    text = MOVING_BOX.format(shutter=0.5, fps=10, end=0.2).replace(
        "{keys: [[0, [-4, 0, 0]], [0.2, [4, 0, 0]]]}", "[0, 0, 0]").replace(
        "diffuse: [1, 1, 1]", "diffuse: {keys: [[0, [1, 1, 1]], [0.2, [0.2, 0.5, 1]]]}")
    scene = scenerender.Scene.from_yaml(text, ".", [VELOCITY])
    compiled = graph_report(scene).compiled
    assert all(compiled.is_static(compiled.node(name).render_pass)
               for name in ("velocity", "velocity_tiles", "velocity_neighbours"))
    assert not compiled.is_static(compiled.node("motion_blur").render_pass)
    frames = {}
    for cache in (True, False):
        with scenerender.Renderer(scene, gl=gl, cache_static_passes=cache, profile=True) as renderer:
            frames[cache] = [renderer.render(index).pixels for index in range(3)]
            runs = len(renderer.timings["velocity"])
        assert runs == (1 if cache else 3)
    assert all(np.array_equal(a, b) for a, b in zip(frames[True], frames[False]))


def test_a_turning_camera_smears_the_skybox_too(gl, tmp_path):
    """A camera turning 24 degrees a frame past the edge between two faces of a skybox (no
    objects): the skybox moves only as the camera turns, and the velocity blur smears the
    edge as 64 sub-frames do. RMSE (of 255) against them: under half the instant's
    (measured 0.15 % against 2.8 %; 2.8 % without the skybox's motion)."""
    sky = tmp_path / "sky"
    sky.mkdir()
    for face, colour in {"posx": 40, "negx": 230, "posy": 120, "negy": 120, "posz": 40, "negz": 40}.items():
        Image.new("RGB", (8, 8), (colour,) * 3).save(sky / f"{face}.png")
    turning = {
        "render": {"size": [160, 120], "skybox": "sky"}, "output": {"fps": 10, "duration": 0.2},
        "camera": {"position": [0, 0, 0], "target": {"keys": [[0, [-0.75, 0, -1.3]], [0.2, [-1.3, 0, -0.75]]]},
                   "fov": 60, "shutter": 0.5},
        "lights": [], "objects": [],
    }

    def render(*overrides):
        with scenerender.Renderer(scenerender.Scene.from_dict(turning, base_dir=tmp_path, overrides=list(overrides)),
                                  gl=gl) as renderer:
            return renderer.render(1).pixels.astype(np.float64)

    filmed = render("render.film_samples=64")
    velocity = render(VELOCITY)
    instant = render("camera.shutter=0")
    to_velocity, to_instant = (np.sqrt(np.mean((frame - filmed) ** 2)) / 255.0 for frame in (velocity, instant))
    print(f"against 64 sub-frames: velocity {to_velocity:.4f}, the instant {to_instant:.4f}")
    assert to_velocity < 0.5 * to_instant, (to_velocity, to_instant)


def test_a_gltf_clip_s_node_motion_is_in_the_motion():
    """scenes/assets/models/fan_and_arm.glb playing its clips: parts a node animation
    moves get motion over the shutter although their object stands still; parts without a
    node motion get none."""
    scene = scenerender.Scene.from_yaml("""
render: {size: [80, 60], motion_blur: velocity}
output: {frames: 4, fps: 4}
camera: {position: [0, 1.3, 3.2], target: [0, 0.8, 0], fov: 50, shutter: 0.5}
objects:
  - mesh: assets/models/fan_and_arm.glb
    animation: {clip: all}
""", str(SCENES))
    world = scene.world
    frame = FrameEvaluator(world, (80, 60), None).evaluate(1, 0.25)
    still = world_to_clip(frame.camera) @ translation(frame.camera.position)
    moved = [not np.allclose(opened, still) for opened in frame.motion.open]
    assert any(moved)
    assert not any(m for obj, m in zip(world.objects, moved) if obj.motion is None)
