"""Built-in meshes: plane, box, sphere, cylinder, prism, cone.

All are centred at the origin with their axis along +Y. Triangles are counter-clockwise
seen from outside, normals are unit and point outward, and every mesh has UVs. The closed
ones are watertight: vertices are duplicated only where normals or UVs differ (seams,
cap rims, box edges) and the copies sit at bit-identical positions, so welding by
position leaves every edge shared by exactly two triangles.

Texture orientation: seen from outside with +Y up, u grows to the right and v upward.
"""
from __future__ import annotations

import inspect
import math
from numbers import Real

import numpy as np

from scenerender.mesh.data import MeshData


class _MeshBuilder:
    """Collects vertex blocks and triangles, then makes one MeshData."""

    def __init__(self) -> None:
        self._positions: list[np.ndarray] = []
        self._normals: list[np.ndarray] = []
        self._uvs: list[np.ndarray] = []
        self._triangles: list[np.ndarray] = []
        self._count = 0

    def add_vertices(self, positions, normals, uvs) -> int:
        """Append (K, 3) positions, (K, 3) normals and (K, 2) uvs; returns the first new index."""
        first = self._count
        positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
        self._positions.append(positions)
        normals = np.asarray(normals, dtype=np.float64)
        self._normals.append(np.broadcast_to(normals, positions.shape))
        self._uvs.append(np.asarray(uvs, dtype=np.float64).reshape(-1, 2))
        self._count += len(positions)
        return first

    def add_triangles(self, triangles) -> None:
        """Append (K, 3) absolute vertex indices."""
        self._triangles.append(np.asarray(triangles, dtype=np.int64).reshape(-1, 3))

    def build(self, source: str) -> MeshData:
        normals = np.concatenate(self._normals)
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        return MeshData(
            positions=np.concatenate(self._positions).astype(np.float32),
            normals=normals.astype(np.float32),
            uvs=np.concatenate(self._uvs).astype(np.float32),
            indices=np.concatenate(self._triangles).astype(np.uint32),
            source=source,
        )


# ---------------------------------------------------------------------------------------
# Parameter checks. The scene schema catches most mistakes earlier; these keep direct
# callers honest and give the same kind of message.


def _is_number(value) -> bool:
    return isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(value)


def _positive(name: str, value) -> float:
    if not _is_number(value) or value <= 0:
        raise ValueError(f"{name} must be a finite number greater than 0, got {value!r}")
    return float(value)


def _count(name: str, value, minimum: int) -> int:
    if not _is_number(value) or value != int(value) or value < minimum:
        raise ValueError(f"{name} must be a whole number of at least {minimum}, got {value!r}")
    return int(value)


def _per_axis(name: str, value, axes: int) -> np.ndarray:
    """A number (the same on every axis) or a list of ``axes`` numbers, each > 0."""
    if isinstance(value, (list, tuple, np.ndarray)):
        if len(value) != axes:
            raise ValueError(
                f"{name} must be a number or a list of {axes} numbers, got {list(value)!r}"
            )
        return np.array([_positive(name, v) for v in value])
    return np.full(axes, _positive(name, value))


# ---------------------------------------------------------------------------------------
# Shared pieces.


def _circle(count: int) -> np.ndarray:
    """(count + 1, 2) float64: (sin, cos) of 2*pi*j/count for j = 0..count.

    Row ``count`` repeats row 0 exactly (the UV seam), rather than sin(2*pi), which is
    not exactly 0 and would leave a crack when welding.
    """
    angles = 2.0 * np.pi * np.arange(count) / count
    ring = np.stack([np.sin(angles), np.cos(angles)], axis=1)
    return np.concatenate([ring, ring[:1]])


def _add_cap(
    builder: _MeshBuilder, ring: np.ndarray, radius: float, y: float, facing_up: bool
) -> None:
    """A flat disc at height ``y`` closing the ring of points ``radius * ring`` (count + 1, 2).

    UVs map the disc onto [0, 1]^2 the way it looks from outside.
    """
    count = len(ring) - 1
    sin_cos = ring[:count]
    rim = np.column_stack([radius * sin_cos[:, 0], np.full(count, y), radius * sin_cos[:, 1]])
    positions = np.vstack([[0.0, y, 0.0], rim])
    # Seen from above, v grows toward -Z; seen from below, toward +Z.
    v_sign = -1.0 if facing_up else 1.0
    uvs = 0.5 + 0.5 * np.column_stack([positions[:, 0], v_sign * positions[:, 2]]) / radius
    normal = [0.0, 1.0 if facing_up else -1.0, 0.0]
    center = builder.add_vertices(positions, normal, uvs)
    j = np.arange(count)
    current, following = center + 1 + j, center + 1 + (j + 1) % count
    centers = np.full(count, center)
    if facing_up:
        builder.add_triangles(np.column_stack([centers, current, following]))
    else:
        builder.add_triangles(np.column_stack([centers, following, current]))


def _quad_strip(top: np.ndarray, bottom: np.ndarray) -> np.ndarray:
    """(2K, 3) triangles between two rows of K + 1 vertex indices, top row above.

    Seen from outside the rows run left to right, so (top_j, bottom_j, bottom_j+1) is
    counter-clockwise.
    """
    a, b, c, d = top[:-1], bottom[:-1], bottom[1:], top[1:]
    return np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])


# ---------------------------------------------------------------------------------------
# The primitives.


def plane(size=1.0, uv_repeat=1.0) -> MeshData:
    """A square in the XZ plane facing +Y: two triangles, four vertices.

    size: a number or [x, z]. uv_repeat: a number or [u, v]; UVs span [0, uv_repeat],
    u along +X and v along -Z (an image reads upright seen from above with -Z ahead).
    """
    half_x, half_z = _per_axis("size", size, 2) / 2.0
    repeat_u, repeat_v = _per_axis("uv_repeat", uv_repeat, 2)
    builder = _MeshBuilder()
    builder.add_vertices(
        [[-half_x, 0, half_z], [half_x, 0, half_z], [half_x, 0, -half_z], [-half_x, 0, -half_z]],
        [0.0, 1.0, 0.0],
        [[0, 0], [repeat_u, 0], [repeat_u, repeat_v], [0, repeat_v]],
    )
    builder.add_triangles([[0, 1, 2], [0, 2, 3]])
    return builder.build("primitive plane")


# Each box face: outward normal, then the directions that are right and up on it seen
# from outside (right x up = normal).
_BOX_FACES = (
    ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
    ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
    ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
    ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
    ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
)


def box(size=1.0) -> MeshData:
    """An axis-aligned box spanning -size/2..size/2: 12 triangles, 24 vertices (4 per face,
    each face with its own normal and the full [0, 1] UV square).

    size: a number or [x, y, z].
    """
    half = _per_axis("size", size, 3) / 2.0
    builder = _MeshBuilder()
    corner_signs = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=np.float64)
    for normal, right, up in _BOX_FACES:
        n, r, u = (np.array(axis, dtype=np.float64) for axis in (normal, right, up))
        positions = (n + corner_signs[:, :1] * r + corner_signs[:, 1:] * u) * half
        first = builder.add_vertices(positions, n, (corner_signs + 1.0) / 2.0)
        builder.add_triangles(first + np.array([[0, 1, 2], [0, 2, 3]]))
    return builder.build("primitive box")


def sphere(radius=0.5, segments=32, rings=16) -> MeshData:
    """A UV sphere: ``segments`` slices around +Y, ``rings`` bands from pole to pole.

    2 * segments * (rings - 1) triangles. UVs are longitude (u, 0 at +Z, growing toward
    +X) and latitude (v, 0 at the south pole, 1 at the north). Each pole has one vertex
    per slice so every pole triangle gets its own u.
    """
    radius = _positive("radius", radius)
    segments = _count("segments", segments, 3)
    rings = _count("rings", rings, 2)
    ring = _circle(segments)
    u = np.arange(segments + 1) / segments
    builder = _MeshBuilder()

    def add_pole(y: float, v: float) -> np.ndarray:
        count = segments
        first = builder.add_vertices(
            np.tile([0.0, y, 0.0], (count, 1)),
            [0.0, y, 0.0],
            np.column_stack([(np.arange(count) + 0.5) / count, np.full(count, v)]),
        )
        return first + np.arange(count)

    north = add_pole(radius, 1.0)
    rows = []
    for i in range(1, rings):
        theta = np.pi * i / rings
        across, height = np.sin(theta), np.cos(theta)
        unit = np.column_stack(
            [across * ring[:, 0], np.full(segments + 1, height), across * ring[:, 1]]
        )
        uvs = np.column_stack([u, np.full(segments + 1, 1.0 - i / rings)])
        first = builder.add_vertices(radius * unit, unit, uvs)
        rows.append(first + np.arange(segments + 1))
    south = add_pole(-radius, 0.0)

    builder.add_triangles(np.column_stack([north, rows[0][:-1], rows[0][1:]]))
    for upper, lower in zip(rows, rows[1:]):
        builder.add_triangles(_quad_strip(upper, lower))
    builder.add_triangles(np.column_stack([rows[-1][:-1], south, rows[-1][1:]]))
    return builder.build("primitive sphere")


def _side_rows(builder: _MeshBuilder, ring, radius, half_height, normals, u):
    """Add the top and bottom rows of a vertical wall through the points ``radius * ring``
    ((K, 2) sin/cos pairs) and return their vertex indices, two (K,) arrays."""
    count = len(ring)
    rows = []
    for y, v in ((half_height, 1.0), (-half_height, 0.0)):
        positions = np.column_stack([radius * ring[:, 0], np.full(count, y), radius * ring[:, 1]])
        first = builder.add_vertices(positions, normals, np.column_stack([u, np.full(count, v)]))
        rows.append(first + np.arange(count))
    return rows[0], rows[1]


def cylinder(radius=0.5, height=1.0, segments=32) -> MeshData:
    """A capped cylinder with smooth (radial) side normals: 4 * segments triangles.

    Side UVs wrap u once around (0 at +Z); caps map the disc onto [0, 1]^2.
    """
    radius = _positive("radius", radius)
    height = _positive("height", height)
    segments = _count("segments", segments, 3)
    ring = _circle(segments)
    builder = _MeshBuilder()
    radial = np.column_stack([ring[:, 0], np.zeros(segments + 1), ring[:, 1]])
    u = np.arange(segments + 1) / segments
    top, bottom = _side_rows(builder, ring, radius, height / 2.0, radial, u)
    builder.add_triangles(_quad_strip(top, bottom))
    _add_cap(builder, ring, radius, height / 2.0, facing_up=True)
    _add_cap(builder, ring, radius, -height / 2.0, facing_up=False)
    return builder.build("primitive cylinder")


def prism(radius=0.5, height=1.0, sides=6) -> MeshData:
    """A capped regular prism with flat sides: 4 * sides triangles.

    ``radius`` is the circumradius (corners lie on the circle); the first corner is at
    +Z. Each side has its own four vertices and normal; u runs around once.
    """
    radius = _positive("radius", radius)
    height = _positive("height", height)
    sides = _count("sides", sides, 3)
    ring = _circle(sides)
    builder = _MeshBuilder()
    for j in range(sides):
        middle = 2.0 * np.pi * (j + 0.5) / sides  # a flat side faces its middle direction
        normal = [np.sin(middle), 0.0, np.cos(middle)]
        u = np.array([j, j + 1]) / sides
        top, bottom = _side_rows(builder, ring[j : j + 2], radius, height / 2.0, normal, u)
        builder.add_triangles(_quad_strip(top, bottom))
    _add_cap(builder, ring, radius, height / 2.0, facing_up=True)
    _add_cap(builder, ring, radius, -height / 2.0, facing_up=False)
    return builder.build("primitive prism")


def cone(radius=0.5, height=1.0, segments=32) -> MeshData:
    """A cone with its base at y = -height/2 and apex at +height/2: 2 * segments triangles.

    Side normals are smooth and tilted up by the slope: at angle phi they point along
    (height sin phi, radius, height cos phi). The apex has one vertex per segment, each
    with the normal of its segment's middle, so no normal is ever averaged to zero.
    """
    radius = _positive("radius", radius)
    height = _positive("height", height)
    segments = _count("segments", segments, 3)
    ring = _circle(segments)
    half = height / 2.0
    builder = _MeshBuilder()

    def slope_normals(sin_cos: np.ndarray) -> np.ndarray:
        heights = np.full(len(sin_cos), radius)
        return np.column_stack([height * sin_cos[:, 0], heights, height * sin_cos[:, 1]])

    u = np.arange(segments + 1) / segments
    base_positions = np.column_stack(
        [radius * ring[:, 0], np.full(segments + 1, -half), radius * ring[:, 1]]
    )
    base_uvs = np.column_stack([u, np.zeros(segments + 1)])
    base = builder.add_vertices(base_positions, slope_normals(ring), base_uvs)
    middles = 2.0 * np.pi * (np.arange(segments) + 0.5) / segments
    apex = builder.add_vertices(
        np.tile([0.0, half, 0.0], (segments, 1)),
        slope_normals(np.column_stack([np.sin(middles), np.cos(middles)])),
        np.column_stack([(np.arange(segments) + 0.5) / segments, np.ones(segments)]),
    )
    j = np.arange(segments)
    builder.add_triangles(np.column_stack([apex + j, base + j, base + j + 1]))
    _add_cap(builder, ring, radius, -half, facing_up=False)
    return builder.build("primitive cone")


PRIMITIVES = {
    "plane": plane,
    "box": box,
    "sphere": sphere,
    "cylinder": cylinder,
    "prism": prism,
    "cone": cone,
}


def make_primitive(kind: str, **params) -> MeshData:
    """Build the primitive ``kind`` (a key of PRIMITIVES) from its parameters; omitted
    parameters take the function's defaults.

    Raises ValueError for an unknown kind, an unknown parameter or an invalid value.
    """
    function = PRIMITIVES.get(kind)
    if function is None:
        raise ValueError(f"unknown primitive {kind!r}; choose one of {', '.join(PRIMITIVES)}")
    accepted = list(inspect.signature(function).parameters)
    unknown = sorted(set(params) - set(accepted))
    if unknown:
        raise ValueError(
            f"primitive {kind} has no parameter {', '.join(repr(p) for p in unknown)}; "
            f"it takes {', '.join(accepted)}"
        )
    return function(**params)
