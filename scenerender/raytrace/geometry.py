"""A frame's geometry as one triangle soup, camera-relative, in float64.

Like the GPU path (scenerender/world/frame.py), world matrices are composed in float64 and
the camera position is subtracted before anything is rounded, so the ray engine's float32
arithmetic sees small numbers wherever the scene sits.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenerender.mesh.geometry import tangents
from scenerender.world.transforms import normal_matrices


@dataclass
class Soup:
    """Every visible triangle of a frame.

    corners:  (T, 3, 3) float64 camera-relative positions, corner-major.
    normals:  (T, 3, 3) float64 world-space vertex normals (not renormalised).
    uvs:      (T, 3, 4) float64 texture coordinates: set 0 (zero where the mesh has none),
              then set 1 (glTF TEXCOORD_1; set 0 again where the mesh has none).
    colors:   (T, 3, 4) float64 vertex colours (white where the mesh has none).
    material: (T,) int32 index into ``materials`` (the frame's material values).
    object:   (T,) int32 index of the scene object.
    casts:    (T,) bool, the object casts shadows.
    materials: list of material value dicts (see world.frame._material_values) and
               their Material objects: [(Material, values), ...].
    """

    corners: np.ndarray
    normals: np.ndarray
    uvs: np.ndarray
    colors: np.ndarray
    material: np.ndarray
    object: np.ndarray
    casts: np.ndarray
    materials: list
    # (T, 3, 4) float64 world-space tangent frames (xyz, handedness w) of the objects with an
    # anisotropic material or a coat's normal map (mesh.geometry.tangents; (1, 0, 0, 1)
    # elsewhere), or None where no object has one
    tangents: np.ndarray | None = None

    @property
    def count(self) -> int:
        return len(self.corners)


def frame_soup(world, frame) -> Soup:
    """The Soup of ``frame`` (a FrameState of ``world``)."""
    parts = []
    materials: list = []
    frames: list = []
    index_of: dict = {}
    camera_position = frame.camera.position
    for object_index, (obj, state) in enumerate(zip(world.objects, frame.objects)):
        if not state.visible or obj.mesh.triangle_count == 0:
            continue
        matrices = obj.matrices(frame.time)
        group_material = []
        for material in obj.materials:
            if id(material) not in index_of:
                index_of[id(material)] = len(materials)
                materials.append((material, frame.materials[id(material)]))
            group_material.append(index_of[id(material)])
        parts.append(_object_triangles(obj.mesh, matrices, camera_position, group_material, object_index,
                                       obj.cast_shadows))
        frames.append(_object_tangents(obj, matrices))
    if not parts:
        empty = np.zeros((0, 3, 3))
        return Soup(empty, empty, np.zeros((0, 3, 4)), np.zeros((0, 3, 4)), np.zeros(0, np.int32),
                    np.zeros(0, np.int32), np.zeros(0, bool), materials)
    tangents = None
    if any(frame is not None for frame in frames):
        tangents = np.concatenate([frame if frame is not None else np.tile(_NO_TANGENT, (len(part[0]), 3, 1))
                                   for frame, part in zip(frames, parts)])
    return Soup(*(np.concatenate([p[k] for p in parts]) for k in range(7)), materials, tangents)


_NO_TANGENT = np.array([1.0, 0.0, 0.0, 1.0])


def _object_tangents(obj, matrices: np.ndarray) -> np.ndarray | None:
    """(T, 3, 4) the object's tangent frames at its triangles' corners, every instance,
    turned by each instance's matrix as the GPU's vertex stage turns them, where a material
    of it is anisotropic or has a coat's normal map (its geometry's tangents); None elsewhere."""
    mesh = obj.mesh
    if not any(material.anisotropy > 0.0 or "clearcoat_normal_map" in material.maps for material in obj.materials):
        return None
    frames = tangents(mesh).astype(np.float64)[mesh.indices]
    return np.concatenate([np.concatenate([frames[..., :3] @ model[:3, :3].T, frames[..., 3:]], axis=-1)
                           for model in matrices])


def _object_triangles(mesh, matrices: np.ndarray, camera_position: np.ndarray, group_material: list,
                      object_index: int, casts: bool):
    """(corners, normals, uvs, colors, material, object, casts) of every instance of one mesh."""
    positions = mesh.positions.astype(np.float64)[mesh.indices]   # (M, 3, 3) object space
    vertex_normals = mesh.normals.astype(np.float64)[mesh.indices]
    if mesh.uvs is not None:
        uvs = mesh.uvs.astype(np.float64)[mesh.indices]
    else:
        uvs = np.zeros((len(mesh.indices), 3, 2))
    uvs = np.concatenate([uvs, mesh.uvs1.astype(np.float64)[mesh.indices] if mesh.uvs1 is not None else uvs], axis=2)
    if mesh.colors is not None:
        colors = mesh.colors.astype(np.float64)[mesh.indices]
    else:
        colors = np.ones((len(mesh.indices), 3, 4))
    per_triangle = np.zeros(len(mesh.indices), np.int32)
    for group, material in zip(mesh.groups, group_material):
        per_triangle[group.first:group.first + group.count] = material
    normal_3x3 = normal_matrices(matrices)
    corners, normals = [], []
    for model, normal_matrix in zip(matrices, normal_3x3):
        linear, offset = model[:3, :3], model[:3, 3] - camera_position
        corners.append(positions @ linear.T + offset)
        normals.append(vertex_normals @ normal_matrix.T)
    count = len(matrices)
    return (np.concatenate(corners), np.concatenate(normals), np.tile(uvs, (count, 1, 1)),
            np.tile(colors, (count, 1, 1)), np.tile(per_triangle, count),
            np.full(len(per_triangle) * count, object_index, np.int32),
            np.full(len(per_triangle) * count, casts, bool))
