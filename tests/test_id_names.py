"""Names of unnamed objects for object ids (scenerender.world.id_names): made from what an
object is, so that inserting one renames no other; a counter only among identical ones.
Scenes are loaded, not rendered (no GL)."""
from __future__ import annotations

from scenerender.run.session import load
from scenerender.world.id_names import id_names

OBJECTS = [
    "  - {mesh: {primitive: sphere, radius: 0.5}, position: [0, 0.5, 0], material: steel}",
    "  - {name: plinth, mesh: {primitive: box}, position: [1, 0.5, 0], material: steel}",
    "  - {mesh: {primitive: box}, position: [-1.004, 0.5, -0.001], material: steel}",
    "  - {mesh: {primitive: cone}, position: [2, 0, 0], material: {diffuse: [1, 0, 0]}}",
    "  - {mesh: {primitive: cone}, position: [2, 0, 0], material: {diffuse: [0, 1, 0]}}",
]
NEW = "  - {mesh: {primitive: sphere, radius: 0.2}, position: [0, 1.5, 0], material: steel}"


def names_of(tmp_path, objects: list[str]) -> dict:
    scene = tmp_path / "scene.yaml"
    scene.write_text("materials:\n  steel: {diffuse: [0.5, 0.5, 0.5]}\nobjects:\n" + "\n".join(objects) + "\n")
    return id_names(load(scene).world)


def test_unnamed_objects_are_named_by_mesh_material_and_position(tmp_path):
    assert names_of(tmp_path, OBJECTS) == {
        1: "sphere steel at (0, 0.5, 0)", 2: "plinth", 3: "box steel at (-1, 0.5, 0)",
        4: "cone inline at (2, 0, 0)", 5: "cone inline at (2, 0, 0) #2"}


def test_inserting_an_object_renames_no_other(tmp_path):
    before = names_of(tmp_path, OBJECTS)
    for at in range(len(OBJECTS) + 1):
        after = names_of(tmp_path, OBJECTS[:at] + [NEW] + OBJECTS[at:])
        assert after.pop(at + 1) == "sphere steel at (0, 1.5, 0)"
        assert list(after.values()) == list(before.values()), at


def test_an_identical_object_inserted_shifts_only_the_counter_of_its_twins(tmp_path):
    twin = OBJECTS[3]
    after = names_of(tmp_path, [twin] + OBJECTS)
    assert list(after.values()) == ["cone inline at (2, 0, 0)", "sphere steel at (0, 0.5, 0)", "plinth",
                                    "box steel at (-1, 0.5, 0)", "cone inline at (2, 0, 0) #2",
                                    "cone inline at (2, 0, 0) #3"]
