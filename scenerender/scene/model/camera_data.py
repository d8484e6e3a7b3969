"""The camera keys a data set needs: ``camera.intrinsics`` (a pinhole's focal lengths and
principal point in pixels, OpenCV's convention) and ``camera.pose`` (a 4 x 4 matrix in a
named axis convention). See docs/scene-notes.md, "Intrinsics, poses and cameras.json"."""
from __future__ import annotations

import numpy as np
from pydantic import model_validator
from pydantic_core import PydanticCustomError

from scenerender.scene.describe import describe
from scenerender.scene.strict import StrictModel
from scenerender.scene.values import animated, choice, number, vector_item

# How far a pose's 3 x 3 part may be from orthonormal (the largest entry of |R^T R - I|):
# the rounding of a matrix printed with 7 significant digits lies well inside.
ROTATION_TOLERANCE = 1e-5

Pixels = number(0, lo_open=True)


class IntrinsicsSpec(StrictModel):
    """A pinhole in pixels: x right, y down, measured from the top-left corner of the image
    (pixel centres at +0.5)."""

    fx: Pixels
    fy: Pixels
    cx: number()
    cy: number()


def _validate_matrix(value):
    """A 4 x 4 matrix written as 4 rows of 4 numbers -> a tuple of row tuples."""
    if not isinstance(value, (list, tuple)) or len(value) != 4:
        raise PydanticCustomError("matrix", "expected 4 rows of 4 numbers, got {got}", {"got": describe(value)})
    rows = []
    for r, row in enumerate(value):
        if not isinstance(row, (list, tuple)) or len(row) != 4:
            raise PydanticCustomError("matrix", "row {r}: expected 4 numbers, got {got}",
                                      {"r": r, "got": describe(row)})
        rows.append(tuple(vector_item(v, i, None, None) for i, v in enumerate(row)))
    return tuple(rows)


def _validate_rigid(value):
    """A rigid 4 x 4 matrix (rows) -> its 16 numbers, rows first (a track's key value)."""
    rows = _validate_matrix(value)
    problem = rigid_problem(np.array(rows, dtype=np.float64))
    if problem:
        raise PydanticCustomError("camera_pose", "{problem}", {"problem": problem})
    return tuple(v for row in rows for v in row)


_MATRIX_SCHEMA = {"type": "array", "minItems": 4, "maxItems": 4,
                  "items": {"type": "array", "items": {"type": "number"}, "minItems": 4, "maxItems": 4}}
# A matrix, or keys of matrices: interpolated number by number with the track's
# interpolation, then the nearest rotation taken (world.camera_data.pose_placement).
AnimatedMatrix4 = animated(_validate_rigid, _MATRIX_SCHEMA, "vector")


class PoseSpec(StrictModel):
    """Where the camera is and how it turns, as one rigid matrix (or keys of them):
    ``camera_to_world`` or ``world_to_camera``, with the camera's axes in ``convention``."""

    camera_to_world: AnimatedMatrix4 | None = None
    world_to_camera: AnimatedMatrix4 | None = None
    convention: choice("opencv", "opengl") = "opencv"

    @model_validator(mode="after")
    def _check(self):
        given = [key for key in ("camera_to_world", "world_to_camera") if getattr(self, key) is not None]
        if len(given) != 1:
            raise PydanticCustomError("camera_pose", "give one of camera_to_world or world_to_camera"
                                      + (", not both" if given else ""), {"subpath": tuple(given[1:])})
        return self

    def camera_to_world_matrix(self, t: float = 0.0) -> np.ndarray:
        """(4, 4) float64 camera -> world at time ``t``, the camera's axes in ``convention``
        (between keys not yet rigid: see pose_placement)."""
        if self.camera_to_world is not None:
            return np.asarray(self.camera_to_world(t), dtype=np.float64).reshape(4, 4)
        return rigid_inverse(np.asarray(self.world_to_camera(t), dtype=np.float64).reshape(4, 4))


def rigid_problem(matrix: np.ndarray) -> str | None:
    """Why ``matrix`` (4, 4) is not a rotation and a translation, or None."""
    if not np.allclose(matrix[3], (0.0, 0.0, 0.0, 1.0), rtol=0.0, atol=1e-12):
        return f"the last row must be [0, 0, 0, 1], got {_row_text(matrix[3])}"
    rotation = matrix[:3, :3]
    if np.abs(rotation.T @ rotation - np.eye(3)).max() > ROTATION_TOLERANCE:
        return ("the upper-left 3 x 3 must be a rotation (orthonormal columns, no scale or shear); "
                f"its column lengths are {_row_text(np.linalg.norm(rotation, axis=0))}")
    if np.linalg.det(rotation) < 0.0:
        return "the upper-left 3 x 3 is a reflection (determinant -1), not a rotation; flip one axis"
    return None


def rigid_inverse(matrix: np.ndarray) -> np.ndarray:
    """The inverse of a rotation-and-translation (4, 4): [R^T | -R^T t]."""
    inverse = np.eye(4)
    inverse[:3, :3] = matrix[:3, :3].T
    inverse[:3, 3] = -matrix[:3, :3].T @ matrix[:3, 3]
    return inverse


def _row_text(values) -> str:
    return "[" + ", ".join(f"{float(v):.6g}" for v in values) + "]"


def check_dataset_camera(camera) -> None:
    """The combinations ``intrinsics`` and ``pose`` rule out (a CameraSpec's validator)."""
    if camera.intrinsics is not None:
        if "fov" in camera.model_fields_set:
            raise PydanticCustomError("camera_lens", "give either fov or intrinsics, not both (intrinsics set the "
                                      "field of view)", {"subpath": ("fov",)})
        if camera.projection == "orthographic":
            raise PydanticCustomError("camera_lens", "intrinsics describe a perspective (pinhole) camera; "
                                      "remove them or projection: orthographic", {"subpath": ("intrinsics",)})
    if camera.pose is not None:
        aims = [key for key in ("position", "target", "yaw", "pitch") if getattr(camera, key) is not None]
        if aims:
            raise PydanticCustomError("camera_aim", "give either pose or {key}, not both (the pose places and "
                                      "turns the camera)", {"key": aims[0], "subpath": (aims[0],)})
        if "up" in camera.model_fields_set:
            raise PydanticCustomError("camera_aim", "up has no effect with a pose (the matrix turns the camera); "
                                      "remove it", {"subpath": ("up",)})

