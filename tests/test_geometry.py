"""Geometry helpers (scenerender.mesh.geometry)."""
from __future__ import annotations

import numpy as np
import pytest

from scenerender.mesh import (
    MeshData,
    MeshGroup,
    apply_normals_mode,
    flat_shaded,
    normalize_unit,
    smooth_normals,
    tangents,
)
from scenerender.mesh.primitives import box, cylinder, plane, sphere


def mesh_from(positions, indices, uvs=None, normals=None, groups=None) -> MeshData:
    positions = np.asarray(positions, dtype=np.float32)
    return MeshData(
        positions=positions,
        normals=None if normals is None else np.asarray(normals, dtype=np.float32),
        uvs=None if uvs is None else np.asarray(uvs, dtype=np.float32),
        indices=np.asarray(indices, dtype=np.uint32).reshape(-1, 3),
        groups=groups or [],
    )


def unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


# A hinge: two triangles meeting along the edge 1-2 at x = 0. The left one is the larger
# (area sqrt(5)/2 against sqrt(2)/2), and the two are weighted so that the shared edge's
# normal comes out exactly +Y; averaging unit normals would lean it to the right.
HINGE_POSITIONS = [[-2, 0, 0], [0, 1, 0], [0, 1, -1], [1, 0, -0.5]]
HINGE_TRIANGLES = [[0, 1, 2], [1, 3, 2]]
LEFT_NORMAL = unit([-1, 2, 0])
RIGHT_NORMAL = unit([1, 1, 0])


def test_smooth_normals_of_a_flat_quad():
    normals = smooth_normals(np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]), np.array([[0, 1, 2], [0, 2, 3]]))
    assert normals.dtype == np.float32 and normals.shape == (4, 3)
    np.testing.assert_allclose(normals, np.tile([0, 0, 1], (4, 1)), atol=1e-7)


def test_smooth_normals_are_area_weighted():
    normals = smooth_normals(np.array(HINGE_POSITIONS, dtype=np.float64), np.array(HINGE_TRIANGLES))
    np.testing.assert_allclose(normals[1], [0, 1, 0], atol=1e-6)
    np.testing.assert_allclose(normals[2], [0, 1, 0], atol=1e-6)
    np.testing.assert_allclose(normals[0], LEFT_NORMAL, atol=1e-6)
    np.testing.assert_allclose(normals[3], RIGHT_NORMAL, atol=1e-6)


def test_smooth_normals_are_shared_across_a_uv_seam():
    # The same hinge, but the right triangle has its own copies of the edge vertices (as
    # a UV seam makes). The copies must still get the same, averaged normal.
    positions = HINGE_POSITIONS + [[0, 1, 0], [0, 1, -1]]
    triangles = [[0, 1, 2], [4, 3, 5]]
    normals = smooth_normals(np.array(positions, dtype=np.float64), np.array(triangles))
    for original, copy in ((1, 4), (2, 5)):
        np.testing.assert_array_equal(normals[original], normals[copy])
        np.testing.assert_allclose(normals[copy], [0, 1, 0], atol=1e-6)


def test_smooth_normals_over_a_sphere_seam():
    mesh = sphere(radius=1, segments=24, rings=12)
    normals = smooth_normals(mesh.positions, mesh.indices)
    # The seam at u = 0 / u = 1 duplicates a column of vertices; each pair must agree.
    _, ids, counts = np.unique(mesh.positions, axis=0, return_inverse=True, return_counts=True)
    ids = ids.reshape(-1)
    seam = np.flatnonzero((counts[ids] == 2))
    assert len(seam) == 2 * 11
    for group in np.unique(ids[seam]):
        copies = np.flatnonzero(ids == group)
        np.testing.assert_array_equal(normals[copies[0]], normals[copies[1]])
    np.testing.assert_allclose(normals[seam], mesh.positions[seam], atol=0.05)


def test_degenerate_triangles_add_nothing_and_never_give_nan():
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0], [5, 5, 5]], dtype=np.float64)
    # A proper triangle, one with a repeated corner, one with three collinear points;
    # vertex 4 is used by nothing.
    triangles = np.array([[0, 1, 2], [0, 0, 1], [0, 1, 3]])
    normals = smooth_normals(positions, triangles)
    assert np.isfinite(normals).all()
    np.testing.assert_allclose(normals[:3], np.tile([0, 0, 1], (3, 1)), atol=1e-7)
    np.testing.assert_allclose(normals[3], [0, 1, 0])  # only in a degenerate triangle: fallback
    np.testing.assert_allclose(normals[4], [0, 1, 0])  # unused: fallback


def test_all_degenerate_mesh_gets_fallback_normals_everywhere():
    mesh = mesh_from([[1, 1, 1]] * 3, [[0, 1, 2]])
    for mode in ("auto", "smooth", "flat"):
        result = apply_normals_mode(mesh, mode)
        assert np.isfinite(result.normals).all()
        np.testing.assert_allclose(np.linalg.norm(result.normals, axis=1), 1.0)


def test_flat_shading_unwelds_and_uses_face_normals():
    source = mesh_from(
        HINGE_POSITIONS,
        HINGE_TRIANGLES,
        uvs=[[i / 4, 0] for i in range(4)],
        groups=[MeshGroup("left", 0, 1), MeshGroup("right", 1, 1)],
    )
    mesh = flat_shaded(source)
    assert mesh.vertex_count == 6 and mesh.triangle_count == 2
    np.testing.assert_array_equal(mesh.indices, np.arange(6).reshape(2, 3))
    np.testing.assert_array_equal(mesh.positions, source.positions[source.indices.reshape(-1)])
    np.testing.assert_array_equal(mesh.uvs, source.uvs[source.indices.reshape(-1)])
    np.testing.assert_allclose(mesh.normals[:3], np.tile(LEFT_NORMAL, (3, 1)), atol=1e-6)
    np.testing.assert_allclose(mesh.normals[3:], np.tile(RIGHT_NORMAL, (3, 1)), atol=1e-6)
    assert mesh.groups == source.groups
    assert source.vertex_count == 4  # the input is not modified


def test_flat_shading_of_a_box_keeps_axis_normals():
    mesh = flat_shaded(box(1.0))
    assert mesh.vertex_count == 36
    np.testing.assert_allclose(np.abs(mesh.normals).max(axis=1), 1.0)


def test_auto_mode_keeps_file_normals_made_unit():
    file_normals = [[0, 0, 3]] * 4
    mesh = mesh_from([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]], normals=file_normals)
    tilted = mesh_from(mesh.positions, mesh.indices, normals=[[0, 1, 1]] * 4)
    np.testing.assert_allclose(apply_normals_mode(mesh, "auto").normals, np.tile([0, 0, 1], (4, 1)))
    # The file's choice wins over what the geometry would give.
    np.testing.assert_allclose(apply_normals_mode(tilted, "auto").normals, np.tile(unit([0, 1, 1]), (4, 1)), atol=1e-6)
    np.testing.assert_allclose(apply_normals_mode(tilted, "smooth").normals, np.tile([0, 0, 1], (4, 1)), atol=1e-6)


def test_auto_mode_replaces_unusable_file_normals():
    mesh = mesh_from(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
        [[0, 1, 2], [0, 2, 3]],
        normals=[[0, 0, 1], [0, 0, 0], [np.nan, 0, 0], [1, 0, 0]],
    )
    normals = apply_normals_mode(mesh, "auto").normals
    np.testing.assert_allclose(normals, [[0, 0, 1], [0, 0, 1], [0, 0, 1], [1, 0, 0]], atol=1e-6)


def test_auto_mode_without_normals_computes_smooth_ones():
    mesh = mesh_from(HINGE_POSITIONS, HINGE_TRIANGLES)
    np.testing.assert_array_equal(
        apply_normals_mode(mesh, "auto").normals,
        smooth_normals(mesh.positions, mesh.indices),
    )


def test_flat_mode_and_unknown_mode():
    mesh = mesh_from(HINGE_POSITIONS, HINGE_TRIANGLES)
    assert apply_normals_mode(mesh, "flat").vertex_count == 6
    with pytest.raises(ValueError, match="faceted"):
        apply_normals_mode(mesh, "faceted")


def test_normalize_unit_centres_and_scales_the_diagonal_to_one():
    mesh = box([2, 4, 4])
    moved = MeshData(mesh.positions + np.float32(10), mesh.normals, mesh.uvs, mesh.indices)
    result = normalize_unit(moved)
    low, high = result.bounds()
    np.testing.assert_allclose((low + high) / 2, 0, atol=1e-6)
    assert np.linalg.norm(high - low) == pytest.approx(1.0, abs=1e-6)
    np.testing.assert_allclose(high, np.array([1, 2, 2]) / 6, atol=1e-6)  # half-extents / old diagonal 6
    np.testing.assert_array_equal(result.normals, moved.normals)
    assert moved.bounds()[0][0] == pytest.approx(9)  # the input is unchanged


def test_normalize_unit_of_a_point_does_not_divide_by_zero():
    mesh = mesh_from([[3, 4, 5]] * 3, [[0, 1, 2]], normals=[[0, 1, 0]] * 3)
    result = normalize_unit(mesh)
    assert np.isfinite(result.positions).all()
    np.testing.assert_allclose(result.positions, 0)


def test_tangents_of_a_plane_follow_u():
    mesh = plane(size=2)
    frames = tangents(mesh)
    assert frames.dtype == np.float32 and frames.shape == (4, 4)
    np.testing.assert_allclose(frames[:, :3], np.tile([1, 0, 0], (4, 1)), atol=1e-6)
    # The bitangent w * cross(n, t) must point along increasing v, which is -Z.
    bitangents = frames[:, 3:] * np.cross(mesh.normals, frames[:, :3])
    np.testing.assert_allclose(bitangents, np.tile([0, 0, -1], (4, 1)), atol=1e-6)
    np.testing.assert_array_equal(frames[:, 3], 1)


def test_mirrored_uvs_flip_the_handedness():
    mesh = plane(size=2)
    mirrored = MeshData(mesh.positions, mesh.normals, mesh.uvs * np.float32([1, -1]), mesh.indices)
    np.testing.assert_array_equal(tangents(mirrored)[:, 3], -1)


@pytest.mark.parametrize("mesh", [sphere(1, 16, 8), cylinder(0.5, 2, 9), box([1, 2, 3])], ids=["sphere", "cylinder", "box"])
def test_tangents_are_unit_and_orthogonal_to_normals(mesh):
    frames = tangents(mesh)
    assert np.isfinite(frames).all()
    np.testing.assert_allclose(np.linalg.norm(frames[:, :3], axis=1), 1.0, atol=1e-5)
    np.testing.assert_allclose(np.einsum("ij,ij->i", frames[:, :3], mesh.normals), 0.0, atol=1e-5)
    assert set(np.unique(frames[:, 3])) <= {-1.0, 1.0}


def test_tangents_with_degenerate_or_missing_uvs_fall_back_to_a_perpendicular():
    square = plane(size=1)
    collapsed = MeshData(square.positions, square.normals, np.zeros_like(square.uvs), square.indices)
    no_uvs = MeshData(square.positions, square.normals, None, square.indices)
    for mesh in (collapsed, no_uvs):
        frames = tangents(mesh)
        assert np.isfinite(frames).all()
        np.testing.assert_allclose(np.linalg.norm(frames[:, :3], axis=1), 1.0, atol=1e-6)
        np.testing.assert_allclose(frames[:, :3] @ np.array([0, 1, 0]), 0.0, atol=1e-6)


def test_tangents_with_degenerate_triangles_have_no_nan():
    positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0]]
    mesh = mesh_from(positions, [[0, 1, 2], [0, 3, 1]], uvs=[[0, 0], [1, 0], [0, 1], [0, 0]])
    mesh = apply_normals_mode(mesh, "smooth")
    frames = tangents(mesh)
    assert np.isfinite(frames).all()
    np.testing.assert_allclose(frames[:3, :3], np.tile([1, 0, 0], (3, 1)), atol=1e-6)
