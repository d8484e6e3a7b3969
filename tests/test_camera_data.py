"""The camera a data set needs: ``camera.intrinsics`` (K in pixels), ``camera.pose`` (a 4 x 4
matrix in OpenCV's or OpenGL's axes), ``cameras.json`` beside every output, and the depth
mode's EXR values in scene units (scenerender.world.camera_data, scenerender.sinks.cameras).
"""
from __future__ import annotations

import json
import math

import numpy as np
import OpenEXR
import pytest
from click.testing import CliRunner

from conftest import render_one
from scenerender.cli import main
from scenerender.world.camera_data import GL_TO_CV, intrinsic_matrix, intrinsics_projection, world_to_camera

MARKER = np.array([0.35, 0.42, -0.3])   # where the marker sits in the world
EYE = np.array([0.6, 1.9, 3.7])
LOOK_AT = np.array([0.0, 0.2, 0.0])
SIZE = (160, 120)
INTRINSICS = {"fx": 150.0, "fy": 140.0, "cx": 66.0, "cy": 52.5}  # off centre: the view is sheared


def cli(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def _camera_to_world(convention: str) -> np.ndarray:
    """A camera at EYE looking at LOOK_AT, its axes in ``convention``."""
    forward = (LOOK_AT - EYE) / np.linalg.norm(LOOK_AT - EYE)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    axes = np.stack([right, up, -forward], axis=1)  # opengl: x right, y up, z back
    if convention == "opencv":
        axes = axes @ GL_TO_CV
    matrix = np.eye(4)
    matrix[:3, :3] = axes
    matrix[:3, 3] = EYE
    return matrix


def _marker_scene(pose_key: str, convention: str) -> str:
    matrix = _camera_to_world(convention)
    if pose_key == "world_to_camera":
        matrix = np.linalg.inv(matrix)
    rows = json.dumps(matrix.tolist())
    return f"""
render: {{size: [{SIZE[0]}, {SIZE[1]}], samples: 4, background: [0, 0, 0]}}
camera:
  intrinsics: {json.dumps(INTRINSICS)}
  pose: {{{pose_key}: {rows}, convention: {convention}}}
objects:
  - mesh: {{primitive: sphere, radius: 0.05, segments: 48}}
    position: {json.dumps(MARKER.tolist())}
    material: {{diffuse: [1, 1, 1], unlit: true}}
"""


def _centroid(pixels: np.ndarray) -> np.ndarray:
    """(u, v) of the bright marker, from the top-left corner (pixel centres at + 0.5)."""
    weight = pixels.astype(np.float64).mean(axis=2)
    assert weight.sum() > 0, "the marker is not in the image"
    v, u = np.mgrid[0:weight.shape[0], 0:weight.shape[1]] + 0.5
    return np.array([(weight * u).sum(), (weight * v).sum()]) / weight.sum()


def _projected(camera: dict, convention: str) -> np.ndarray:
    """Where cameras.json says MARKER lands, using its pose in ``convention``."""
    k = np.array(camera["K"])
    point = np.array(camera["world_to_camera"][convention]) @ np.append(MARKER, 1.0)
    if convention == "opengl":  # the same K, on axes with y and z turned round
        point[:3] = GL_TO_CV @ point[:3]
    pixel = k @ point[:3]
    return pixel[:2] / pixel[2]


@pytest.mark.gl
@pytest.mark.parametrize("convention, pose_key", [("opencv", "camera_to_world"), ("opengl", "world_to_camera")])
def test_marker_renders_where_cameras_json_projects_it(gl, tmp_path, convention, pose_key):
    path = tmp_path / "marker.yaml"
    path.write_text(_marker_scene(pose_key, convention), encoding="utf-8")
    result = cli("render", path, "-o", tmp_path / "out")
    assert result.exit_code == 0, result.output
    camera = json.loads((tmp_path / "out" / "cameras.json").read_text())["frames"][0]
    from PIL import Image
    pixels = np.asarray(Image.open(tmp_path / "out" / "frame_0000.png"))
    found, expected = _centroid(pixels), _projected(camera, convention)
    assert np.abs(found - expected).max() < 0.5, (found, expected)
    # the principal point matters: a centred one would put the marker 14 px to the left
    centred = expected + np.array(SIZE) / 2.0 - [INTRINSICS["cx"], INTRINSICS["cy"]]
    assert np.abs(found - centred).max() > 5.0
    assert np.allclose(camera["K"], [[150, 0, 66], [0, 140, 52.5], [0, 0, 1]], rtol=0, atol=1e-9)
    given = _camera_to_world(convention)
    assert np.allclose(np.array(camera["world_to_camera"][convention]) @ given, np.eye(4), atol=1e-9)


@pytest.mark.gl
def test_intrinsics_equal_to_a_fov_render_the_same_bytes(gl):
    scene = """
render: {size: [160, 120], samples: 4}
camera: {position: [0.5, 2, 5], target: [0, 0.3, 0], CAMERA}
lights: [{type: directional, direction: [-0.4, -1, -0.3], shadows: true}]
objects:
  - mesh: {primitive: plane, size: 6}
  - mesh: {primitive: box, size: 1}
    position: [0.3, 0.5, 0]
"""
    f = 120 / (2.0 * math.tan(math.radians(50.0) / 2.0))
    by_fov = render_one(gl, scene.replace("CAMERA", "fov: 50"))
    by_intrinsics = render_one(gl, scene.replace("CAMERA", f"intrinsics: {{fx: {f!r}, fy: {f!r}, cx: 80, cy: 60}}"))
    assert np.array_equal(by_fov, by_intrinsics)


@pytest.mark.gl
def test_a_pose_equal_to_position_and_target_renders_the_same_image(gl):
    scene = """
render: {size: [160, 120], samples: 4}
camera: {CAMERA}
objects:
  - mesh: {primitive: plane, size: 6}
  - mesh: {primitive: box, size: 1}
    position: [0.3, 0.5, 0]
"""
    aimed = render_one(gl, scene.replace("CAMERA", f"position: {EYE.tolist()}, target: {LOOK_AT.tolist()}"))
    posed = render_one(gl, scene.replace(
        "CAMERA", f"pose: {{camera_to_world: {json.dumps(_camera_to_world('opengl').tolist())}, convention: opengl}}"))
    # the rotation reaches the renderer by two roads (look_rotation; the matrix's polar
    # factor) that may round the last bit apart: at most one level, on edge pixels only
    assert np.abs(aimed.astype(int) - posed).max() <= 1
    assert (aimed != posed).any(axis=2).mean() < 0.002


def test_intrinsics_projection_maps_pixels_like_k():
    intrinsics = type("K", (), INTRINSICS)
    projection = intrinsics_projection(intrinsics, SIZE, 0.1, 100.0)
    point = np.array([0.3, -0.2, -2.0])  # opengl view space
    clip = projection @ np.append(point, 1.0)
    ndc = clip[:2] / clip[3]
    u, v = (ndc[0] + 1.0) * SIZE[0] / 2.0, (1.0 - ndc[1]) * SIZE[1] / 2.0
    cv = GL_TO_CV @ point
    assert u == pytest.approx(INTRINSICS["fx"] * cv[0] / cv[2] + INTRINSICS["cx"], abs=1e-9)
    assert v == pytest.approx(INTRINSICS["fy"] * cv[1] / cv[2] + INTRINSICS["cy"], abs=1e-9)
    assert np.allclose(intrinsic_matrix(projection, SIZE), [[150, 0, 66], [0, 140, 52.5], [0, 0, 1]])


def test_world_to_camera_conventions_differ_by_the_axis_flip():
    rotation = _camera_to_world("opengl")[:3, :3].T
    gl_matrix = world_to_camera(EYE, rotation, "opengl")
    cv_matrix = world_to_camera(EYE, rotation, "opencv")
    assert np.allclose(np.diag([1, -1, -1, 1]) @ gl_matrix, cv_matrix)
    assert np.allclose(gl_matrix @ np.append(EYE, 1.0), [0, 0, 0, 1])
    in_front = cv_matrix @ np.append(LOOK_AT, 1.0)
    assert in_front[2] > 0 and abs(in_front[0]) < 1e-12 and abs(in_front[1]) < 1e-12


# ---------------------------------------------------------------------------------------
# cameras.json follows the output


ANIMATED = """
render: {size: [48, 32], samples: 1}
output: {duration: 0.2, fps: 20}
camera: {position: {keys: [[0, [0, 1, 4]], [0.2, [1, 1, 4]]]}, target: [0, 0, 0], fov: FOV}
objects:
  - mesh: {primitive: box}
"""


def _frames(path):
    return json.loads(path.read_text())["frames"]


@pytest.mark.gl
def test_cameras_json_lists_the_frames_the_output_holds(gl, tmp_path):
    scene = tmp_path / "walk.yaml"
    scene.write_text(ANIMATED.replace("FOV", "50"), encoding="utf-8")
    out = tmp_path / "out"
    assert cli("render", scene, "-o", out, "--frames", "1:3").exit_code == 0
    assert [f["index"] for f in _frames(out / "cameras.json")] == [1, 2]
    assert cli("render", scene, "-o", out).exit_code == 0  # resumes: frames 0 and 3 added
    frames = _frames(out / "cameras.json")
    assert [(f["file"], f["index"]) for f in frames] == [(f"frame_{i:04d}.png", i) for i in range(4)]
    assert frames[3]["time"] == pytest.approx(0.15)
    assert frames[1]["world_to_camera"] != frames[2]["world_to_camera"]  # the camera moves
    first = frames[0]
    assert (first["width"], first["height"], first["projection"]) == (48, 32, "perspective")
    assert 0 < first["near"] < first["far"]
    assert first["K"][1][1] == pytest.approx(16 / math.tan(math.radians(25)))
    # the scene changes: every frame is stale, and so is every camera
    scene.write_text(ANIMATED.replace("FOV", "30"), encoding="utf-8")
    assert cli("render", scene, "-o", out, "--frames", "0:2").exit_code == 0
    frames = _frames(out / "cameras.json")
    assert [f["index"] for f in frames] == [0, 1]
    assert frames[0]["K"][1][1] == pytest.approx(16 / math.tan(math.radians(15)))


@pytest.mark.gl
def test_a_video_has_its_cameras_beside_it(gl, tmp_path):
    scene = tmp_path / "walk.yaml"
    scene.write_text(ANIMATED.replace("FOV", "50"), encoding="utf-8")
    result = cli("render", scene, "-o", tmp_path / "clip.mp4")
    assert result.exit_code == 0, result.output
    frames = _frames(tmp_path / "clip.mp4.cameras.json")
    assert [f["index"] for f in frames] == [0, 1, 2, 3] and "file" not in frames[0]


# ---------------------------------------------------------------------------------------
# depth in scene units


@pytest.mark.gl
def test_exr_depth_is_the_distance_along_the_view_axis_in_scene_units(gl, tmp_path):
    scene = tmp_path / "depth.yaml"
    scene.write_text("""
render: {size: [80, 60], samples: 4, mode: depth}
camera: {position: [0, 4, 0], target: [0, 0, 0], up: [0, 0, -1], fov: 60}
objects:
  - mesh: {primitive: plane, size: 40}
  - mesh: {primitive: box, size: 1}
    position: [0, 0.5, 0]
""", encoding="utf-8")
    assert cli("render", scene, "-o", tmp_path / "out", "--format", "exr").exit_code == 0
    with OpenEXR.File(str(tmp_path / "out" / "frame_0000.exr")) as exr:
        depth = exr.channels()["RGB"].pixels[:, :, 0]
    # the floor is 4 units below the eye everywhere, also in the corners, where the ray
    # to it is 1.3 times longer: depth is along the view axis, not along the ray
    assert depth[0, 0] == pytest.approx(4.0, rel=1e-6) and depth[-1, -1] == pytest.approx(4.0, rel=1e-6)
    assert depth[30, 40] == pytest.approx(3.0, rel=1e-6)  # the box's top
    assert np.all((np.abs(depth - 4.0) < 1e-5) | (np.abs(depth - 3.0) < 1e-5))


# ---------------------------------------------------------------------------------------
# bad input


BAD_CAMERAS = [
    ("{fov: 40, intrinsics: {fx: 100, fy: 100, cx: 40, cy: 30}}", "camera.fov: give either fov or intrinsics"),
    ("{projection: orthographic, intrinsics: {fx: 100, fy: 100, cx: 40, cy: 30}}",
     "camera.intrinsics: intrinsics describe a perspective"),
    ("{intrinsics: {fx: 0, fy: 100, cx: 40, cy: 30}}", "camera.intrinsics.fx: must be > 0"),
    ("{position: [0, 1, 2], pose: {camera_to_world: [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}}",
     "camera.position: give either pose or position"),
    ("{pose: {camera_to_world: [[2,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}}",
     "camera.pose.camera_to_world: the upper-left 3 x 3 must be a rotation"),
    ("{pose: {world_to_camera: [[1,0,0,0],[0,1,0,0],[0,0,-1,3],[0,0,0,1]]}}",
     "camera.pose.world_to_camera: the upper-left 3 x 3 is a reflection"),
    ("{pose: {world_to_camera: [[1,0,0,0],[0,1,0,0],[0,0,1,3]]}}", "camera.pose.world_to_camera: expected 4 rows"),
    ("{pose: {convention: opencv}}", "camera.pose: give one of camera_to_world or world_to_camera"),
    ("{pose: {camera_to_world: [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]], convention: blender}}",
     "camera.pose.convention: expected one of opencv, opengl"),
]


@pytest.mark.parametrize("camera, message", BAD_CAMERAS)
def test_bad_camera_is_one_line_naming_file_line_and_key(tmp_path, camera, message):
    scene = tmp_path / "bad.yaml"
    scene.write_text(f"render: {{size: [80, 60]}}\ncamera: {camera}\nobjects:\n  - mesh: {{primitive: box}}\n",
                     encoding="utf-8")
    result = cli("validate", scene)
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    assert len(result.stderr.splitlines()) == 1
    assert "bad.yaml:2:" in result.stderr and message in result.stderr, result.stderr


def _turned(degrees: float, position) -> list:
    """camera -> world (opengl axes) turned about y by ``degrees`` and placed at ``position``."""
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return [[c, 0, s, position[0]], [0, 1, 0, position[1]], [-s, 0, c, position[2]], [0, 0, 0, 1]]


@pytest.mark.gl
def test_a_keyed_pose_is_exact_at_its_keys_and_rigid_between(gl, tmp_path):
    first, last = _turned(0.0, [0, 1, 5]), _turned(40.0, [2, 1, 5])
    scene = tmp_path / "keyed.yaml"
    scene.write_text(f"""
render: {{size: [48, 32], samples: 1}}
output: {{frames: 5, fps: 4}}
camera:
  pose:
    camera_to_world: {{keys: [[0, {json.dumps(first)}], [1, {json.dumps(last)}]]}}
    convention: opengl
objects:
  - mesh: {{primitive: box}}
""", encoding="utf-8")
    assert cli("render", scene, "-o", tmp_path / "out").exit_code == 0
    frames = json.loads((tmp_path / "out" / "cameras.json").read_text())["frames"]
    for frame, key in ((0, first), (4, last)):
        pose = np.array(frames[frame]["world_to_camera"]["opengl"])
        assert np.allclose(pose @ np.array(key), np.eye(4), atol=1e-12)
    middle = np.linalg.inv(np.array(frames[2]["world_to_camera"]["opengl"]))
    assert np.allclose(middle[:3, :3].T @ middle[:3, :3], np.eye(3), atol=1e-12)
    assert np.allclose(middle[:3, 3], [1, 1, 5])
    angle = math.degrees(math.atan2(middle[0, 2], middle[0, 0]))
    assert 15.0 < angle < 25.0  # turned part of the way (the nearest rotation to the blended matrix)


def test_a_keyed_pose_checks_each_key(tmp_path):
    scene = tmp_path / "bad.yaml"
    bent = _turned(0.0, [0, 1, 5])
    bent[0][0] = 2.0
    scene.write_text(f"camera:\n  pose:\n    camera_to_world: {{keys: [[0, {json.dumps(_turned(0, [0, 1, 5]))}], "
                     f"[1, {json.dumps(bent)}]]}}\nobjects:\n  - mesh: {{primitive: box}}\n", encoding="utf-8")
    result = cli("validate", scene)
    assert result.exit_code == 2
    assert "camera.pose.camera_to_world.keys[1][1]: the upper-left 3 x 3 must be a rotation" in result.stderr, result.stderr
