"""Objects that never move are evaluated as arrays (world/frame.py StillObjects): their
frames must hold what the one-object-at-a-time evaluation gives, bit for bit."""
from __future__ import annotations

import numpy as np

import scenerender
from scenerender.world.frame import FrameEvaluator, frustum_planes

SCENE = """
render: {size: [160, 120]}
output: {fps: 10, frames: 20}
camera:
  position: {keys: [[0, [0, 2, 6]], [1, [4, 1.5, 3]], [2, [0.2, 0.6, 1.4]]]}
  target: [0, 0.5, 0]
lights:
  - {type: directional, direction: [-0.4, -1, -0.3], shadows: true}
objects:
  - {name: ground, mesh: {primitive: plane, size: 10}}
  - {name: near, mesh: {primitive: box}, position: [0.3, 0.5, 1.0], rotation: [0, 30, 0], scale: [1, 0.5, 2]}
  - {name: mirrored, mesh: {primitive: sphere, radius: 0.4}, position: [-1.5, 0.4, 0], scale: [-1, 1, 1]}
  - {name: far, mesh: {primitive: cone}, position: [30, 0.5, -40]}
  - {name: edge, mesh: {primitive: box, size: [8, 0.2, 0.2]}, position: [6.5, 0.5, 0]}  # centre out of view
  - {name: hidden, mesh: {primitive: box}, position: [1.5, 0.5, -1], visible: false}
  - {name: moving, mesh: {primitive: box}, position: {keys: [[0, [2, 0.5, 0]], [2, [2, 0.5, 2]]]}}
  - name: many
    mesh: {primitive: box, size: [0.2, 0.2, 0.2]}
    instances: {random: {count: 5, seed: 1, position: {min: [-2, 0, -2], max: [2, 1, 2]}}}
"""


def one_at_a_time(evaluator: FrameEvaluator, frame) -> list:
    """The frames FrameEvaluator._object makes object by object for ``frame``'s camera."""
    world = evaluator.world
    planes = frustum_planes(frame.camera.view_proj_relative())
    placements = [evaluator._placement(obj, obj.matrices(frame.time), evaluator._windings[i], frame.time)
                  for i, obj in enumerate(world.objects)]
    return [evaluator._object(obj, p, bool(obj.visible(frame.time)), frame.camera, planes, frame.time)
            for obj, p in zip(world.objects, placements)]


def test_still_objects_are_evaluated_as_one_object_at_a_time_would_be():
    world = scenerender.Scene.from_yaml(SCENE, ".").world
    evaluator = FrameEvaluator(world, (160, 120), None)
    assert len(evaluator._still.rows) == 6  # ground, near, mirrored, far, edge, hidden
    for index in (0, 7, 13, 19):
        frame = evaluator.evaluate(index, index / 10.0)
        for obj, got, want in zip(world.objects, frame.objects, one_at_a_time(evaluator, frame)):
            assert got.models_rel.tobytes() == want.models_rel.tobytes(), obj.name
            assert got.models.tobytes() == want.models.tobytes(), obj.name
            assert got.normals.tobytes() == want.normals.tobytes(), obj.name
            assert np.array_equal(got.bounds, want.bounds) and np.array_equal(got.center, want.center), obj.name
            assert (got.visible, got.in_view, got.hidden_faces, got.winding) == \
                   (want.visible, want.in_view, want.hidden_faces, want.winding), (obj.name, index)


def test_the_scene_tests_what_matters():
    """The frames above include objects out of view, in view, hidden, seen from inside
    their bounds' reach and not: else the comparison would not cover them."""
    world = scenerender.Scene.from_yaml(SCENE, ".").world
    evaluator = FrameEvaluator(world, (160, 120), None)
    frames = [evaluator.evaluate(i, i / 10.0) for i in (0, 7, 13, 19)]
    names = [obj.name for obj in world.objects]
    far = names.index("far")
    assert {f.objects[far].in_view for f in frames} == {0, 1}
    assert {f.objects[names.index("near")].hidden_faces for f in frames} >= {None, "back"}
    assert all(f.objects[names.index("hidden")].in_view == 0 for f in frames)
    # in view only by its reach: its centre projects outside the image
    edge = names.index("edge")
    clip = frames[0].camera.view_proj_relative() @ np.append(frames[0].objects[edge].models_rel[0][:3, 3], 1.0)
    assert frames[0].objects[edge].in_view == 1 and abs(clip[0] / clip[3]) > 1.0


def test_each_object_is_looked_through_once_for_its_animated_keys(gl, monkeypatch):
    """Which keys of the objects and materials animate is worked out once a world
    (World.animated_parts) and shared by the inputs with and without fixed shadow views and
    by the frames' still objects. Each walk goes through every field of every object: at
    1,000 objects it cost 0.06 s, and it ran three times before a first frame."""
    from scenerender.world import frame_inputs

    walked = []
    every_key = frame_inputs.animated_keys
    monkeypatch.setattr(frame_inputs, "animated_keys", lambda value, skip=(): walked.append(value) or
                        every_key(value, skip))
    scene = scenerender.Scene.from_yaml(SCENE, ".")
    with scenerender.Renderer(scene, gl=gl) as renderer:
        for index in (0, 7):
            renderer.render(index)
    objects = scene.world.objects
    assert len(objects) == 8 and all(sum(value is obj for value in walked) == 1 for obj in objects)
