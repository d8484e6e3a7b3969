"""The visible-samples prepass draws only what the post-depth coverage needs
(rendering/visible_samples.py): the plan on scenes evaluated without GL, and frames that
are the same bytes as with every object through the prepass."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import scenerender
from scenerender.rendering.draw import opaque_items
from scenerender.rendering.graph_inputs import ObjectsInput
from scenerender.rendering.passes import forward
from scenerender.rendering.visible_samples import VisibleSamplesPlan, plan_visible_samples
from scenerender.world.frame import FrameEvaluator

from conftest import render_one

SCENES = Path(__file__).resolve().parent.parent / "scenes"

SPHERES_ON_GROUND = """
render: {size: [96, 72], samples: 4}
camera: {position: [0.6, 1.6, 4.5], target: [0, 0.4, 0], fov: 45}
lights:
  - {type: directional, direction: [-0.5, -1, -0.4], shadows: {size: 256}}
  - {type: ambient, color: [0.2, 0.2, 0.2]}
objects:
  - {name: ground, mesh: {primitive: plane, size: 8}, cast_shadows: false}
  - {name: front, mesh: {primitive: sphere, radius: 0.4, segments: 16, rings: 9}, position: [0.2, 0.4, 1.2]}
  - {name: behind, mesh: {primitive: sphere, radius: 0.5, segments: 16, rings: 9}, position: [-0.1, 0.5, -0.2]}
  - {name: side, mesh: {primitive: box, size: [0.6, 0.6, 0.6]}, position: [-1.4, 0.3, 0.4]}
"""


def plan_of(text: str, overrides=()) -> tuple[VisibleSamplesPlan, list]:
    world = scenerender.Scene.from_yaml(text, ".", list(overrides)).world
    frame = FrameEvaluator(world, world.settings.size, None).evaluate(0, 0.0)
    objects = ObjectsInput(world.objects, frame.objects, frame.camera.position, None)
    items = opaque_items(objects, frame.camera)
    names = [obj.name for obj in world.objects]
    return plan_visible_samples(objects, frame.camera, items), names


def test_apart_convex_objects_and_the_ground_skip_the_prepass_in_an_order_that_hides_first():
    plan, names = plan_of(SPHERES_ON_GROUND)
    assert plan.prepass == frozenset()
    order = [names[item.object_index] for item in plan.order]
    # the ground last; the sphere in front before the one it hides
    assert order[-1] == "ground" and order.index("front") < order.index("behind")


def test_objects_whose_bounding_spheres_meet_go_through_the_prepass():
    touching = SPHERES_ON_GROUND.replace("position: [-0.1, 0.5, -0.2]", "position: [0.2, 0.5, 0.5]")
    plan, names = plan_of(touching)
    assert {names[i] for i in plan.prepass} == {"front", "behind"}


def test_a_camera_that_may_see_inside_keeps_the_object_in_the_prepass():
    # the near plane can cut into the box: its hidden faces are drawn, it may cover itself
    inside = SPHERES_ON_GROUND.replace("position: [-1.4, 0.3, 0.4]", "position: [0.6, 1.6, 4.5]")
    plan, names = plan_of(inside)
    assert "side" in {names[i] for i in plan.prepass}


def test_a_flat_object_with_something_beneath_it_is_no_ground():
    under = SPHERES_ON_GROUND.replace("position: [-1.4, 0.3, 0.4]", "position: [-1.4, -0.5, 0.4]")
    plan, names = plan_of(under)
    # the box below it could be hidden by it: the ground meets the other spheres' bounds
    assert names.index("ground") in plan.prepass


def test_an_orthographic_camera_keeps_every_object_in_the_prepass():
    plan, names = plan_of(SPHERES_ON_GROUND, ["camera.projection=orthographic"])
    assert plan.prepass_is_everything


def every_object_through_the_prepass(objects, camera, items, last=None):
    """The plan before rendering/visible_samples.py: every object, nearest first."""
    return VisibleSamplesPlan(items, frozenset(item.object_index for item in items))


def nearest_first_without_prepass(objects, camera, items, last=None):
    """A wrong plan, to show the comparison below sees one: the ground, nearest, is drawn
    first, and its coverage counts the samples the spheres and the box cover later."""
    return VisibleSamplesPlan(items, frozenset())


@pytest.mark.parametrize("frame_scene", [
    SPHERES_ON_GROUND,
    SPHERES_ON_GROUND.replace("position: [-0.1, 0.5, -0.2]", "position: [0.2, 0.5, 0.5]"),
    # an alpha-masked sheet in the prepass, the ground drawn after it: with depth writes
    # left on for the sheet, its holes showed the clear colour (149 levels off)
    SCENES / "gltf_pbr.yaml",
], ids=["apart", "meeting", "alpha_mask"])
def test_frames_are_the_bytes_the_full_prepass_gives(gl, monkeypatch, frame_scene):
    """Exact: 0 levels. The same comparison against a wrong plan (nearest first, no
    prepass: the ground's coverage counts samples covered later) differs, so it can fail."""
    overrides = ["render.size=[160, 90]", "render.samples=4"]
    planned = render_one(gl, frame_scene, overrides)
    monkeypatch.setattr(forward, "plan_visible_samples", every_object_through_the_prepass)
    full = render_one(gl, frame_scene, overrides)
    monkeypatch.setattr(forward, "plan_visible_samples", nearest_first_without_prepass)
    wrong = render_one(gl, frame_scene, overrides)
    monkeypatch.undo()
    assert np.array_equal(planned, full)
    assert not np.array_equal(wrong, full)
