"""4x4 transforms in float64, following the contract: M = T * Rz * Ry * Rx * S, angles in
degrees, right-handed, column vectors (p' = M p)."""
from __future__ import annotations

import math

import numpy as np


def scaling(factors) -> np.ndarray:
    """(4, 4) float64 scale; ``factors`` is a number or (3,)."""
    f = np.broadcast_to(np.asarray(factors, dtype=np.float64).reshape(-1), (3,))
    return np.diag([f[0], f[1], f[2], 1.0])


def rotation_x(degrees: float) -> np.ndarray:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]], dtype=np.float64)


def rotation_y(degrees: float) -> np.ndarray:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]], dtype=np.float64)


def rotation_z(degrees: float) -> np.ndarray:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]], dtype=np.float64)


def euler_rotation(degrees) -> np.ndarray:
    """(3, 3) float64: rotate about X, then Y, then Z (R = Rz Ry Rx)."""
    rx, ry, rz = (float(a) for a in degrees)
    return rotation_z(rz) @ rotation_y(ry) @ rotation_x(rx)


def model_matrix(position, rotation_degrees, scale) -> np.ndarray:
    """(4, 4) float64: T * Rz * Ry * Rx * S."""
    m = np.eye(4)
    m[:3, :3] = euler_rotation(rotation_degrees) @ scaling(scale)[:3, :3]
    m[:3, 3] = position
    return m


def model_matrices(positions, rotations_degrees, scales) -> np.ndarray:
    """Batched ``model_matrix``: positions (K, 3), rotations (K, 3) degrees, scales (K, 3)
    -> (K, 4, 4) float64."""
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    angles = np.radians(np.asarray(rotations_degrees, dtype=np.float64).reshape(-1, 3))
    scales = np.asarray(scales, dtype=np.float64).reshape(-1, 3)
    cx, cy, cz = np.cos(angles).T
    sx, sy, sz = np.sin(angles).T
    k = len(positions)
    r = np.empty((k, 3, 3))
    # Rz @ Ry @ Rx written out
    r[:, 0, 0] = cz * cy
    r[:, 0, 1] = cz * sy * sx - sz * cx
    r[:, 0, 2] = cz * sy * cx + sz * sx
    r[:, 1, 0] = sz * cy
    r[:, 1, 1] = sz * sy * sx + cz * cx
    r[:, 1, 2] = sz * sy * cx - cz * sx
    r[:, 2, 0] = -sy
    r[:, 2, 1] = cy * sx
    r[:, 2, 2] = cy * cx
    m = np.zeros((k, 4, 4))
    m[:, :3, :3] = r * scales[:, None, :]
    m[:, :3, 3] = positions
    m[:, 3, 3] = 1.0
    return m


def normal_matrices(models: np.ndarray) -> np.ndarray:
    """(K, 4, 4) -> (K, 3, 3) float64 matrices that transform normals.

    This is the inverse transpose of the upper 3x3, computed as the cofactor matrix times
    sign(det): the same directions (normals are renormalised in the shader) but defined
    even when a scale is zero, where the inverse does not exist.
    """
    a = models[..., :3, :3]
    cof = np.empty_like(a)
    cof[..., 0, :] = np.cross(a[..., 1, :], a[..., 2, :])
    cof[..., 1, :] = np.cross(a[..., 2, :], a[..., 0, :])
    cof[..., 2, :] = np.cross(a[..., 0, :], a[..., 1, :])
    det = np.linalg.det(a)
    sign = np.where(det < 0, -1.0, 1.0)
    return cof * sign[..., None, None]


def box_corners(bounds: np.ndarray) -> np.ndarray:
    """(2, 3) min/max -> (8, 3) corners."""
    lo, hi = bounds
    return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])


def union_bounds(boxes: list) -> np.ndarray | None:
    """(2, 3) min/max around (2, 3) boxes; None for no boxes."""
    if not boxes:
        return None
    stacked = np.stack(boxes)
    return np.stack([stacked[:, 0].min(axis=0), stacked[:, 1].max(axis=0)])


def transformed_bounds(bounds: np.ndarray, models: np.ndarray) -> np.ndarray:
    """World AABB (2, 3) of a local AABB (2, 3) placed by each of (K, 4, 4) matrices."""
    corners = box_corners(bounds)
    world = np.einsum("kij,nj->kni", models[:, :3, :3], corners) + models[:, None, :3, 3]
    world = world.reshape(-1, 3)
    return np.stack([world.min(axis=0), world.max(axis=0)])
