"""OBJ reading (scenerender.mesh.obj) and file loading (scenerender.mesh.loader)."""
from __future__ import annotations

import contextlib
import re
import warnings as python_warnings
from pathlib import Path

import numpy as np
import pytest

from scenerender.errors import UserError, Warnings
from scenerender.mesh import MeshGroup, load_mesh, parse_obj
from scenerender.mesh import obj as obj_module

SQUARE_VERTICES = """\
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
"""


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def parse(folder: Path, text: str, name: str = "model.obj", warnings: Warnings | None = None):
    return parse_obj(write(folder, name, text), warnings if warnings is not None else Warnings())


def triangle_positions(mesh) -> np.ndarray:
    """(M, 3, 3): the corner positions of every triangle, in index order."""
    return mesh.positions[mesh.indices.astype(np.int64)]


@contextlib.contextmanager
def np_warnings_as_errors():
    """NumPy's RuntimeWarnings (overflow in a cast...) fail the test instead of printing."""
    with python_warnings.catch_warnings():
        python_warnings.simplefilter("error", RuntimeWarning)
        yield


def error_from(folder: Path, text: str) -> UserError:
    with pytest.raises(UserError) as caught:
        parse(folder, text)
    return caught.value


# --------------------------------------------------------------------------------------
# Geometry


def test_single_triangle_without_normals_or_uvs(tmp_path):
    mesh = parse(tmp_path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert mesh.triangle_count == 1
    np.testing.assert_array_equal(triangle_positions(mesh)[0], [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    assert mesh.uvs is None
    assert mesh.normals is None  # left for the loader to compute
    assert mesh.positions.dtype == np.float32
    assert mesh.indices.dtype == np.uint32
    assert mesh.groups == [MeshGroup(None, 0, 1)]


def test_quad_is_split_into_two_triangles_sharing_the_first_corner(tmp_path):
    mesh = parse(tmp_path, SQUARE_VERTICES + "f 1 2 3 4\n")
    assert mesh.triangle_count == 2
    assert mesh.vertex_count == 4
    np.testing.assert_array_equal(
        triangle_positions(mesh),
        [[[0, 0, 0], [1, 0, 0], [1, 1, 0]], [[0, 0, 0], [1, 1, 0], [0, 1, 0]]],
    )


def test_pentagon_is_fan_triangulated(tmp_path):
    corners = [(np.cos(a), np.sin(a), 0.0) for a in np.linspace(0, 2 * np.pi, 5, endpoint=False)]
    text = "".join(f"v {x} {y} {z}\n" for x, y, z in corners) + "f 1 2 3 4 5\n"
    mesh = parse(tmp_path, text)
    assert mesh.triangle_count == 3
    expected = [[corners[0], corners[i], corners[i + 1]] for i in (1, 2, 3)]
    np.testing.assert_allclose(triangle_positions(mesh), expected, atol=1e-6)


def test_mixed_triangles_and_polygons_keep_file_order(tmp_path):
    text = SQUARE_VERTICES + "v 2 0 0\nf 1 2 3\nf 1 2 3 4\nf 2 5 3\n"
    mesh = parse(tmp_path, text)
    assert mesh.triangle_count == 4
    np.testing.assert_array_equal(triangle_positions(mesh)[3], [[1, 0, 0], [2, 0, 0], [1, 1, 0]])


def test_negative_indices_count_back_from_the_vertices_defined_so_far(tmp_path):
    text = (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
        "f -3 -2 -1\n"
        "v 5 0 0\nv 6 0 0\nv 5 1 0\n"
        "f -3 -2 -1\n"
    )
    mesh = parse(tmp_path, text)
    np.testing.assert_array_equal(
        triangle_positions(mesh),
        [[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[5, 0, 0], [6, 0, 0], [5, 1, 0]]],
    )


def test_negative_texture_and_normal_indices(tmp_path):
    text = (
        SQUARE_VERTICES
        + "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 2\n"
        + "f -4/-3/-1 -3/-2/-1 -2/-1/-1\n"
    )
    mesh = parse(tmp_path, text)
    np.testing.assert_array_equal(triangle_positions(mesh)[0], [[0, 0, 0], [1, 0, 0], [1, 1, 0]])
    np.testing.assert_array_equal(mesh.uvs[mesh.indices[0]], [[0, 0], [1, 0], [1, 1]])
    np.testing.assert_array_equal(mesh.normals[mesh.indices[0]], [[0, 0, 2]] * 3)


def test_all_corner_forms_and_normals_from_file(tmp_path):
    text = (
        SQUARE_VERTICES
        + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
        + "f 1/1/1 2/2/1 3/3/1\n"
        + "f 1//1 3//1 4//1\n"
    )
    mesh = parse(tmp_path, text)
    assert mesh.normals is not None
    np.testing.assert_array_equal(mesh.normals, np.tile([0, 0, 1], (mesh.vertex_count, 1)))
    # The second face has no texture coordinates: its corners get (0, 0).
    np.testing.assert_array_equal(mesh.uvs[mesh.indices[0]], [[0, 0], [1, 0], [1, 1]])
    np.testing.assert_array_equal(mesh.uvs[mesh.indices[1]], [[0, 0], [0, 0], [0, 0]])


def test_partial_normals_are_left_for_computation(tmp_path):
    text = SQUARE_VERTICES + "vn 0 0 1\nf 1//1 2//1 3//1\nf 1 3 4\n"
    mesh = parse(tmp_path, text)
    assert mesh.normals is None


def test_vt_with_one_value_and_w_components(tmp_path):
    text = "v 0 0 0 1\nv 1 0 0 1 0.5 0.5 0.5\nv 0 1 0\nvt 0.25\nvt 0.5 0.75 0\nf 1/1 2/2 3/2\n"
    mesh = parse(tmp_path, text)
    np.testing.assert_array_equal(triangle_positions(mesh)[0], [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    np.testing.assert_array_equal(mesh.uvs[mesh.indices[0]], [[0.25, 0], [0.5, 0.75], [0.5, 0.75]])


def test_vertices_are_shared_per_v_vt_vn_triple(tmp_path):
    # Two triangles share the edge 1-3 with the same texture coordinates there, but
    # vertex 1 also appears with a different vt (a UV seam): that makes one extra vertex.
    text = SQUARE_VERTICES + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
    text += "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 1/5 2/2 4/4\n"
    mesh = parse(tmp_path, text)
    assert mesh.vertex_count == 5
    assert mesh.triangle_count == 3
    # Positions of the shared corners stay identical, so the seam closes in space.
    np.testing.assert_array_equal(triangle_positions(mesh)[2][0], [0, 0, 0])


def test_ignored_statements_do_not_change_the_mesh(tmp_path):
    text = (
        "# a comment\n\n"
        "o thing\ng part\ns 1\n"
        + SQUARE_VERTICES
        + "vp 0.5\nl 1 2\np 3\ncstype bezier\nunknown statement here\n"
        + "f 1 2 3\n   \n\ts off\n"
    )
    mesh = parse(tmp_path, text)
    assert mesh.triangle_count == 1
    assert mesh.vertex_count == 3


def test_tabs_crlf_and_line_continuation(tmp_path):
    text = "v\t0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nv 1 1 0\r\nf 1 2 \\\r\n 3\r\nf 2 4 3\r\n"
    mesh = parse(tmp_path, text)
    assert mesh.triangle_count == 2
    np.testing.assert_array_equal(triangle_positions(mesh)[1], [[1, 0, 0], [1, 1, 0], [0, 1, 0]])


def test_trailing_slash_corner_means_no_normal(tmp_path):
    text = SQUARE_VERTICES + "vt 0 0\nvt 1 0\nvt 1 1\nf 1/1/ 2/2/ 3/3/\n"
    mesh = parse(tmp_path, text)
    assert mesh.normals is None
    np.testing.assert_array_equal(mesh.uvs[mesh.indices[0]], [[0, 0], [1, 0], [1, 1]])


def test_fast_and_careful_corner_parsers_agree(tmp_path):
    rng = np.random.default_rng(3)
    lines = [f"v {x} {y} {z}" for x, y, z in rng.random((50, 3))]
    lines += [f"vt {u} {v}" for u, v in rng.random((20, 2))]
    lines += [f"vn {x} {y} {z}" for x, y, z in rng.random((10, 3)) + 0.1]
    forms = ["{v}", "{v}/{t}", "{v}//{n}", "{v}/{t}/{n}"]
    for _ in range(300):
        size = int(rng.integers(3, 7))
        form = forms[int(rng.integers(0, 4))]  # one form per face, as OBJ requires
        corners = []
        for _ in range(size):
            v, t, n = int(rng.integers(1, 51)), int(rng.integers(1, 21)), int(rng.integers(-10, 0))
            corners.append(form.format(v=v, t=t, n=n))
        lines.append("f " + " ".join(corners))
    statements = obj_module._collect_statements("\n".join(lines), "x.obj")
    fast = obj_module._parse_corners_fast(statements.corner_tokens)
    careful = obj_module._parse_corners_slowly(statements, "x.obj")
    assert fast is not None
    for name in ("v", "vt", "vn", "has_vt", "has_vn"):
        np.testing.assert_array_equal(getattr(fast, name), getattr(careful, name), err_msg=name)
    assert careful.has_vt.any() and careful.has_vn.any() and not careful.has_vn.all()


# --------------------------------------------------------------------------------------
# Materials and groups


TWO_MATERIALS_MTL = """\
newmtl red
Kd 1 0 0
newmtl blue
Kd 0 0 1
"""


def test_usemtl_splits_the_mesh_into_groups(tmp_path):
    write(tmp_path, "colors.mtl", TWO_MATERIALS_MTL)
    text = (
        "mtllib colors.mtl\n" + SQUARE_VERTICES
        + "f 1 2 3\n"            # before any usemtl: the object's material
        + "usemtl red\nf 1 2 3\nf 1 3 4\n"
        + "usemtl blue\nf 1 2 3 4\n"
        + "usemtl red\nf 2 3 4\n"
    )
    mesh = parse(tmp_path, text)
    assert mesh.groups == [
        MeshGroup(None, 0, 1),
        MeshGroup("red", 1, 2),
        MeshGroup("blue", 3, 2),
        MeshGroup("red", 5, 1),
    ]
    assert set(mesh.materials) == {"red", "blue"}
    assert mesh.materials["blue"].diffuse == (0.0, 0.0, 1.0)


def test_repeated_and_empty_usemtl_runs_merge(tmp_path):
    write(tmp_path, "colors.mtl", TWO_MATERIALS_MTL)
    text = (
        "mtllib colors.mtl\n" + SQUARE_VERTICES
        + "usemtl red\nf 1 2 3\n"
        + "usemtl red\nf 1 3 4\n"
        + "usemtl blue\n"          # no faces: contributes nothing
        + "usemtl red\nf 2 3 4\n"
    )
    mesh = parse(tmp_path, text)
    assert mesh.groups == [MeshGroup("red", 0, 3)]


def test_groups_cover_all_triangles_in_order(tmp_path):
    text = SQUARE_VERTICES + "usemtl a\nf 1 2 3 4\nusemtl b\nf 1 2 3\nf 2 3 4\nusemtl c\nf 1 2 3 4\n"
    mesh = parse(tmp_path, text)
    first = 0
    for group in mesh.groups:
        assert group.first == first
        first += group.count
    assert first == mesh.triangle_count == 6
    assert [g.material for g in mesh.groups] == ["a", "b", "c"]


def test_missing_mtl_file_is_a_warning_naming_the_obj_line(tmp_path):
    warnings = Warnings()
    mesh = parse(tmp_path, "# header\nmtllib nowhere.mtl\n" + SQUARE_VERTICES + "f 1 2 3\n", warnings=warnings)
    assert mesh.triangle_count == 1
    assert mesh.materials == {}
    assert len(warnings.items) == 1
    assert "model.obj:2:" in warnings.items[0]
    assert "nowhere.mtl" in warnings.items[0]


def test_missing_mtl_file_is_an_error_when_strict(tmp_path):
    with pytest.raises(UserError, match="nowhere.mtl"):
        parse(tmp_path, "mtllib nowhere.mtl\n" + SQUARE_VERTICES + "f 1 2 3\n", warnings=Warnings(strict=True))


def test_several_libraries_on_one_mtllib_line(tmp_path):
    write(tmp_path, "a.mtl", "newmtl first\nKd 1 1 1\n")
    write(tmp_path, "sub/b.mtl", "newmtl second\nNs 10\n")
    mesh = parse(tmp_path, "mtllib a.mtl sub\\b.mtl\n" + SQUARE_VERTICES + "usemtl first\nf 1 2 3\n")
    assert set(mesh.materials) == {"first", "second"}
    assert mesh.materials["second"].shininess == 10.0


def test_undefined_material_name_warns_once(tmp_path):
    write(tmp_path, "colors.mtl", TWO_MATERIALS_MTL)
    warnings = Warnings()
    text = "mtllib colors.mtl\n" + SQUARE_VERTICES + "usemtl green\nf 1 2 3\nusemtl red\nf 1 2 3\nusemtl green\nf 1 3 4\n"
    parse(tmp_path, text, warnings=warnings)
    assert len(warnings.items) == 1
    assert "model.obj:6:" in warnings.items[0] and "'green'" in warnings.items[0]


# --------------------------------------------------------------------------------------
# Errors name the file and line


def test_face_referring_to_a_missing_vertex(tmp_path):
    error = error_from(tmp_path, "# cube\n" + SQUARE_VERTICES + "f 1 2 3\nf 1 2 12\n")
    assert error.location.line == 7
    assert error.location.file.endswith("model.obj")
    assert error.message == "face refers to vertex 12 but only 4 vertices are defined so far"


def test_face_may_not_refer_to_a_vertex_defined_later(tmp_path):
    error = error_from(tmp_path, "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n")
    assert error.location.line == 3
    assert "vertex 3" in error.message and "only 2 vertices" in error.message


def test_negative_index_reaching_before_the_first_vertex(tmp_path):
    error = error_from(tmp_path, SQUARE_VERTICES + "f -1 -2 -5\n")
    assert error.location.line == 5
    assert "-5" in error.message and "4 vertices" in error.message


def test_index_zero_is_rejected(tmp_path):
    error = error_from(tmp_path, SQUARE_VERTICES + "f 0 1 2\n")
    assert error.location.line == 5
    assert "start at 1" in error.message


def test_an_undefined_texture_coordinate_is_dropped_with_a_warning(tmp_path):
    warnings = Warnings()
    mesh = parse(tmp_path, SQUARE_VERTICES + "vt 0 0\nf 1/1 2/1 3/2\n", warnings=warnings)
    assert mesh.triangle_count == 1
    assert len(warnings.items) == 1 and ":6:" in warnings.items[0]
    assert "dropped 1 texture coordinate reference that nothing defines" in warnings.items[0]
    assert "texture coordinate 2" in warnings.items[0]


def test_normals_no_vn_defines_are_computed_as_subdivision_tools_write_them(tmp_path):
    """`f 1//1 2//2 3//3` in a file without normals: mainstream readers drop the index."""
    warnings = Warnings()
    mesh = parse(tmp_path, SQUARE_VERTICES + "f 1//1 2//1 3//1\nf 1//2 3//2 4//2\n", warnings=warnings)
    assert mesh.triangle_count == 2 and mesh.normals is None  # computed by the loader
    assert len(warnings.items) == 1 and ":5:" in warnings.items[0]
    assert "dropped 6 normal references" in warnings.items[0] and "no normals are defined" in warnings.items[0]


def test_an_undefined_normal_is_an_error_under_strict(tmp_path):
    with pytest.raises(UserError, match="dropped 3 normal references"):
        parse(tmp_path, SQUARE_VERTICES + "f 1//1 2//1 3//1\n", warnings=Warnings(strict=True))


def test_an_undefined_position_is_still_an_error(tmp_path):
    error = error_from(tmp_path, SQUARE_VERTICES + "f 1 2 9\n")
    assert error.location.line == 5 and "vertex 9" in error.message


def test_a_concave_face_is_ear_clipped_not_fanned(tmp_path):
    """An L-shaped hexagon whose first corner cannot see the whole face: a fan from it would
    cover the notch; ear clipping covers exactly the L (area 3), wound as the face."""
    text = "v 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nv 0 0 0\nv 2 0 0\nf 1 2 3 4 5 6\n"
    mesh = parse(tmp_path, text)
    triangles = triangle_positions(mesh)
    assert len(triangles) == 4
    cross = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    assert np.allclose(np.abs(cross[:, 2]).sum() / 2, 3.0)  # the L's area, no overlap
    assert (cross[:, 2] > 0).all()  # counter-clockwise like the face
    centroids = triangles.mean(axis=1)
    assert not ((centroids[:, 0] > 1) & (centroids[:, 1] > 1)).any()  # nothing in the notch


def test_a_convex_quad_is_still_a_fan(tmp_path):
    mesh = parse(tmp_path, SQUARE_VERTICES + "f 1 2 3 4\n")
    assert mesh.indices.tolist() == [[0, 1, 2], [0, 2, 3]]


def test_free_form_geometry_is_skipped_with_one_warning(tmp_path):
    warnings = Warnings()
    text = SQUARE_VERTICES + "vp 0.5 0.5\ncstype bspline\ndeg 3\ncurv 0 1 1 2 3 4\nparm u 0 0 0 0 1 1 1 1\nend\nf 1 2 3\n"
    mesh = parse(tmp_path, text, warnings=warnings)
    assert mesh.triangle_count == 1
    assert len(warnings.items) == 1
    assert warnings.items[0].endswith("model.obj:5: skipped 6 free-form geometry statements")


def test_escaped_spaces_in_library_and_texture_names(tmp_path):
    from PIL import Image

    Image.new("RGB", (4, 4), (200, 10, 10)).save(tmp_path / "my wood.png")
    write(tmp_path, "my lib.mtl", "newmtl wood\nKd 1 1 1\nmap_Kd my\\ wood.png\n")
    warnings = Warnings()
    mesh = parse(tmp_path, "mtllib my\\ lib.mtl\n" + SQUARE_VERTICES + "usemtl wood\nf 1 2 3\n", warnings=warnings)
    assert warnings.items == []
    material = mesh.materials["wood"]
    assert material.diffuse_map is not None and material.diffuse_map.path.name == "my wood.png"
    assert not material.diffuse_map.missing


def test_bad_number_in_a_vertex(tmp_path):
    error = error_from(tmp_path, "v 0 0 0\nv 1 abc 0\nv 0 1 0\nf 1 2 3\n")
    assert error.location.line == 2
    assert error.message == "expected a number, got 'abc'"


def test_non_finite_vertex_is_rejected(tmp_path):
    error = error_from(tmp_path, "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")
    assert error.location.line == 3
    assert "finite" in error.message


@pytest.mark.parametrize("line", ["v 1e39 0 0", "v 0 -3.5e38 0", "vt 0 1e39", "vn 0 0 1e39"])
def test_a_number_beyond_32_bit_floats_is_an_error_at_its_line(tmp_path, line):
    """The arrays are float32: 1e39 would become infinity there (and a triangle without
    area, a normal without direction), so the reader refuses it as the scene reader does."""
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n" + line + "\nf 1/1/1 2/1/1 3/1/1\n"
    with np_warnings_as_errors():
        error = error_from(tmp_path, text)
    assert error.location.line == 6
    assert error.message.startswith("expected a number at most 3.4e38 in size (32-bit floats), got ")


def test_the_largest_32_bit_float_is_still_a_coordinate(tmp_path):
    path = write(tmp_path, "far.obj", "v 0 0 0\nv 3.4e38 0 0\nv 0 -3.4e38 0\nvt 3.4e38 0\nf 1/1 2/1 3/1\n")
    with np_warnings_as_errors():
        mesh = load_mesh(path, warnings=Warnings())
    assert np.isfinite(mesh.positions).all() and mesh.positions.max() == np.float32(3.4e38)
    assert np.isfinite(mesh.uvs).all() and np.isfinite(mesh.normals).all()


@pytest.mark.parametrize("ply_type, value, reason", [
    ("double", "1e39", "a vertex coordinate is 1e+39, beyond 32-bit floats"),
    ("float", "1e39", "a vertex coordinate is not a finite number"),  # the file's own float32 is infinite
])
def test_a_ply_coordinate_beyond_32_bit_floats_is_an_error_naming_the_file(tmp_path, ply_type, value, reason):
    path = write(tmp_path, "far.ply", f"ply\nformat ascii 1.0\nelement vertex 3\nproperty {ply_type} x\n"
                 f"property {ply_type} y\nproperty {ply_type} z\nelement face 1\n"
                 f"property list uchar int vertex_indices\nend_header\n{value} 0 0\n0 1 0\n0 0 1\n3 0 1 2\n")
    with np_warnings_as_errors(), pytest.raises(UserError, match=re.escape(reason)) as caught:
        load_mesh(path, warnings=Warnings())
    assert caught.value.location.file.endswith("far.ply")


def test_a_node_transform_taking_a_gltf_beyond_32_bit_floats_is_an_error(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    from scenerender.mesh import box

    cube = box(1.0)
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.Trimesh(cube.positions, cube.indices.astype(np.int64), process=False),
                       transform=np.diag([1e38, 1e38, 1e38, 1.0]) @ np.diag([1e10, 1, 1, 1.0]))
    path = tmp_path / "huge.glb"
    scene.export(path)
    with np_warnings_as_errors(), pytest.raises(UserError, match="after the node transform is 5e\\+47"):
        load_mesh(path, warnings=Warnings())


def test_bad_number_in_a_face(tmp_path):
    error = error_from(tmp_path, SQUARE_VERTICES + "f 1 2 3\nf 1 x 3\n")
    assert error.location.line == 6
    assert "'x'" in error.message


def test_face_with_too_few_vertices_is_skipped_with_a_warning(tmp_path):
    warnings = Warnings()
    mesh = parse(tmp_path, SQUARE_VERTICES + "f 1 2 3\nf 1 2\nf 3\nl 1 2\n", warnings=warnings)
    assert mesh.triangle_count == 1
    assert len(warnings.items) == 1
    assert warnings.items[0].endswith("model.obj:6: skipped 2 faces with fewer than 3 vertices and 1 line element (l)")


def test_face_with_too_few_vertices_is_an_error_when_strict(tmp_path):
    with pytest.raises(UserError, match="fewer than 3 vertices") as caught:
        parse(tmp_path, SQUARE_VERTICES + "f 1 2\n", warnings=Warnings(strict=True))
    assert caught.value.location.line == 5


def test_vertex_with_too_few_numbers(tmp_path):
    error = error_from(tmp_path, "v 0 0\n")
    assert error.location.line == 1
    assert "3 numbers" in error.message


def test_error_text_is_file_line_message(tmp_path):
    error = error_from(tmp_path, SQUARE_VERTICES + "f 1 2 9\n")
    assert str(error).endswith("model.obj:5: face refers to vertex 9 but only 4 vertices are defined so far")


# --------------------------------------------------------------------------------------
# load_mesh


def test_load_mesh_computes_unit_normals_for_obj_without_them(tmp_path):
    path = write(tmp_path, "square.obj", SQUARE_VERTICES + "f 1 2 3 4\n")
    mesh = load_mesh(path, warnings=Warnings())
    np.testing.assert_allclose(mesh.normals, np.tile([0, 0, 1], (4, 1)), atol=1e-6)
    assert mesh.normals.dtype == np.float32


def test_load_mesh_normalizes_file_normals_and_can_normalize_size(tmp_path):
    path = write(tmp_path, "square.obj", SQUARE_VERTICES + "vn 0 0 5\nf 1//1 2//1 3//1 4//1\n")
    mesh = load_mesh(path, normalize=True, warnings=Warnings())
    np.testing.assert_allclose(mesh.normals, np.tile([0, 0, 1], (4, 1)))
    low, high = mesh.bounds()
    np.testing.assert_allclose((low + high) / 2, 0, atol=1e-7)
    assert np.linalg.norm(high - low) == pytest.approx(1.0)


def test_load_mesh_flat_mode(tmp_path):
    path = write(tmp_path, "square.obj", SQUARE_VERTICES + "f 1 2 3 4\n")
    mesh = load_mesh(path, normals="flat", warnings=Warnings())
    assert mesh.vertex_count == 6


def test_load_mesh_missing_file(tmp_path):
    with pytest.raises(UserError, match="not found") as caught:
        load_mesh(tmp_path / "absent.obj", warnings=Warnings())
    assert caught.value.location.file.endswith("absent.obj")


def test_load_mesh_without_triangles(tmp_path):
    path = write(tmp_path, "points.obj", "v 0 0 0\nv 1 0 0\np 1 2\n")
    with pytest.raises(UserError, match="no triangles") as caught:
        load_mesh(path, warnings=Warnings())
    assert caught.value.location.file.endswith("points.obj")


def test_load_mesh_unsupported_extension(tmp_path):
    path = write(tmp_path, "model.xyz", "1 2 3\n")
    with pytest.raises(UserError, match="unsupported mesh format"):
        load_mesh(path, warnings=Warnings())


def test_load_mesh_reads_off_through_trimesh(tmp_path):
    path = write(tmp_path, "quad.off", "OFF\n4 1 0\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n4 0 1 2 3\n")
    mesh = load_mesh(path, warnings=Warnings())
    assert mesh.triangle_count == 2
    np.testing.assert_allclose(mesh.bounds(), [[0, 0, 0], [2, 2, 0]])
    np.testing.assert_allclose(mesh.normals, np.tile([0, 0, 1], (mesh.vertex_count, 1)), atol=1e-6)


def test_load_mesh_flattens_a_gltf_scene_with_transforms_and_uvs(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    from scenerender.mesh import box

    cube = box(1.0)
    geometry = trimesh.Trimesh(cube.positions, cube.indices.astype(np.int64), process=False)
    geometry.visual = trimesh.visual.TextureVisuals(uv=cube.uvs)
    scene = trimesh.Scene()
    shift = np.eye(4)
    shift[:3, 3] = [10, 0, 0]
    scene.add_geometry(geometry, transform=shift)
    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])  # a mirrored instance must stay outward-facing
    scene.add_geometry(geometry, transform=mirror @ shift)
    path = tmp_path / "two_boxes.glb"
    scene.export(path)

    mesh = load_mesh(path, warnings=Warnings())
    assert mesh.triangle_count == 24
    np.testing.assert_allclose(mesh.bounds(), [[-10.5, -0.5, -0.5], [10.5, 0.5, 0.5]], atol=1e-6)
    assert mesh.uvs is not None and mesh.uvs.shape == (mesh.vertex_count, 2)
    # Outward winding: positive signed volume for both boxes together.
    tri = mesh.positions[mesh.indices.astype(np.int64)].astype(np.float64)
    volume = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0
    assert volume == pytest.approx(2.0, rel=1e-5)


def test_load_mesh_unreadable_file_is_a_user_error(tmp_path):
    path = write(tmp_path, "broken.ply", "this is not a ply file\n")
    with pytest.raises(UserError) as caught:
        load_mesh(path, warnings=Warnings())
    assert caught.value.location.file.endswith("broken.ply")


# --------------------------------------------------------------------------------------
# Real-world tolerance and hostile input


def test_a_model_with_two_vertex_faces_loads_with_one_counting_warning(tmp_path):
    from asset_files import model_with_two_vertex_faces

    write(tmp_path, "model.mtl", "newmtl stone\nKd 0.5 0.5 0.5\n")
    warnings = Warnings()
    mesh = parse(tmp_path, model_with_two_vertex_faces(201), warnings=warnings)
    assert mesh.triangle_count == 12 * 12 * 2
    assert mesh.groups == [MeshGroup("stone", 0, 288)]
    assert len(warnings.items) == 1
    assert warnings.items[0].endswith(
        "skipped 201 faces with fewer than 3 vertices, 1 line element (l) and 1 point element (p)")
    with pytest.raises(UserError, match="skipped 201 faces"):
        parse(tmp_path, model_with_two_vertex_faces(201), warnings=Warnings(strict=True))


def test_zero_area_triangles_are_skipped_and_counted(tmp_path):
    warnings = Warnings()
    text = SQUARE_VERTICES + "v 2 0 0\nusemtl a\nf 1 2 3\nf 1 1 2\nusemtl b\nf 1 2 5\nf 1 3 4\n"
    mesh = parse(tmp_path, text, warnings=warnings)
    assert mesh.triangle_count == 2
    assert mesh.groups == [MeshGroup("a", 0, 1), MeshGroup("b", 1, 1)]
    assert warnings.items[0].endswith("skipped 2 zero-area triangles")


@pytest.mark.parametrize("corner", ["9223372036854775808", "-9223372036854775809", "99999999999999999999999",
                                    "1/9223372036854775807", "1//-99999999999999999999", "4611686018427387904"])
def test_face_indices_beyond_64_bits_are_an_error_at_their_line(tmp_path, corner):
    error = error_from(tmp_path, SQUARE_VERTICES + f"f 1 2 3\nf 1 {corner} 3\n")
    assert error.location.line == 6
    assert "out of range" in error.message


def test_a_face_index_far_past_the_vertices_is_an_error(tmp_path):
    error = error_from(tmp_path, SQUARE_VERTICES + "f 1 2 4611686018427387903\n")
    assert error.location.line == 5
    assert "only 4 vertices" in error.message


@pytest.mark.parametrize("name, content", [
    ("broken.ply", "ply\nformat ascii 1.0\nelement vertex 99999999999999\nproperty float x\nend_header\n1\n"),
    ("broken.stl", b"solid x\nfacet normal 0 0 nan\nouter loop\nvertex 1 2\n"),
    ("broken.glb", b"glTF\x02\x00\x00\x00\xff\xff\xff\x7f" + b"\x00" * 8),
    ("broken.gltf", '{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 7}}]}]}'),
    ("broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"),
])
def test_malformed_trimesh_formats_are_user_errors_naming_the_file(tmp_path, name, content):
    path = tmp_path / name
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    with pytest.raises(UserError) as caught:
        load_mesh(path, warnings=Warnings())
    assert caught.value.location.file.endswith(name)


def test_a_gltf_buffer_outside_the_allowed_folders_is_refused(tmp_path):
    import json

    from scenerender.scene.assets import AssetPolicy

    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "data.bin").write_bytes(np.zeros(36, np.float32).tobytes())
    gltf = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"uri": "../outside/data.bin", "byteLength": 36}],
    }
    path = write(tmp_path / "scene", "model.gltf", json.dumps(gltf))
    with pytest.raises(UserError, match="outside the folders"):
        load_mesh(path, warnings=Warnings(), assets=AssetPolicy(path.parent))
    # the same file with its buffer inside the folder loads, and the buffer counts as read
    (tmp_path / "scene" / "data.bin").write_bytes(np.array([0, 0, 0, 1, 0, 0, 0, 1, 0], np.float32).tobytes())
    gltf["buffers"][0]["uri"] = "data.bin"
    path.write_text(json.dumps(gltf))
    policy = AssetPolicy(path.parent)
    mesh = load_mesh(path, warnings=Warnings(), assets=policy)
    assert mesh.triangle_count == 1
    assert policy.files_read == [(tmp_path / "scene" / "data.bin").resolve()]


@pytest.mark.parametrize("name, header", [
    ("huge.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 b"property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\nend_header\n"),
    ("huge.stl", b"\0" * 80 + (4_000_000_000).to_bytes(4, "little")),
    ("huge.off", b"OFF\n3 4000000000 0\n0 0 0\n"),
])
def test_declared_face_counts_are_checked_against_the_budget_before_reading(tmp_path, name, header):
    from scenerender.mesh.budget import TriangleBudget

    path = tmp_path / name
    path.write_bytes(header)
    with pytest.raises(UserError, match="4,000,000,000, over the limit of 1,000") as caught:
        load_mesh(path, warnings=Warnings(), budget=TriangleBudget(limit=1000))
    assert caught.value.location.file.endswith(name)


def test_a_gltf_whose_faces_name_missing_vertices_is_a_user_error(tmp_path):
    import base64
    import json

    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32).tobytes()
    indices = np.array([0, 1, 7], np.uint16).tobytes()  # vertex 7 does not exist
    buffer = positions + indices
    gltf = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(buffer).decode(),
                     "byteLength": len(buffer)}],
    }
    path = write(tmp_path, "bad.gltf", json.dumps(gltf))
    with pytest.raises(UserError, match="faces refer to vertex 7 but the file has 3 vertices"):
        load_mesh(path, warnings=Warnings())


def test_far_texture_coordinates_move_towards_zero_by_whole_even_numbers():
    from scenerender.mesh.obj import recentred_texcoords

    near = np.array([[0.0, 0.0], [1.5, -3.0]])
    assert recentred_texcoords(near) is near  # ordinary coordinates are left alone
    far = np.array([[10000.0, 0.25], [10000.25, 0.5]])
    moved = recentred_texcoords(far)
    assert np.array_equal(moved[:, 1], far[:, 1])  # only the far axis moves
    shift = far[:, 0] - moved[:, 0]
    assert shift[0] == shift[1] and shift[0] % 2 == 0  # period 2: repeat and mirrored repeat agree
    assert np.abs(moved[:, 0]).max() < 2
