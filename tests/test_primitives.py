"""Built-in primitives (scenerender.mesh.primitives)."""
from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from scenerender.mesh import PRIMITIVES, make_primitive
from scenerender.mesh.primitives import box, cone, cylinder, plane, prism, sphere

CLOSED_CASES = [
    ("box", {}),
    ("box", {"size": [1, 2, 3]}),
    ("sphere", {}),
    ("sphere", {"radius": 2, "segments": 3, "rings": 2}),
    ("sphere", {"radius": 1, "segments": 7, "rings": 5}),
    ("cylinder", {}),
    ("cylinder", {"radius": 0.25, "height": 3, "segments": 3}),
    ("prism", {}),
    ("prism", {"radius": 1, "height": 0.5, "sides": 3}),
    ("cone", {}),
    ("cone", {"radius": 2, "height": 0.5, "segments": 5}),
]


def welded_triangles(mesh) -> np.ndarray:
    """(M, 3) triangles re-indexed so vertices at the same position share one index."""
    _, ids = np.unique(mesh.positions, axis=0, return_inverse=True)
    return ids.reshape(-1)[mesh.indices.astype(np.int64)]


def signed_volume(mesh) -> float:
    tri = mesh.positions[mesh.indices.astype(np.int64)].astype(np.float64)
    return float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0)


def face_normals(mesh) -> np.ndarray:
    tri = mesh.positions[mesh.indices.astype(np.int64)].astype(np.float64)
    return np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])


@pytest.mark.parametrize("kind, params", CLOSED_CASES)
def test_closed_primitives_are_watertight(kind, params):
    triangles = welded_triangles(make_primitive(kind, **params))
    directed = Counter()
    for a, b, c in triangles:
        directed.update([(a, b), (b, c), (c, a)])
    undirected = Counter()
    for (a, b), n in directed.items():
        undirected[(min(a, b), max(a, b))] += n
    assert set(undirected.values()) == {2}, "every edge must be shared by exactly two triangles"
    # Consistent orientation: each edge is used once in each direction.
    assert set(directed.values()) == {1}


@pytest.mark.parametrize("kind, params", CLOSED_CASES)
def test_closed_primitives_wind_outward(kind, params):
    mesh = make_primitive(kind, **params)
    assert signed_volume(mesh) > 0
    # Every triangle's winding agrees with the normals stored on its corners.
    per_face = face_normals(mesh)
    corner_normals = mesh.normals[mesh.indices.astype(np.int64)].astype(np.float64)
    agreement = np.einsum("ij,ikj->ik", per_face, corner_normals)
    assert (agreement > 0).all()


@pytest.mark.parametrize("kind, params", CLOSED_CASES + [("plane", {}), ("plane", {"size": [2, 5], "uv_repeat": 3})])
def test_attributes_are_complete_and_unit(kind, params):
    mesh = make_primitive(kind, **params)
    assert mesh.positions.dtype == np.float32 and mesh.positions.shape[1] == 3
    assert mesh.normals.dtype == np.float32 and mesh.normals.shape == mesh.positions.shape
    assert mesh.uvs is not None and mesh.uvs.dtype == np.float32 and mesh.uvs.shape == (mesh.vertex_count, 2)
    assert mesh.indices.dtype == np.uint32 and mesh.indices.max() < mesh.vertex_count
    assert np.isfinite(mesh.positions).all() and np.isfinite(mesh.uvs).all()
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-6)
    assert mesh.groups[0].first == 0 and mesh.groups[0].count == mesh.triangle_count
    assert mesh.source == f"primitive {kind}"
    # No degenerate triangles.
    assert (np.linalg.norm(face_normals(mesh), axis=1) > 1e-9).all()


def test_exact_volumes():
    assert signed_volume(box([1, 2, 3])) == pytest.approx(6.0)
    assert signed_volume(prism(radius=1, height=2, sides=4)) == pytest.approx(4.0)  # square of side sqrt(2)
    # An n-gon cylinder or cone encloses the inscribed polygon's prism or pyramid.
    polygon_area = 0.5 * 32 * np.sin(2 * np.pi / 32)
    assert signed_volume(cylinder(radius=1, height=1, segments=32)) == pytest.approx(polygon_area, rel=1e-5)
    assert signed_volume(cone(radius=1, height=3, segments=32)) == pytest.approx(polygon_area, rel=1e-5)
    assert signed_volume(sphere(radius=1, segments=64, rings=32)) == pytest.approx(4 / 3 * np.pi, rel=0.01)


@pytest.mark.parametrize(
    "kind, params, triangles",
    [
        ("plane", {}, 2),
        ("box", {}, 12),
        ("sphere", {"segments": 32, "rings": 16}, 2 * 32 * 15),
        ("sphere", {"segments": 5, "rings": 3}, 2 * 5 * 2),
        ("cylinder", {"segments": 24}, 4 * 24),
        ("cylinder", {"segments": 3}, 12),
        ("prism", {"sides": 6}, 24),
        ("prism", {"sides": 9}, 36),
        ("cone", {"segments": 24}, 48),
        ("cone", {"segments": 4}, 8),
    ],
)
def test_segment_counts_set_triangle_counts(kind, params, triangles):
    assert make_primitive(kind, **params).triangle_count == triangles


@pytest.mark.parametrize(
    "kind, params, low, high",
    [
        ("box", {"size": 2}, [-1, -1, -1], [1, 1, 1]),
        ("box", {"size": [1, 2, 4]}, [-0.5, -1, -2], [0.5, 1, 2]),
        ("plane", {"size": 3}, [-1.5, 0, -1.5], [1.5, 0, 1.5]),
        ("plane", {"size": [2, 6]}, [-1, 0, -3], [1, 0, 3]),
        ("sphere", {"radius": 1.5}, [-1.5, -1.5, -1.5], [1.5, 1.5, 1.5]),
        ("cylinder", {"radius": 2, "height": 5}, [-2, -2.5, -2], [2, 2.5, 2]),
        ("cone", {"radius": 0.5, "height": 4}, [-0.5, -2, -0.5], [0.5, 2, 0.5]),
        ("prism", {"radius": 1, "height": 2, "sides": 4}, [-1, -1, -1], [1, 1, 1]),
    ],
)
def test_bounds_follow_the_sizes(kind, params, low, high):
    np.testing.assert_allclose(make_primitive(kind, **params).bounds(), [low, high], atol=1e-6)


def test_defaults():
    assert sphere().bounds()[1] == pytest.approx([0.5, 0.5, 0.5])
    assert sphere().triangle_count == 2 * 32 * 15
    assert cylinder().triangle_count == 4 * 32
    assert cone().triangle_count == 2 * 32
    assert prism().triangle_count == 4 * 6
    assert box().bounds().tolist() == [[-0.5] * 3, [0.5] * 3]
    np.testing.assert_allclose(plane().uvs.max(axis=0), [1, 1])


def test_plane_faces_up_with_repeated_uvs():
    mesh = plane(size=[4, 2], uv_repeat=8)
    np.testing.assert_array_equal(mesh.normals, np.tile([0, 1, 0], (4, 1)))
    assert (face_normals(mesh)[:, 1] > 0).all()
    np.testing.assert_allclose(mesh.uvs.min(axis=0), [0, 0])
    np.testing.assert_allclose(mesh.uvs.max(axis=0), [8, 8])
    # u grows along +X, v toward -Z.
    right = mesh.positions[:, 0] > 0
    far = mesh.positions[:, 2] < 0
    np.testing.assert_allclose(mesh.uvs[right, 0], 8)
    np.testing.assert_allclose(mesh.uvs[far, 1], 8)


def test_box_faces_have_axis_normals_and_full_uv_squares():
    mesh = box([2, 2, 2])
    assert mesh.vertex_count == 24
    # Every vertex lies on the face its normal names.
    np.testing.assert_allclose(np.einsum("ij,ij->i", mesh.positions, mesh.normals), 1.0)
    for face in range(6):
        uvs = mesh.uvs[4 * face : 4 * face + 4]
        assert sorted(map(tuple, uvs.tolist())) == [(0, 0), (0, 1), (1, 0), (1, 1)]


def test_sphere_normals_are_radial_and_uvs_cover_the_square():
    mesh = sphere(radius=2, segments=16, rings=8)
    np.testing.assert_allclose(mesh.normals, mesh.positions / 2.0, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(mesh.positions, axis=1), 2.0, atol=1e-6)
    assert mesh.uvs[:, 0].min() == 0 and mesh.uvs[:, 0].max() == 1
    assert mesh.uvs[:, 1].min() == 0 and mesh.uvs[:, 1].max() == 1
    # v is latitude: 1 at the north pole, 0 at the south.
    np.testing.assert_allclose(mesh.uvs[mesh.positions[:, 1] > 1.999, 1], 1.0)
    np.testing.assert_allclose(mesh.uvs[mesh.positions[:, 1] < -1.999, 1], 0.0)
    # u is longitude: a quarter turn from +Z toward +X.
    quarter = (np.abs(mesh.positions[:, 1]) < 1e-6) & (mesh.positions[:, 0] > 1.999)
    np.testing.assert_allclose(mesh.uvs[quarter, 0], 0.25)


def test_cylinder_sides_are_smooth_and_caps_flat():
    mesh = cylinder(radius=1, height=2, segments=12)
    side = np.abs(mesh.normals[:, 1]) < 1e-6
    cap = np.abs(np.abs(mesh.normals[:, 1]) - 1) < 1e-6
    assert side.sum() == 2 * 13 and cap.sum() == 2 * 13  # seam copy on the side, centre on each cap
    radial = mesh.positions[side] * [1, 0, 1]
    np.testing.assert_allclose(mesh.normals[side], radial, atol=1e-6)
    np.testing.assert_allclose(mesh.normals[cap, 1], np.sign(mesh.positions[cap, 1]))


def test_prism_sides_are_flat():
    sides = 5
    mesh = prism(radius=1, height=1, sides=sides)
    side = np.abs(mesh.normals[:, 1]) < 1e-6
    distinct = np.unique(np.round(mesh.normals[side], 6), axis=0)
    assert len(distinct) == sides
    # All four corners of each side share that side's face normal.
    per_face = face_normals(mesh)
    side_faces = np.abs(per_face[:, 1]) < 1e-9
    per_face = per_face / np.linalg.norm(per_face, axis=1, keepdims=True)
    corner_normals = mesh.normals[mesh.indices[side_faces].astype(np.int64)]
    np.testing.assert_allclose(corner_normals, np.repeat(per_face[side_faces, None, :], 3, axis=1), atol=1e-6)


def test_cone_side_normals_are_tilted_by_the_slope():
    radius, height = 1.0, 2.0
    mesh = cone(radius=radius, height=height, segments=16)
    side = mesh.normals[:, 1] > -0.999
    n = mesh.normals[side].astype(np.float64)
    # The slope rises by height over radius, so the normal's up component is
    # radius / sqrt(radius^2 + height^2) everywhere on the side, apex included.
    np.testing.assert_allclose(n[:, 1], radius / np.hypot(radius, height), atol=1e-6)
    # And it is perpendicular to the line from each base point up to the apex.
    base = side & (mesh.positions[:, 1] < 0)
    up_the_side = np.array([0.0, height / 2, 0.0]) - mesh.positions[base]
    np.testing.assert_allclose(np.einsum("ij,ij->i", up_the_side, mesh.normals[base]), 0, atol=1e-6)
    apex = mesh.positions[:, 1] > height / 2 - 1e-6
    assert apex.sum() == 16
    assert np.isfinite(mesh.normals).all()


@pytest.mark.parametrize(
    "kind, params, message",
    [
        ("sphere", {"segments": 2}, "segments"),
        ("sphere", {"rings": 1}, "rings"),
        ("sphere", {"radius": 0}, "radius"),
        ("cylinder", {"height": -1}, "height"),
        ("cylinder", {"segments": 3.5}, "segments"),
        ("prism", {"sides": 2}, "sides"),
        ("cone", {"radius": float("nan")}, "radius"),
        ("box", {"size": [1, 0, 1]}, "size"),
        ("box", {"size": [1, 1]}, "size"),
        ("plane", {"size": True}, "size"),
        ("plane", {"uv_repeat": 0}, "uv_repeat"),
        ("sphere", {"radius": 1, "colour": 3}, "colour"),
        ("torus", {}, "torus"),
    ],
)
def test_invalid_parameters(kind, params, message):
    with pytest.raises(ValueError, match=message):
        make_primitive(kind, **params)


def test_whole_float_counts_are_accepted():
    assert make_primitive("cylinder", segments=8.0).triangle_count == 32


def test_every_primitive_is_registered():
    assert set(PRIMITIVES) == {"plane", "box", "sphere", "cylinder", "prism", "cone"}
