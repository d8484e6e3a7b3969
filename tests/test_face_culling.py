"""Skipping the faces the camera cannot see: closed surfaces are found from the mesh alone,
faces are skipped only where no part of the surface can be seen from inside, and the
image does not change."""
from __future__ import annotations

import numpy as np
import pytest

import scenerender
from scenerender.compare import DEFAULT_RULE, compare_images
from scenerender.mesh import make_primitive
from scenerender.mesh.topology import closed_winding
from scenerender.world import frame as frame_module
from scenerender.world.camera import CameraState, look_rotation, orthographic, perspective
from scenerender.world.frame import hidden_faces


@pytest.mark.parametrize("kind", ["box", "sphere", "cylinder", "prism", "cone"])
def test_primitives_are_closed_and_wound_outwards(kind):
    mesh = make_primitive(kind)
    assert closed_winding(mesh.positions, mesh.indices) == 1


def test_a_plane_is_open():
    mesh = make_primitive("plane")
    assert closed_winding(mesh.positions, mesh.indices) == 0


def test_reversed_triangles_wind_inwards():
    mesh = make_primitive("box")
    assert closed_winding(mesh.positions, mesh.indices[:, ::-1]) == -1


def test_a_box_missing_a_face_is_open():
    mesh = make_primitive("box")
    assert closed_winding(mesh.positions, mesh.indices[2:]) == 0


def test_one_flipped_triangle_is_inconsistent():
    mesh = make_primitive("sphere")
    indices = mesh.indices.copy()
    indices[5] = indices[5, ::-1]
    assert closed_winding(mesh.positions, indices) == 0


def test_two_boxes_sharing_nothing_are_closed_but_a_shared_face_is_not():
    box = make_primitive("box")
    n = len(box.positions)
    positions = np.concatenate([box.positions, box.positions + np.float32(5.0)])
    assert closed_winding(positions, np.concatenate([box.indices, box.indices + n])) == 1
    twice = np.concatenate([box.indices, box.indices + n])
    assert closed_winding(np.concatenate([box.positions, box.positions]), twice) == 0  # every edge used 4 times


def _camera(position, target=(0.0, 0.0, 0.0), near=0.1, ortho=False):
    position = np.asarray(position, dtype=np.float64)
    rotation = look_rotation(np.asarray(target) - position, np.array([0.0, 1.0, 0.0]))
    projection = orthographic(4.0, 1.0, near, 100.0) if ortho else perspective(60.0, 1.0, near, 100.0)
    return CameraState(position, rotation, projection, near, 100.0, 60.0, 1.0, ortho)


UNIT = np.array([[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]])


def test_outside_a_closed_surface_its_far_faces_are_hidden():
    assert hidden_faces(1, UNIT, _camera((0, 0, 5))) == "back"
    assert hidden_faces(-1, UNIT, _camera((0, 0, 5))) == "front"
    assert hidden_faces(0, UNIT, _camera((0, 0, 5))) is None


def test_inside_or_near_enough_to_clip_into_it_every_face_may_show():
    assert hidden_faces(1, UNIT, _camera((0, 0, 0.5), target=(0, 0, -1))) is None  # inside
    # 0.05 outside: the near plane (0.1 away, its corners ~0.14) cuts into the surface
    assert hidden_faces(1, UNIT, _camera((0, 0, 1.05), near=0.1)) is None
    assert hidden_faces(1, UNIT, _camera((0, 0, 1.2), near=0.1)) == "back"


def test_orthographic_cameras_never_skip_faces():
    assert hidden_faces(1, UNIT, _camera((0, 0, 5), ortho=True)) is None


def _object_frames(scene: dict, tmp_path, index: int = 0):
    s = scenerender.Scene.from_dict(scene, base_dir=tmp_path)
    world = s.world
    evaluator = frame_module.FrameEvaluator(world, (64, 48), None)
    return evaluator.evaluate(0, 0.0).objects


CAMERA = {"position": [0, 1, 6], "target": [0, 0, 0]}


def test_the_near_plane_may_be_close_when_the_surface_lies_beyond_it():
    camera = _camera((0, 0, 1.15), near=0.1)  # near plane corners reach 0.14 > 0.15 - 0.1
    assert hidden_faces(1, UNIT, camera) == "back"  # the whole box is 0.15..2.15 deep


def test_transparent_surfaces_and_open_meshes_keep_every_face(tmp_path):
    objects = _object_frames({"camera": CAMERA, "objects": [
        {"mesh": {"primitive": "box"}},
        {"mesh": {"primitive": "box"}, "material": {"opacity": 0.5}, "position": [2, 0, 0]},
        {"mesh": {"primitive": "plane"}, "position": [0, -1, 0]},
        {"mesh": {"primitive": "box"}, "position": [0, 1, 7]},  # behind the camera, around it
    ]}, tmp_path)
    assert [o.hidden_faces for o in objects] == ["back", None, None, "back"]


def _render(scene, tmp_path, cull: bool, monkeypatch, gl):
    if not cull:
        monkeypatch.setattr(frame_module, "hidden_faces", lambda winding, bounds, camera: None)
    with scenerender.Renderer(scenerender.Scene.from_dict(scene, base_dir=tmp_path), gl=gl) as renderer:
        pixels = [renderer.render(i).pixels for i in range(3)]
    monkeypatch.undo()
    return pixels


@pytest.mark.gl
def test_skipping_hidden_faces_leaves_the_image_as_it_was(gl, tmp_path, monkeypatch):
    """Closed and open meshes, shadows, AO and 4x MSAA; the camera moves."""
    scene = {
        "render": {"size": [96, 72], "samples": 4, "ambient_occlusion": {"radius": 0.5, "samples": 8}},
        "output": {"frames": 3, "fps": 2},
        "camera": {"position": {"keys": [[0, [0, 2, 6]], [1, [3, 1.5, 4]]]}, "target": [0, 0.5, 0]},
        "lights": [{"type": "directional", "direction": [-1, -2, -1], "shadows": True}, {"type": "ambient"}],
        "objects": [
            {"mesh": {"primitive": "plane", "size": 8}},
            {"mesh": {"primitive": "sphere"}, "position": [0, 1, 0]},
            {"mesh": {"primitive": "box"}, "position": [1.5, 0.5, 0], "rotation": [0, 30, 0]},
            {"mesh": {"primitive": "cone"}, "position": [-1.5, 0.5, 0]},
        ],
    }
    culled = _render(scene, tmp_path, True, monkeypatch, gl)
    drawn = _render(scene, tmp_path, False, monkeypatch, gl)
    for a, b in zip(drawn, culled):
        verdict = compare_images("cull", a, b, DEFAULT_RULE, keep_images=False)
        assert verdict.passed, verdict
        assert (np.abs(a.astype(int) - b.astype(int)).max(axis=2) > 0).mean() < 0.002  # silhouette ties at most


# -- shadow maps skip the faces turned away from the light ------------------------------

def _light_view(kind: str, eye=(0.0, 0.0, 5.0)):
    from scenerender.world.shadows import ShadowView, Tile
    camera = _camera(eye, near=0.1, ortho=kind == "directional")
    view = np.eye(4)
    view[:3, :3] = camera.rotation
    view[:3, 3] = -camera.rotation @ camera.position
    return ShadowView(view, camera.projection, 0.1, 100.0, kind == "point", Tile(0, 0, 64))


def test_a_directional_view_sees_every_closed_surface_from_outside():
    from scenerender.world.shadows import hidden_from_light
    assert hidden_from_light(_light_view("directional", (0, 0, 0.5)), 1, UNIT) == "back"
    assert hidden_from_light(_light_view("directional"), -1, UNIT) == "front"
    assert hidden_from_light(_light_view("directional"), 0, UNIT) is None


def test_a_light_inside_a_closed_surface_sees_its_inner_faces():
    from scenerender.world.shadows import hidden_from_light
    assert hidden_from_light(_light_view("point", (0, 0, 0.5)), 1, UNIT) is None  # a lamp in a shade
    assert hidden_from_light(_light_view("point", (0, 0, 5)), 1, UNIT) == "back"


SHADOW_SCENE = {
    "render": {"size": [96, 72], "mode": "light_depth"},
    "output": {"frames": 2, "fps": 1},
    "camera": {"position": {"keys": [[0, [0, 2, 6]], [1, [3, 1.5, 4]]]}, "target": [0, 0.5, 0]},
    "objects": [
        {"mesh": {"primitive": "plane", "size": 8}},
        {"mesh": {"primitive": "sphere"}, "position": [0, 1, 0]},
        {"mesh": {"primitive": "box"}, "position": [1.5, 0.5, 0], "rotation": [0, 30, 0]},
        {"mesh": {"primitive": "cone"}, "position": [-1.5, 0.5, 0], "scale": [1, 1, -1]},  # mirrored
    ],
}


def _light_depth(light: dict, tmp_path, gl, faces=None, monkeypatch=None):
    from scenerender.rendering.passes import shadow as shadow_module
    if faces is not None:
        monkeypatch.setattr(shadow_module, "hidden_from_light", faces)
    scene = {**SHADOW_SCENE, "lights": [light]}
    with scenerender.Renderer(scenerender.Scene.from_dict(scene, base_dir=tmp_path), gl=gl) as renderer:
        pixels = [renderer.render(i).pixels.astype(int) for i in range(2)]
    if monkeypatch is not None:
        monkeypatch.undo()
    return pixels


def _towards_the_light(view, winding, bounds):
    """Skips the faces turned towards the light instead: a regression the test must catch."""
    from scenerender.world.shadows import hidden_from_light
    return {"back": "front", "front": "back"}.get(hidden_from_light(view, winding, bounds))


@pytest.mark.gl
@pytest.mark.parametrize("light, skips", [
    ({"type": "directional", "direction": [-1, -2, -1], "shadows": True}, True),
    ({"type": "point", "position": [0.5, 2.5, 1.5], "shadows": True}, True),
    ({"type": "point", "position": [0, 1, 0], "shadows": True}, False),  # inside the sphere: it skips none
], ids=["directional", "point", "point-inside"])
def test_skipping_faces_turned_from_the_light_leaves_its_map_as_it_was(gl, tmp_path, monkeypatch, light, skips):
    """The light's depth map with the faces skipped against every face drawn; and skipping
    the wrong faces (the ones turned towards the light) is caught."""
    culled = _light_depth(light, tmp_path, gl)
    drawn = _light_depth(light, tmp_path, gl, lambda view, winding, bounds: None, monkeypatch)
    wrong = _light_depth(light, tmp_path, gl, _towards_the_light, monkeypatch)
    for a, b, c in zip(drawn, culled, wrong):
        assert (np.abs(a - b).max(axis=2) > 0).mean() < 0.002  # texel-centre ties on silhouettes at most
        assert ((np.abs(a - c).max(axis=2) > 8).mean() > 0.01) == skips  # 1.8-3 % where it skips
