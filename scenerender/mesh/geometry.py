"""Pure array functions on meshes: normals, flat shading, normalisation, tangent frames.

Everything here is NumPy only and never returns NaN: degenerate triangles and vertices
without a usable direction get a finite fallback instead.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from scenerender.mesh.data import MeshData

NORMAL_MODES = ("auto", "smooth", "flat")

# Used where no direction can be derived (isolated vertices, zero-area fans).
FALLBACK_NORMAL = np.array([0.0, 1.0, 0.0])

# Below this squared length a vector counts as zero.
_TINY = 1e-30


def face_normals_unnormalized(positions: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """Cross products of the triangle edges: direction of the face normal, length twice
    the triangle's area.

    positions: (N, 3) float; indices: (M, 3) integer. Returns (M, 3) float64.
    """
    p = np.asarray(positions, dtype=np.float64)
    tri = np.asarray(indices, dtype=np.int64)
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    return np.cross(b - a, c - a)


def unit_or_fallback(vectors: np.ndarray, fallback: np.ndarray = FALLBACK_NORMAL) -> np.ndarray:
    """Normalise rows; rows that are zero or not finite become ``fallback``.

    vectors: (K, 3) float. Returns (K, 3) float64.
    """
    v = np.asarray(vectors, dtype=np.float64)
    finite = np.isfinite(v).all(axis=1)
    v = np.where(finite[:, None], v, 0.0)
    length_sq = np.einsum("ij,ij->i", v, v)
    usable = length_sq > _TINY
    out = np.empty_like(v)
    out[usable] = v[usable] / np.sqrt(length_sq[usable])[:, None]
    out[~usable] = fallback
    return out


def position_ids(positions: np.ndarray) -> np.ndarray:
    """(N,) int64: the same id for vertices at exactly the same position.

    Vertices are often duplicated along UV seams or material borders; giving such copies
    one id lets normals be shared across the seam.
    """
    p = np.ascontiguousarray(np.asarray(positions, dtype=np.float64) + 0.0)  # -0.0 -> 0.0
    if len(p) == 0:
        return np.zeros(0, dtype=np.int64)
    rows = p.view(np.dtype((np.void, p.dtype.itemsize * 3))).reshape(-1)
    _, ids = np.unique(rows, return_inverse=True)
    return ids.reshape(-1).astype(np.int64)


def smooth_normals(positions: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals, shared by all vertices at the same position.

    positions: (N, 3) float; indices: (M, 3) integer.
    Returns (N, 3) float32 unit vectors. A zero-area triangle adds nothing; a vertex that
    ends up with no direction (unused, or only in degenerate triangles) gets +Y.
    """
    count = len(positions)
    if count == 0:
        return np.zeros((0, 3), dtype=np.float32)
    ids = position_ids(positions)
    # The cross product's length is twice the area, which gives the area weighting.
    weighted = face_normals_unnormalized(positions, indices)
    corner_ids = ids[np.asarray(indices, dtype=np.int64).reshape(-1)]
    per_corner = np.repeat(weighted, 3, axis=0)
    summed = _sum_per_vertex(corner_ids, per_corner, int(ids.max()) + 1)
    return unit_or_fallback(summed[ids]).astype(np.float32)


def flat_shaded(mesh: MeshData) -> MeshData:
    """Unweld so every triangle has three vertices of its own carrying the face normal.

    The result has 3 * M vertices; indices become 0..3M-1 in order, so triangle ranges
    (groups) stay valid. Degenerate triangles get +Y.
    """
    corners = np.asarray(mesh.indices, dtype=np.int64).reshape(-1)
    normals = unit_or_fallback(face_normals_unnormalized(mesh.positions, mesh.indices))
    return replace(
        mesh,
        positions=mesh.positions[corners].astype(np.float32),
        normals=np.repeat(normals, 3, axis=0).astype(np.float32),
        uvs=None if mesh.uvs is None else mesh.uvs[corners].astype(np.float32),
        colors=None if mesh.colors is None else mesh.colors[corners].astype(np.float32),
        tangents=None if mesh.tangents is None else mesh.tangents[corners].astype(np.float32),
        uvs1=None if mesh.uvs1 is None else mesh.uvs1[corners].astype(np.float32),
        indices=np.arange(len(corners), dtype=np.uint32).reshape(-1, 3),
        groups=list(mesh.groups),
    )


def apply_normals_mode(mesh: MeshData, mode: str) -> MeshData:
    """Return a mesh whose normals follow ``mode``.

    auto:   the mesh's own normals (made unit; unusable ones are replaced by smooth
            normals) when it has them (``normals`` is not None), else smooth.
    smooth: smooth_normals, ignoring any normals the mesh has.
    flat:   flat_shaded.
    """
    if mode not in NORMAL_MODES:
        raise ValueError(f"normals mode must be one of {', '.join(NORMAL_MODES)}, not {mode!r}")
    if mode == "flat":
        return flat_shaded(mesh)
    if mode == "auto" and mesh.normals is not None and len(mesh.normals) == len(mesh.positions):
        return replace(mesh, normals=_repaired_normals(mesh))
    return replace(mesh, normals=smooth_normals(mesh.positions, mesh.indices))


def _repaired_normals(mesh: MeshData) -> np.ndarray:
    """The mesh's normals made unit; zero or non-finite ones become smooth normals."""
    repaired = unit_or_fallback(mesh.normals, fallback=np.full(3, np.nan))
    unusable = np.isnan(repaired[:, 0])
    if unusable.any():
        repaired[unusable] = smooth_normals(mesh.positions, mesh.indices)[unusable]
    return repaired.astype(np.float32)


def normalize_unit(mesh: MeshData) -> MeshData:
    """Center the bounding box at the origin and scale the box diagonal to 1.

    A mesh whose box has no extent (one point, or empty) is only centred. Normals are
    unchanged because the scale is uniform.
    """
    if mesh.vertex_count == 0:
        return replace(mesh)
    low, high = mesh.bounds()
    center = (low + high) / 2.0
    diagonal = float(np.linalg.norm(high - low))
    scale = 1.0 / diagonal if diagonal > 1e-12 else 1.0
    positions = (mesh.positions.astype(np.float64) - center) * scale
    return replace(mesh, positions=positions.astype(np.float32))


def any_perpendicular(normals: np.ndarray) -> np.ndarray:
    """(K, 3) float64 unit vectors perpendicular to the given unit ``normals`` (K, 3).

    Crosses each normal with the coordinate axis it is least aligned with, so the
    result is never close to zero.
    """
    n = np.asarray(normals, dtype=np.float64)
    axis = np.zeros_like(n)
    axis[np.arange(len(n)), np.argmin(np.abs(n), axis=1)] = 1.0
    return unit_or_fallback(np.cross(n, axis), fallback=np.array([1.0, 0.0, 0.0]))


def tangents(mesh: MeshData) -> np.ndarray:
    """Per-vertex tangent frames for tangent-space normal maps.

    Returns (N, 4) float32: xyz is a unit tangent (the direction of increasing u)
    orthogonal to the vertex normal; w = +1 or -1 is the handedness, so the bitangent
    (direction of increasing v) is ``w * cross(normal, tangent)``.

    Triangles contribute weighted by their UV-space orientation only (a triangle whose
    UVs have no area contributes nothing). Vertices left without a tangent, and meshes
    without UVs, get an arbitrary unit vector perpendicular to the normal and w = +1.
    Tangents the file stores (``mesh.tangents``, glTF's TANGENT) are used instead, made
    orthogonal to the normal, their handedness kept.
    """
    count = mesh.vertex_count
    if mesh.normals is not None:
        normals = unit_or_fallback(mesh.normals)
    else:
        normals = np.tile(FALLBACK_NORMAL, (count, 1))
    tangent_sum = np.zeros((count, 3))
    bitangent_sum = np.zeros((count, 3))
    if mesh.tangents is not None:
        stored = np.asarray(mesh.tangents, dtype=np.float64)
        tangent_sum = stored[:, :3]
        bitangent_sum = np.cross(normals, tangent_sum) * np.where(stored[:, 3:] < 0.0, -1.0, 1.0)
    elif mesh.uvs is not None and mesh.triangle_count:
        tangent_sum, bitangent_sum = _accumulated_uv_directions(mesh)

    # Gram-Schmidt: remove the normal component so the frame is orthogonal.
    t = tangent_sum - normals * np.einsum("ij,ij->i", tangent_sum, normals)[:, None]
    length_sq = np.einsum("ij,ij->i", t, t)
    usable = length_sq > 1e-20
    result = np.empty((count, 4), dtype=np.float64)
    result[usable, :3] = t[usable] / np.sqrt(length_sq[usable])[:, None]
    result[~usable, :3] = any_perpendicular(normals[~usable])
    handedness = np.einsum("ij,ij->i", np.cross(normals, result[:, :3]), bitangent_sum)
    result[:, 3] = np.where(handedness < 0.0, -1.0, 1.0)
    return result.astype(np.float32)


def _accumulated_uv_directions(mesh: MeshData) -> tuple[np.ndarray, np.ndarray]:
    """Sum, per vertex, the object-space directions of increasing u and v of its triangles.

    Solving [e1 e2] = [T B] [duv1 duv2] gives T and B divided by the UV determinant r.
    Multiplying by sign(r) instead of dividing by r keeps the direction without blowing up
    on near-degenerate UVs, and r == 0 makes the contribution vanish.
    """
    tri = np.asarray(mesh.indices, dtype=np.int64)
    p = np.asarray(mesh.positions, dtype=np.float64)
    uv = np.asarray(mesh.uvs, dtype=np.float64)
    e1 = p[tri[:, 1]] - p[tri[:, 0]]
    e2 = p[tri[:, 2]] - p[tri[:, 0]]
    d1 = uv[tri[:, 1]] - uv[tri[:, 0]]
    d2 = uv[tri[:, 2]] - uv[tri[:, 0]]
    r = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    sign = np.sign(r)[:, None]
    face_t = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) * sign
    face_b = (e2 * d1[:, 0:1] - e1 * d2[:, 0:1]) * sign
    count = mesh.vertex_count
    corners = tri.reshape(-1)
    sums = []
    for face_vectors in (face_t, face_b):
        per_corner = np.repeat(face_vectors, 3, axis=0)
        sums.append(_sum_per_vertex(corners, per_corner, count))
    return sums[0], sums[1]


def _sum_per_vertex(vertex_of_row: np.ndarray, rows: np.ndarray, count: int) -> np.ndarray:
    """(count, 3) float64: rows (K, 3) added up by vertex_of_row (K,) int.

    np.bincount per column is several times faster than np.add.at.
    """
    return np.stack(
        [np.bincount(vertex_of_row, weights=rows[:, k], minlength=count) for k in range(3)],
        axis=1,
    )
