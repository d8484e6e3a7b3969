"""A flat receiver is drawn without the shadow lookup outside the screen rectangle where
directional shadows can fall on it (rendering/shadow_reach.py): frames are the same bytes
as with the whole receiver shadowed, and the rectangle is only used where it can be told."""
from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from scenerender.rendering import shadow_reach
from scenerender.rendering.passes import forward

from conftest import render

BENCH = Path(__file__).resolve().parent.parent / "benchmarks" / "scenes" / "bench" / "bench.yaml"

SPHERES_ON_GROUND = """
render: {size: [160, 90], samples: 4}
camera: {position: [0.6, 1.6, 4.5], target: [0, 0.4, 0], fov: 45}
lights:
  - {type: directional, direction: [-0.5, -1, -0.4], shadows: {size: 256}}
  - {type: ambient, color: [0.2, 0.2, 0.2]}
objects:
  - {name: ground, mesh: {primitive: plane, size: 8}, cast_shadows: false}
  - {name: front, mesh: {primitive: sphere, radius: 0.4, segments: 16, rings: 9}, position: [0.2, 0.4, 1.2]}
  - {name: side, mesh: {primitive: box, size: [0.6, 0.6, 0.6]}, position: [-1.4, 0.3, 0.4]}
"""


def rectangles_seen(monkeypatch) -> list:
    """Every {object index: rectangle} the opaque pass works out, as it renders."""
    seen = []
    original = forward.Shading.shadow_free

    def spy(self, *args):
        found = original(self, *args)
        seen.append(found)
        return found

    monkeypatch.setattr(forward.Shading, "shadow_free", spy)
    return seen


@pytest.mark.parametrize("frame_scene, overrides, frames", [
    (SPHERES_ON_GROUND, [], (0,)),
    (BENCH, ["render.size=[160, 120]"], (0, 40, 80)),
], ids=["spheres", "bench"])
def test_frames_are_the_bytes_of_the_whole_receiver_shadowed(gl, monkeypatch, frame_scene, overrides, frames):
    """Exact: 0 levels, with the rectangle inside the screen (so both draws ran). A
    rectangle that cuts through the shadows (the lower-left pixel alone) differs, so the
    comparison can fail."""
    seen = rectangles_seen(monkeypatch)
    split = render(gl, frame_scene, overrides, frames=frames)
    size = split[0].shape[1], split[0].shape[0]
    rectangles = [r for found in seen for r in found.values()]
    assert len(rectangles) == len(frames)
    assert all(0 <= x0 < x1 <= size[0] and 0 <= y0 < y1 <= size[1] and (x1 - x0) * (y1 - y0) < size[0] * size[1]
               for x0, y0, x1, y1 in rectangles)
    monkeypatch.setattr(forward.Shading, "shadow_free", lambda self, *args: {})
    whole = render(gl, frame_scene, overrides, frames=frames)
    monkeypatch.undo()
    monkeypatch.setattr(forward, "shadowed_rectangle", lambda *args: (0, 0, 1, 1))
    wrong = render(gl, frame_scene, overrides, frames=frames)
    monkeypatch.undo()
    for a, b in zip(split, whole):
        assert np.array_equal(a, b)
    assert not all(np.array_equal(a, b) for a, b in zip(wrong, whole))


def test_a_spot_lights_shadow_keeps_the_whole_receiver_shadowed(gl, monkeypatch):
    """Its views are perspective: where they reach is not worked out, so no rectangle."""
    seen = rectangles_seen(monkeypatch)
    spot = SPHERES_ON_GROUND.replace(
        "{type: directional, direction: [-0.5, -1, -0.4], shadows: {size: 256}}",
        "{type: spot, position: [1, 3, 1], direction: [-0.3, -1, -0.3], shadows: {size: 256}}")
    render(gl, spot)
    assert seen == [{}]


def ortho_view(direction) -> SimpleNamespace:
    """A directional light's view looking along ``direction`` over [-4, 4]^2."""
    forward_axis = np.asarray(direction, dtype=np.float64) / np.linalg.norm(direction)
    up = np.array([0.0, 1.0, 0.0]) if abs(forward_axis[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = np.cross(forward_axis, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward_axis)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = right, true_up, -forward_axis
    projection = np.diag([0.25, 0.25, -0.1, 1.0])
    return SimpleNamespace(view=view, projection=projection, radial=False)


CAMERA = SimpleNamespace(position=np.array([0.0, 2.0, 6.0]),
                         view_proj_relative=lambda: np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0],
                                                              [0, 0, -1.0, -0.2], [0, 0, -1.0, 0]]))
BOX = np.array([[[-0.5, 0.0, -0.5], [0.5, 1.0, 0.5]]])


def test_the_rectangle_holds_the_casters_shadow_on_the_plane():
    # the sun straight down: the box's shadow is its own footprint on the ground
    rectangle = shadow_reach.shadowed_rectangle([(ortho_view([0, -1, 0]), 256)], BOX, 1, 0.0, CAMERA, (200, 200), 3)
    x0, y0, x1, y1 = rectangle
    for corner in ([-0.5, 0.0, -0.5], [0.5, 0.0, 0.5]):
        relative = np.array(corner) - CAMERA.position
        clip = CAMERA.view_proj_relative() @ np.append(relative, 1.0)
        pixel = (clip[:2] / clip[3] * 0.5 + 0.5) * 200
        assert x0 < pixel[0] < x1 and y0 < pixel[1] < y1
    assert (x1 - x0) * (y1 - y0) < 200 * 200


def test_no_rectangle_where_it_cannot_be_told():
    level = ortho_view([1, 0, 0])  # light along the plane: its shadows stretch without end
    assert shadow_reach.shadowed_rectangle([(level, 256)], BOX, 1, 0.0, CAMERA, (200, 200), 3) is None
    radial = SimpleNamespace(**{**vars(ortho_view([0, -1, 0])), "radial": True})
    assert shadow_reach.shadowed_rectangle([(radial, 256)], BOX, 1, 0.0, CAMERA, (200, 200), 3) is None
    # no caster: nothing is shadowed anywhere
    assert shadow_reach.shadowed_rectangle([(ortho_view([0, -1, 0]), 256)], BOX[:0], 1, 0.0, CAMERA,
                                           (200, 200), 3) == (0, 0, 0, 0)


def test_around_covers_the_rest_once():
    pieces = shadow_reach.around((3, 2, 7, 5), (10, 8))
    covered = np.zeros((8, 10), dtype=int)
    covered[2:5, 3:7] += 1
    for x0, y0, x1, y1 in pieces:
        covered[y0:y1, x0:x1] += 1
    assert np.all(covered == 1)
    assert shadow_reach.around((0, 0, 0, 0), (10, 8)) == [(0, 0, 10, 8)]
