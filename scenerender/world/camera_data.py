"""The camera as a data set records it, and the camera a data set gives: a pinhole's
intrinsic matrix K in pixels and poses in OpenCV's and OpenGL's axis conventions.

Pixel coordinates (u, v) run right and down from the top-left corner of the image, so the
centre of pixel (i, j) is at (i + 0.5, j + 0.5) and a centred principal point is
(width / 2, height / 2). OpenCV's calibration puts pixel centres at whole numbers: add 0.5
to its cx and cy.

Camera axes: ``opengl`` x right, y up, the camera looking down -z (what the renderer uses,
``CameraState.rotation``); ``opencv`` x right, y down, looking down +z. One is the other
with y and z negated.
"""
from __future__ import annotations

import math

import numpy as np

# opengl camera axes -> opencv camera axes (and back: it is its own inverse)
GL_TO_CV = np.diag([1.0, -1.0, -1.0])


def intrinsics_fov(intrinsics, size: tuple) -> float:
    """The vertical field of view (degrees) of ``intrinsics`` on an image of ``size``
    (width, height) pixels, about the image centre: what frames a default camera."""
    return math.degrees(2.0 * math.atan(size[1] / (2.0 * intrinsics.fy)))


def intrinsics_projection(intrinsics, size: tuple, near: float, far: float) -> np.ndarray:
    """(4, 4) float64 view -> clip (OpenGL conventions) of a pinhole with focal lengths
    fx, fy and principal point cx, cy in pixels of an image ``size`` (width, height).

    A view point (x, y, z) lands at u = cx + fx * x / -z, v = cy - fy * y / -z; with
    x_ndc = 2 u / W - 1 and y_ndc = 1 - 2 v / H that is the matrix below, whose third
    column shears the frustum when the principal point is off centre. Depth rows are
    ``perspective``'s."""
    width, height = size
    m = np.zeros((4, 4))
    m[0, 0] = 2.0 * intrinsics.fx / width
    m[0, 2] = 1.0 - 2.0 * intrinsics.cx / width
    m[1, 1] = 2.0 * intrinsics.fy / height
    m[1, 2] = 2.0 * intrinsics.cy / height - 1.0
    m[2, 2] = (far + near) / (near - far)
    m[2, 3] = 2.0 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def pose_placement(pose, t: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(position (3,), world -> view rotation (3, 3), rows right, up, back) of a
    ``camera.pose`` (scene.model.camera_data.PoseSpec) at time ``t``, float64. Keyed
    matrices are interpolated number by number; the nearest rotation to the result is the
    camera's turn (exact at the keys)."""
    to_world = pose.camera_to_world_matrix(t)
    axes = to_world[:3, :3]  # columns: the camera's axes in the world
    if pose.convention == "opencv":
        axes = axes @ GL_TO_CV
    return to_world[:3, 3].copy(), _nearest_rotation(axes.T)


def _nearest_rotation(matrix: np.ndarray) -> np.ndarray:
    """The rotation nearest ``matrix`` (its polar factor): a pose written with 7 digits is
    orthonormal only to about 1e-7, and the renderer wants orthonormal rows."""
    u, _, vt = np.linalg.svd(matrix)
    return u @ vt


def intrinsic_matrix(projection: np.ndarray, size: tuple) -> np.ndarray:
    """(3, 3) K of a perspective ``projection`` (intrinsics_projection's inverse: also for
    a projection made from ``fov``) on an image ``size`` (width, height) pixels."""
    width, height = size
    return np.array([[projection[0, 0] * width / 2.0, 0.0, (1.0 - projection[0, 2]) * width / 2.0],
                     [0.0, projection[1, 1] * height / 2.0, (1.0 + projection[1, 2]) * height / 2.0],
                     [0.0, 0.0, 1.0]])


def world_to_camera(position: np.ndarray, rotation: np.ndarray, convention: str) -> np.ndarray:
    """(4, 4) world -> camera of a camera at ``position`` turned by ``rotation`` (world ->
    view, OpenGL axes), in ``convention`` ("opengl" or "opencv")."""
    axes = rotation if convention == "opengl" else GL_TO_CV @ rotation
    matrix = np.eye(4)
    matrix[:3, :3] = axes
    matrix[:3, 3] = -axes @ position
    return matrix


def camera_record(camera, size: tuple, index: int, time: float) -> dict:
    """What cameras.json says of one frame: plain JSON values (see sinks/cameras.py)."""
    width, height = int(size[0]), int(size[1])
    record = {
        "index": int(index), "time": float(time), "width": width, "height": height,
        "projection": "orthographic" if camera.orthographic else "perspective",
        "near": float(camera.near), "far": float(camera.far),
        "world_to_camera": {convention: world_to_camera(camera.position, camera.rotation, convention).tolist()
                            for convention in ("opencv", "opengl")},
    }
    if camera.orthographic:
        record["orthographic_height"] = 2.0 / float(camera.projection[1, 1])
    else:
        record["K"] = intrinsic_matrix(camera.projection, size).tolist()
    return record
