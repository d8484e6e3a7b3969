"""glTF animations read from the file's JSON (scenerender.mesh.gltf_animation): each
interpolation checked against an independent reading of the glTF 2.0 specification's
Appendix C (slerp as q0 (q0^-1 q1)^u through the axis and angle; the cubic spline as a
Bezier curve by de Casteljau), to 1e-5."""
from __future__ import annotations

import math

import numpy as np
import pytest

from gltf_files import GlbBuilder, sphere
from scenerender.mesh.gltf import GltfProblem, split_glb
from scenerender.mesh.gltf_animation import clip_time, read_clips, read_skins

TIMES = np.array([0.0, 0.75, 2.0])  # float32 holds these exactly
ROTATIONS = np.array([[0.0, 0.0, 0.0, 1.0],
                      [0.0, math.sin(0.7), 0.0, math.cos(0.7)],                      # 80 degrees about y
                      [math.sin(1.2) * 0.6, math.sin(1.2) * 0.8, 0.0, math.cos(1.2)]]).astype(np.float32).astype(float)
# (the file stores float32: the keys are those numbers exactly)


def _quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz])


def _quat_power(q, u):
    """q^u for a unit quaternion: the same axis, u times the angle."""
    angle = 2.0 * math.atan2(np.linalg.norm(q[:3]), q[3])
    axis = q[:3] / np.linalg.norm(q[:3]) if np.linalg.norm(q[:3]) > 0 else np.array([1.0, 0.0, 0.0])
    return np.append(axis * math.sin(u * angle / 2.0), math.cos(u * angle / 2.0))


def spec_slerp(q0, q1, u):
    """slerp(q0, q1, u) = q0 (q0^-1 q1)^u, the shorter way round (q1 negated when q0.q1 < 0)."""
    if np.dot(q0, q1) < 0:
        q1 = -q1
    inverse = np.array([-q0[0], -q0[1], -q0[2], q0[3]])
    return _quat_mul(q0, _quat_power(_quat_mul(inverse, q1), u))


def spec_cubic(p0, out_tangent, p1, in_tangent, td, u):
    """The Hermite segment as a Bezier curve: controls p0, p0 + td b / 3, p1 - td a / 3, p1."""
    points = [p0, p0 + td * out_tangent / 3.0, p1 - td * in_tangent / 3.0, p1]
    while len(points) > 1:
        points = [(1 - u) * a + u * b for a, b in zip(points, points[1:])]
    return points[0]


def _same_rotation(a, b):
    """Quaternions q and -q are one rotation."""
    return min(np.abs(a - b).max(), np.abs(a + b).max())


@pytest.fixture
def clips(tmp_path):
    builder = GlbBuilder()
    node = builder.node(builder.mesh(builder.primitive(sphere(0.2, 1))))
    rng = np.random.default_rng(3)
    tangents = (rng.normal(size=(3, 2, 4)) * 0.5).astype(np.float32).astype(float)  # in and out tangent per key
    cubic = np.concatenate([[a, v, b] for (a, b), v in zip(tangents, ROTATIONS)])
    translations = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, -1.0], [3.0, 0.0, 0.5]])
    builder.animation("step", [(node, "rotation", TIMES, ROTATIONS, "STEP")])
    builder.animation("linear", [(node, "rotation", TIMES, ROTATIONS, "LINEAR"),
                                 (node, "translation", TIMES, translations, "LINEAR")])
    builder.animation(None, [(node, "rotation", TIMES, cubic, "CUBICSPLINE")])
    path = builder.write(tmp_path / "spin.glb")
    return read_clips(split_glb(path.read_bytes())), cubic


@pytest.mark.parametrize("t", [0.3, 0.75, 1.37, 1.99])
def test_rotation_between_keys_follows_the_specification_in_all_three_modes(clips, t):
    found, cubic = clips
    k = int(np.searchsorted(TIMES, t, side="right")) - 1
    td = TIMES[k + 1] - TIMES[k]
    u = (t - TIMES[k]) / td
    step, linear, spline = (clip.channels[0](t) for clip in found)
    assert _same_rotation(step, ROTATIONS[k]) < 1e-12
    assert _same_rotation(linear, spec_slerp(ROTATIONS[k], ROTATIONS[k + 1], u)) < 1e-5
    expected = spec_cubic(cubic[3 * k + 1], cubic[3 * k + 2], cubic[3 * k + 4], cubic[3 * k + 3], td, u)
    assert _same_rotation(spline, expected / np.linalg.norm(expected)) < 1e-5
    assert abs(np.linalg.norm(linear) - 1.0) < 1e-6 and abs(np.linalg.norm(spline) - 1.0) < 1e-12


def test_translation_is_linear_and_held_outside_the_keys(clips):
    linear = clips[0][1]
    translation = linear.channels[1]
    assert np.allclose(translation(0.375), [0.5, 1.0, -0.5], atol=1e-6)
    assert np.allclose(translation(-1.0), [0, 0, 0]) and np.allclose(translation(5.0), [3.0, 0.0, 0.5], atol=1e-6)


def test_clips_have_names_indices_and_durations(clips):
    found = clips[0]
    assert [(c.index, c.name, c.label) for c in found] == [(0, "step", "'step'"), (1, "linear", "'linear'"),
                                                           (2, None, "#2")]
    assert [c.duration for c in found] == [2.0, 2.0, 2.0]


def test_a_file_without_animations_has_no_clips(tmp_path):
    builder = GlbBuilder()
    builder.node(builder.mesh(builder.primitive(sphere(0.2, 1))))
    assert read_clips(split_glb(builder.write(tmp_path / "still.glb").read_bytes())) == []


def test_bad_animations_are_named(tmp_path):
    builder = GlbBuilder()
    node = builder.node(builder.mesh(builder.primitive(sphere(0.2, 1))))
    builder.animation("bad", [(node, "rotation", [0.0, 1.0, 0.5], ROTATIONS, "LINEAR")])
    with pytest.raises(GltfProblem, match="strictly increasing"):
        read_clips(split_glb(builder.write(tmp_path / "bad.glb").read_bytes()))
    builder.json["animations"][0]["samplers"][0]["interpolation"] = "SMOOTH"
    with pytest.raises(GltfProblem, match="unknown interpolation 'SMOOTH'"):
        read_clips(split_glb(builder.write(tmp_path / "bad.glb").read_bytes()))


@pytest.mark.parametrize("t, speed, offset, loop, expected", [
    (2.5, 1.0, 0.0, True, 0.5), (2.5, 1.0, 0.0, False, 2.0), (1.0, 2.0, 0.25, True, 1.5),
    (0.1, 1.0, 0.5, True, 1.6), (0.1, 1.0, 0.5, False, 0.0), (1.0, -1.0, 0.0, True, 1.0)])
def test_scene_time_to_clip_time(t, speed, offset, loop, expected):
    assert clip_time(t, 2.0, speed, offset, loop) == pytest.approx(expected)


def test_the_example_animated_glb_is_what_its_generator_writes_and_has_its_clips():
    """scenes/assets/models/fan_and_arm.glb: regenerated byte for byte, and its clips read."""
    import importlib.util

    from conftest import SCENES

    spec = importlib.util.spec_from_file_location("animated_models", SCENES / "assets" / "animated_models.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    stored = (SCENES / "assets" / "models" / "fan_and_arm.glb").read_bytes()
    assert module.build() == stored
    found = read_clips(split_glb(stored))
    assert [(c.name, c.duration) for c in found] == [("spin", 2.0), ("bend", 2.0), ("tick", 2.0), ("all", 2.0)]
    assert {ch.interpolation for ch in found[3].channels} == {"STEP", "LINEAR", "CUBICSPLINE"}
    assert {ch.path for ch in found[3].channels} == {"rotation", "weights"}
    assert len(read_skins(split_glb(stored))) == 1


@pytest.mark.gl
def test_the_example_animated_glb_plays(gl):
    """Its skinned tube, one-target morph and rigid parts pose and draw, and move."""
    from conftest import render

    scene = """
render: {size: [80, 60], samples: 1}
output: {frames: 4, fps: 4}
camera: {position: [0, 1.3, 3.2], target: [0, 0.8, 0], fov: 50}
objects:
  - mesh: assets/models/fan_and_arm.glb
    animation: {clip: all}
"""
    first, later = render(gl, scene, frames=(0, 3))
    assert not np.array_equal(first, later)
