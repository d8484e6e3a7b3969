"""render.indirect: light bounced between surfaces, from the probe grid
(rendering/passes/indirect.py, shaders/lighting/indirect.glsl).

- A white furnace: a closed box of albedo a whose walls all emit e, and no light. After
  N bounces every wall shows e (1 + a + ... + a^N), exactly, wherever it is seen.
- A thin wall: a lit room beside a dark one, a 5 cm wall between them. What reaches the
  dark room is the classic failure of probe grids (light interpolated through the wall).
- Bounce off: the graph has no bake, and it adds light where on.
- The Cornell box against the path tracer, by region; outdoors, the same at the default
  probe spacing.

Images are 96 x 72 (the furnace), 160 x 80 (the rooms) and 128 x 128 (the Cornell box),
linear light."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import scenerender
from scenerender.rendering.renderer import plan
from scenerender.raytrace import render_reference
from scenerender.tools.bounce_regions import bounce_regions, outdoor_regions, red_over_green, region_errors, relative_rmse

pytestmark = pytest.mark.xdist_group("indirect")

FURNACE = """
render: {{size: [96, 72], samples: 1, background: [0, 0, 0], indirect: {{bounces: {bounces}}}}}
camera: {{position: [0.3, 0.2, 0.9], target: [-0.4, -0.3, -1], fov: 70}}
lights: []
objects:
  - mesh: {{primitive: box, size: [3, 2, 2.4]}}
    material: {{diffuse: [{a}, {a}, {a}], specular: [0, 0, 0], emissive: [{e}, {e}, {e}]}}
  - mesh: {{primitive: box, size: [0.5, 0.5, 0.5]}}
    position: [-0.5, -0.75, -0.4]
    material: {{diffuse: [{a}, {a}, {a}], specular: [0, 0, 0], emissive: [{e}, {e}, {e}]}}
"""
EMISSION = 0.2
# |GPU - analytic| / analytic, the largest of the image's pixels
FURNACE_TOLERANCE = 0.01


def gpu_linear(scene, gl) -> np.ndarray:
    with scenerender.Renderer(scene, gl=gl, want_linear=True) as renderer:
        return renderer.render(0).linear[:, :, :3].astype(np.float64)


def furnace_truth(albedo: float, bounces: int) -> float:
    return EMISSION * sum(albedo ** k for k in range(bounces + 1))


@pytest.mark.parametrize("albedo, bounces", [(0.5, 3), (0.8, 6)])
def test_white_furnace_converges_to_the_analytic_answer(gl, albedo, bounces):
    scene = scenerender.Scene.from_yaml(FURNACE.format(a=albedo, e=EMISSION, bounces=bounces), ".")
    image = gpu_linear(scene, gl)
    truth = furnace_truth(albedo, bounces)
    error = np.abs(image / truth - 1.0).max()
    assert error < FURNACE_TOLERANCE, f"furnace off the analytic {truth:.4f} by {error:.2%} at worst"
    # the tolerance tells one bounce more or less apart
    assert abs(furnace_truth(albedo, bounces - 1) / truth - 1.0) > 3 * FURNACE_TOLERANCE


# Two rooms side by side, open to the sky above (the camera looks in from over them), 2 m
# high, a 5 cm wall between them; a point light in the left one. No surface of the left
# room sees into the right one over the wall, so the right room's truth is black.
ROOMS = """
render: {{size: [160, 80], samples: 1, background: [0, 0, 0], indirect: {{bounces: 2}}}}
camera: {{position: [{x}, 9, 0.01], target: [{x}, 0, 0], fov: 34}}
lights:
  - {{type: point, position: [-1.5, 1.2, 0.3], intensity: 3, attenuation: [0, 0, 1], shadows: true}}
materials:
  white: {{diffuse: [0.8, 0.8, 0.8], specular: [0, 0, 0]}}
objects:
  - {{mesh: {{primitive: box, size: [4.2, 0.1, 2.2]}}, position: [0, -0.05, 0], material: white}}
  - {{mesh: {{primitive: box, size: [0.1, 2, 2.2]}}, position: [-2.05, 1, 0], material: white}}
  - {{mesh: {{primitive: box, size: [0.1, 2, 2.2]}}, position: [2.05, 1, 0], material: white}}
  - {{mesh: {{primitive: box, size: [4.2, 2, 0.1]}}, position: [0, 1, -1.05], material: white}}
  - {{mesh: {{primitive: box, size: [4.2, 2, 0.1]}}, position: [0, 1, 1.05], material: white}}
  - {{mesh: {{primitive: box, size: [0.05, 2, 2.2]}}, position: [{wall}, 1, 0], material: white}}
"""
LEAK_LIMIT = 0.02  # the dark room's floor, at most this fraction of the lit room's


def room_floors(gl, wall: float, spacing: str = "") -> tuple[float, float]:
    """Mean linear brightness of the lit room's floor and of the dark room's beside the wall."""
    text = ROOMS.format(wall=wall, x=0.0)
    if spacing:
        text = text.replace("bounces: 2", f"bounces: 2, probe_spacing: {spacing}")
    image = gpu_linear(scenerender.Scene.from_yaml(text, "."), gl).mean(axis=2)
    height, width = image.shape
    # the floor 9 m below the camera, 80 px over the vertical field of 34 degrees: 14.5 px
    # a metre; the floor's middle band of each room
    metre = height / (2 * 9 * np.tan(np.radians(17)))
    columns = lambda x0, x1: slice(int(width / 2 + x0 * metre), int(width / 2 + x1 * metre))  # noqa: E731
    rows = slice(int(height / 2 - 0.6 * metre), int(height / 2 + 0.6 * metre))
    # the dark room's floor beside the wall, where light interpolated through it would show
    return float(image[rows, columns(-1.8, wall - 0.3)].mean()), float(image[rows, columns(wall + 0.06, wall + 0.6)].mean())


@pytest.mark.parametrize("wall, spacing", [
    (0.0, ""),        # the default grid (13 probes across): a layer of them in the wall's middle
    (0.0, "0.525"),   # 8 across: probes 0.28 m either side of the wall
    (0.0, "0.4"),     # 11 probes across: a layer of them inside the wall
    (0.065, "0.4"),   # probes 4 cm from the wall's lit face
])
def test_a_thin_wall_keeps_the_dark_room_dark(gl, wall, spacing):
    lit, dark = room_floors(gl, wall, spacing)
    assert lit > 0.05
    assert dark <= LEAK_LIMIT * lit, f"the dark room gets {dark / lit:.2%} of the lit room's light"


def test_bounce_off_has_no_bake(gl):
    text = ROOMS.format(wall=0.0, x=0.0)
    off = scenerender.Scene.from_yaml(text.replace(", indirect: {bounces: 2}", ""), ".")
    on = scenerender.Scene.from_yaml(text, ".")
    assert "indirect_light" not in _pass_names(off)
    assert "indirect_light" in _pass_names(on)
    # and the light it adds is what this file's other tests measure
    assert gpu_linear(on, gl).mean() > 1.05 * gpu_linear(off, gl).mean()


def _pass_names(scene) -> list:
    world = scene.world
    return plan(world, world.settings.size, world.settings.samples).compiled.pass_names


# The Cornell box of benchmarks/quality/scenes/cornell_box.yaml at the setting's defaults,
# against the path tracer's kept image (16 bounces, 1024 paths a pixel), by region
# (scenerender/tools/bounce_regions.py). The goal is 5 % in every region; measured at the
# defaults (benchmarks/quality/cornell_indirect.md): the floor in the boxes' shadow -2.5 %
# with the scene's solid casters (+11 % without: the direct light's soft shadow let light
# into the umbra beside the tall box's foot, cornell_split.md), the floor
# under the lamp -2.9 %, the ceiling +2.1 %, every other region within 2 %. Each tolerance
# leaves a point or more over what is measured; the direct-only image is off by 40-100 % in
# every region, and 4 bounces instead of 8 fail (the floor under the lamp -7.6 %, the red
# wall -9.5 %).
QUALITY = Path(__file__).resolve().parent.parent / "benchmarks" / "quality"
CORNELL_TOLERANCES = {"ceiling": 0.04, "floor_under_light": 0.045, "floor_in_shadow": 0.05, "red_wall": 0.03,
                      "green_wall": 0.02, "back_wall": 0.02, "box_sides": 0.02, "tall_box_front": 0.02,
                      "short_box_front": 0.03}
CORNELL_RMSE = 0.06     # measured 4.8 %; the goal 10 %
BLEEDING_TOLERANCE = 0.045  # red/green of each box's side face against the truth's: measured 3.1-3.3 % low


def test_cornell_box_against_the_path_tracer(gl):
    scene_file = QUALITY / "scenes" / "cornell_box.yaml"
    kept = QUALITY / "references"
    reference = np.load(kept / "cornell_box_bounces16.npy").astype(np.float64)
    direct = np.load(kept / "cornell_box_direct.npy").astype(np.float64)
    objects = np.load(kept / "cornell_box_objects.npy")

    def render(overrides):
        scene = scenerender.Scene.from_yaml(scene_file.read_text(), scene_file.parent, overrides)
        return gpu_linear(scene, gl)

    encoded = render(["render.mode=normals", "render.samples=1"])
    normals = encoded * 2.0 - 1.0
    normals /= np.maximum(np.linalg.norm(normals, axis=2, keepdims=True), 1e-9)
    regions = bounce_regions(objects, normals, direct)
    image = render(["render.indirect={}"])
    errors = region_errors(image, reference, regions)
    failed = {name: f"{100 * error:+.1f} %" for name, error in errors.items() if abs(error) > CORNELL_TOLERANCES[name]}
    assert not failed, f"regions off the path tracer: {failed}"
    assert relative_rmse(image, reference) < CORNELL_RMSE
    for face in ("tall_box_front", "short_box_front"):
        bleeding = red_over_green(image, regions[face]) / red_over_green(reference, regions[face])
        assert abs(bleeding - 1.0) < BLEEDING_TOLERANCE, f"{face}: red/green {bleeding:.3f} of the truth's"


# benchmarks/quality/scenes/outdoor_bounce.yaml (a 16 m ground, white boxes of 0.6-1.6 m, a
# sky and a sun) at the setting's defaults against the path tracer rendered here (8
# bounces, 4 x 4 paths a pixel; against 6 x 6 the regions read within 2.2 points). The goal:
# every region within 10 %. Measured (benchmarks/quality/README.md, 12 x 12 paths): the
# boxes' faces in the sun's shadow +8.9 %, the rest within 2.5 % (at 4 x 4: +6.4 %, within
# 4.2 %); the first default (the longest side over 8, probes 2 m apart) fails here, the
# ground in the boxes' shadow at -20 %.
OUTDOOR_TOLERANCE = 0.10


def test_outdoors_at_the_default_spacing_against_the_path_tracer(gl):
    scene_file = QUALITY / "scenes" / "outdoor_bounce.yaml"

    def load(overrides=()):
        return scenerender.Scene.from_yaml(scene_file.read_text(), scene_file.parent, list(overrides))

    truth = render_reference(load(), 0, spp=4, bounces=8)
    direct = render_reference(load(), 0, spp=4).linear.astype(np.float64)
    normals = gpu_linear(load(["render.mode=normals", "render.samples=1"]), gl) * 2.0 - 1.0
    normals /= np.maximum(np.linalg.norm(normals, axis=2, keepdims=True), 1e-9)
    regions = outdoor_regions(truth.object, normals, direct, (1, 2, 3))
    errors = region_errors(gpu_linear(load(["render.indirect={}"]), gl), truth.linear.astype(np.float64), regions)
    failed = {name: f"{100 * error:+.1f} %" for name, error in errors.items() if abs(error) > OUTDOOR_TOLERANCE}
    assert not failed, f"regions off the path tracer: {failed}"
