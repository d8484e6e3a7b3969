"""A glTF clip played on an object (``objects[].animation``): each node with a mesh moves with
its node and every animated node above it (scenerender.world.node_animation)."""
from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from click.testing import CliRunner

from conftest import render
from gltf_files import GlbBuilder
from scenerender.cli import main

TIMES = [0.0, 1.0, 2.0]
SPIN = np.array([[0, 0, 0, 1], [0, 0, 1, 0], [0, 0, 0, -1]], dtype=float)  # 0, 180, 360 degrees about z
BOB = [[0, 1, 0], [0, 1.5, 0], [0, 1, 0]]


def _fan(path, blade_rotation=None, hub_translation=(0, 1, 0), clips=True):
    """A hub with a bar of blades as its child; the clips turn the blades and raise the hub."""
    builder = GlbBuilder()
    blades = builder.mesh(builder.primitive(trimesh.creation.box((1.6, 0.2, 0.1))))
    hub = builder.mesh(builder.primitive(trimesh.creation.box((0.3, 0.3, 0.3))))
    extra = {"rotation": list(blade_rotation)} if blade_rotation is not None else {}
    blade = builder.node(blades, root=False, name="blades", translation=[0, 0, 0.2], **extra)
    top = builder.node(hub, name="hub", translation=list(hub_translation), children=[blade])
    if clips:
        builder.animation("spin", [(blade, "rotation", TIMES, SPIN, "LINEAR")])
        builder.animation("both", [(blade, "rotation", TIMES, SPIN, "LINEAR"), (top, "translation", TIMES, BOB, "LINEAR")])
    return builder.write(path)


def _scene(mesh: str, animation: str = "") -> str:
    return f"""
render: {{size: [96, 72], samples: 4}}
output: {{frames: 8, fps: 4}}
camera: {{position: [0, 1.3, 4], target: [0, 1.2, 0], fov: 50}}
lights: [{{type: directional, direction: [-0.3, -1, -0.5], shadows: true}}]
objects:
  - mesh: {{primitive: plane, size: 6}}
  - mesh: {mesh}
    {animation}
"""


@pytest.mark.gl
@pytest.mark.parametrize("frame", [1, 3, 6])
def test_a_clip_moves_each_node_and_its_subtree_as_the_file_would_at_rest(gl, tmp_path, frame):
    _fan(tmp_path / "fan.glb")
    t = frame / 4.0
    angle = math.pi * t  # half a turn a second, about z
    height = 1.0 + 0.5 * (t if t <= 1 else 2 - t)
    _fan(tmp_path / "posed.glb", (0, 0, math.sin(angle / 2), math.cos(angle / 2)), (0, height, 0), clips=False)
    played = render(gl, _scene("fan.glb", "animation: {clip: both}"), frames=(frame,), base_dir=tmp_path)[0]
    posed = render(gl, _scene("posed.glb"), frames=(frame,), base_dir=tmp_path)[0]
    # the same triangles placed by two roads (a node's matrix at rest; the rest pose moved
    # by W(t) W_rest^-1): float32 rounding may move an edge sample, never a surface
    differs = np.abs(played.astype(int) - posed).max(axis=2) > 2
    assert differs.mean() < 0.003, differs.sum()
    assert not np.array_equal(played, render(gl, _scene("fan.glb"), frames=(frame,), base_dir=tmp_path)[0])


@pytest.mark.gl
def test_a_file_with_clips_but_no_animation_key_renders_todays_bytes(gl, tmp_path):
    _fan(tmp_path / "fan.glb")
    _fan(tmp_path / "still.glb", clips=False)
    with_clips = render(gl, _scene("fan.glb"), frames=(0, 3), base_dir=tmp_path)
    without = render(gl, _scene("still.glb"), frames=(0, 3), base_dir=tmp_path)
    assert all(np.array_equal(a, b) for a, b in zip(with_clips, without))


@pytest.mark.gl
def test_speed_offset_and_loop_play_the_clip_in_scene_time(gl, tmp_path):
    _fan(tmp_path / "fan.glb")
    # speed 2 at 0.25 s is clip time 0.5; offset 0.25 at 0.75 s is clip time 0.5 too;
    # looped, 2.5 s is clip time 0.5 again
    base = render(gl, _scene("fan.glb", "animation: {clip: spin}"), frames=(2,), base_dir=tmp_path)[0]
    fast = render(gl, _scene("fan.glb", "animation: {clip: 0, speed: 2}"), frames=(1,), base_dir=tmp_path)[0]
    late = render(gl, _scene("fan.glb", "animation: {clip: spin, offset: 0.25}"), frames=(3,), base_dir=tmp_path)[0]
    looped = render(gl, _scene("fan.glb", "animation: {clip: spin}").replace("frames: 8", "frames: 12"),
                    frames=(10,), base_dir=tmp_path)[0]
    assert np.array_equal(base, fast) and np.array_equal(base, late) and np.array_equal(base, looped)


def _validate(tmp_path, animation):
    _fan(tmp_path / "fan.glb")
    (tmp_path / "s.yaml").write_text(_scene("fan.glb", animation), encoding="utf-8")
    return CliRunner().invoke(main, ["validate", str(tmp_path / "s.yaml")])


def test_validate_lists_the_clips_and_their_durations(tmp_path):
    result = _validate(tmp_path, "animation: {clip: both}")
    assert result.exit_code == 0, result.output
    assert "fan.glb: clips #0 'spin' (2 s), #1 'both' (2 s)" in result.stdout


@pytest.mark.parametrize("animation, message", [
    ("animation: {clip: walk}", "fan.glb has no clip 'walk'; its clips: #0 'spin' (2 s), #1 'both' (2 s)"),
    ("animation: {clip: 2}", "fan.glb has no clip 2; its clips"),
    ("animation: {clip: spin, speed: fast}", "objects[1].animation.speed: expected a number"),
])
def test_a_clip_the_file_lacks_is_one_line_naming_file_line_key_and_clips(tmp_path, animation, message):
    result = _validate(tmp_path, animation)
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert len(result.stderr.splitlines()) == 1
    assert "s.yaml:9:" in result.stderr
    assert ("objects[1].animation." in result.stderr) and message in result.stderr, result.stderr


def test_animation_needs_a_gltf_mesh(tmp_path):
    (tmp_path / "s.yaml").write_text(_scene("{primitive: box}", "animation: {clip: 0}"), encoding="utf-8")
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "s.yaml")])
    assert result.exit_code == 2
    assert "objects[1].animation: animation plays the clips of a glTF file" in result.stderr


@pytest.mark.gl
def test_frames_of_a_playing_clip_equal_frames_drawn_from_scratch(gl, tmp_path):
    """The parts move, so nothing that draws them (their shadow map) may be kept from an
    earlier frame: a run's frames equal each frame rendered on its own."""
    _fan(tmp_path / "fan.glb")
    scene = _scene("fan.glb", "animation: {clip: both}")
    run = render(gl, scene, frames=(0, 1, 2, 5), base_dir=tmp_path)
    alone = [render(gl, scene, frames=(i,), base_dir=tmp_path)[0] for i in (0, 1, 2, 5)]
    assert all(np.array_equal(a, b) for a, b in zip(run, alone))
    assert not np.array_equal(run[1], run[2])


def test_parts_the_clip_does_not_move_stay_still(tmp_path):
    from conftest import scene

    _fan(tmp_path / "fan.glb")
    world = scene(_scene("fan.glb", "animation: {clip: spin}"), base_dir=tmp_path).world
    parts = {obj.name: obj.motion for obj in world.objects}
    assert parts["fan1/hub"] is None and parts["fan1/blades"] is not None  # spin turns the blades alone
    world = scene(_scene("fan.glb", "animation: {clip: both}"), base_dir=tmp_path).world
    assert all(obj.motion is not None for obj in world.objects[1:])  # the hub moves, and with it the blades


def test_normalize_and_a_clip_do_not_go_together(tmp_path):
    _fan(tmp_path / "fan.glb")
    (tmp_path / "s.yaml").write_text(_scene("fan.glb", "animation: {clip: 0}\n    normalize: true"), encoding="utf-8")
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "s.yaml")])
    assert result.exit_code == 2 and "objects[1].normalize: normalize rescales the mesh at rest" in result.stderr
