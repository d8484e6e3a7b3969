"""A shadow map whose views and casters did not change is kept, not redrawn, and the frames
are the frames drawn from scratch."""
from __future__ import annotations

import numpy as np
import pytest

import scenerender
from scenerender.rendering.renderer import GraphRenderer

ORBIT = {"keys": [[0, [0, 2.5, 6]], [1, [6, 2.5, 0]], [2, [0, 2.5, -6]]]}
CASTERS = [
    {"mesh": {"primitive": "plane", "size": 12}, "cast_shadows": False},
    {"mesh": {"primitive": "sphere"}, "position": [0, 1, 0]},
    {"mesh": {"primitive": "box"}, "position": [1.2, 0.5, 0.3]},
]
SUN = {"name": "sun", "type": "directional", "direction": [-1, -2, -1], "shadows": True}


def _scene(lights, objects=CASTERS) -> dict:
    return {"render": {"size": [64, 48], "samples": 1}, "output": {"frames": 6, "fps": 2},
            "camera": {"position": ORBIT, "target": [0, 0.5, 0]}, "lights": lights, "objects": objects}


def _frames(gl, tmp_path, scene: dict, cache: bool):
    """(pixels of frames 0-5, how many times each shadow pass ran)."""
    world = scenerender.Scene.from_dict(scene, base_dir=tmp_path).world
    renderer = GraphRenderer(world, gl, profile=True, cache_static_passes=cache)
    try:
        pixels = [renderer.render(i).pixels for i in range(6)]
        runs = {name: len(times) for name, times in renderer.timings.items() if name.startswith("shadow:")}
    finally:
        renderer.release()
    return pixels, runs


def _same_as_from_scratch(gl, tmp_path, scene: dict) -> dict:
    kept, runs = _frames(gl, tmp_path, scene, cache=True)
    fresh, _ = _frames(gl, tmp_path, scene, cache=False)
    assert any(not np.array_equal(kept[0], f) for f in kept[1:]), "the camera did not move"
    for a, b in zip(kept, fresh):
        assert np.array_equal(a, b)
    return runs


@pytest.mark.gl
def test_a_turntable_keeps_the_sun_map_its_view_never_changes(gl, tmp_path):
    """The casters stay inside the camera's view, so the sun's view, fitted to them, is the
    same in every frame: drawn once, though the view follows the camera."""
    assert _same_as_from_scratch(gl, tmp_path, _scene([SUN])) == {"shadow:sun": 1}


@pytest.mark.gl
def test_a_moving_caster_redraws_the_map_every_frame(gl, tmp_path):
    moving = {**CASTERS[2], "position": {"keys": [[0, [1.2, 0.5, 0.3]], [3, [0.2, 0.5, 1.3]]]}}
    runs = _same_as_from_scratch(gl, tmp_path, _scene([SUN], [*CASTERS[:2], moving]))
    assert runs == {"shadow:sun": 6}


@pytest.mark.gl
def test_a_changed_map_beside_a_kept_one_on_the_same_page_clears_only_its_own_tiles(gl, tmp_path):
    """The sun's map is kept (it creates the page and would clear it); the swinging spot
    light's map, on the same page, is redrawn every frame over its own cleared tiles."""
    spot = {"name": "spot", "type": "spot", "position": [2, 3, 2], "shadows": True,
            "direction": {"keys": [[0, [-0.5, -1, -0.5]], [3, [-0.2, -1, -0.6]]]}}
    runs = _same_as_from_scratch(gl, tmp_path, _scene([SUN, spot]))
    assert runs == {"shadow:sun": 1, "shadow:spot": 6}
