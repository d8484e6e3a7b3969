"""glTF geometry read without trimesh (scenerender/mesh/gltf_geometry.py): the same mesh as
trimesh reads, on generated files and the example GLB; what it leaves to trimesh still
loads; and reading a GLB no longer imports trimesh."""
from __future__ import annotations

import json
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gltf_files import GlbBuilder, quad, sphere
from scenerender.errors import Warnings
from scenerender.mesh import load_mesh
from scenerender.mesh import loader
from scenerender.mesh.gltf import split_glb
from scenerender.mesh.gltf_geometry import NotReadHere, read_parts
from scenerender.scene.assets import policy_for

ROOT = Path(__file__).resolve().parent.parent
PROPS = ROOT / "scenes" / "assets" / "models" / "pbr_props.glb"


def both_ways(path: Path):
    """(the mesh as gltf_geometry reads it, as trimesh reads it), both through the loader's
    own checks and joins."""
    raw = path.read_bytes()
    read_file = loader._policy_reader(path, policy_for(path))
    source = split_glb(raw)
    gltf = loader._read_gltf(source, path, read_file, Warnings())
    here = read_parts(source, read_file, [m.name for m in gltf.materials] if gltf else [])
    theirs = loader._trimesh_parts(path, raw, policy_for(path), gltf, Warnings())
    return loader._joined(here, gltf, path.name), loader._joined(theirs, gltf, path.name)


def assert_same_mesh(a, b):
    assert a.vertex_count == b.vertex_count and a.triangle_count == b.triangle_count
    # trimesh may list the node instances in another order: compare triangle by triangle,
    # each as its three corners' positions, sorted
    corners_a = a.positions[a.indices.reshape(-1, 3)].reshape(-1, 9)
    corners_b = b.positions[b.indices.reshape(-1, 3)].reshape(-1, 9)
    order_a, order_b = np.lexsort(corners_a.T[::-1]), np.lexsort(corners_b.T[::-1])
    assert np.allclose(corners_a[order_a], corners_b[order_b], atol=1e-5)
    for name in ("normals", "uvs", "colors"):
        values_a, values_b = getattr(a, name), getattr(b, name)
        assert (values_a is None) == (values_b is None), name
        if values_a is not None:
            per_a = values_a[a.indices.reshape(-1, 3)].reshape(len(corners_a), -1)[order_a]
            per_b = values_b[b.indices.reshape(-1, 3)].reshape(len(corners_b), -1)[order_b]
            assert np.allclose(per_a, per_b, atol=1e-5), name
    assert triangles_by_material(a) == triangles_by_material(b)


def triangles_by_material(mesh) -> dict:
    """material -> triangles (the groups are runs, which the instances' order splits)."""
    counts: dict = {}
    for group in mesh.groups:
        counts[group.material] = counts.get(group.material, 0) + group.count
    return counts


def test_the_example_glb_reads_as_trimesh_reads_it():
    here, theirs = both_ways(PROPS)
    assert here.triangle_count == 22414
    assert_same_mesh(here, theirs)
    assert here.materials.keys() == theirs.materials.keys() and here.images.keys() == theirs.images.keys()


def test_node_transforms_colours_and_materials_read_as_trimesh_reads_them(tmp_path):
    builder = GlbBuilder()
    red = builder.material(pbrMetallicRoughness={"baseColorFactor": [1, 0, 0, 1]})
    mesh, uv = quad()
    colors = np.random.default_rng(1).uniform(0, 1, (len(mesh.vertices), 4))
    flat = builder.mesh(builder.primitive(mesh, red, uv=uv, colors=colors, color_component=5121))
    ball = builder.mesh(builder.primitive(sphere(0.5, 2)))
    child = builder.node(ball, root=False, translation=[0, 2, 0], rotation=[0, 0, 0.3826834, 0.9238795],
                         scale=[1, 2, 1])
    builder.node(flat, children=[child], matrix=[2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, -1, 1])
    builder.node(ball, translation=[-3, 0, 0])  # one mesh, two instances
    here, theirs = both_ways(builder.write(tmp_path / "nodes.glb"))
    assert_same_mesh(here, theirs)


def test_a_strided_non_indexed_gltf_with_an_external_buffer(tmp_path):
    # positions and normals interleaved in one view (byteStride 24), no indices
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 1, 0], [1, 0, 0]], np.float32)
    normals = np.tile(np.array([[0, 0, 1]], np.float32), (6, 1))
    interleaved = np.hstack([positions, normals]).astype(np.float32).tobytes()
    (tmp_path / "data.bin").write_bytes(interleaved)
    document = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "buffers": [{"uri": "data.bin", "byteLength": len(interleaved)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(interleaved), "byteStride": 24}],
        "accessors": [{"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 6, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
    }
    (tmp_path / "strided.gltf").write_text(json.dumps(document))
    here, theirs = both_ways(tmp_path / "strided.gltf")
    assert here.triangle_count == 2
    assert_same_mesh(here, theirs)
    assert np.allclose(here.normals, [0, 0, 1])


def test_what_it_leaves_to_trimesh_still_loads(tmp_path):
    # a triangle strip (mode 5): not read here, read by trimesh
    builder = GlbBuilder()
    strip = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], np.float32)
    builder.json["meshes"].append({"primitives": [{"attributes": {"POSITION": builder.accessor(strip, "VEC3")},
                                                   "mode": 5}]})
    builder.node(0)
    path = builder.write(tmp_path / "strip.glb")
    with pytest.raises(NotReadHere):
        read_parts(split_glb(path.read_bytes()), lambda name: b"", [])
    assert load_mesh(path, warnings=Warnings()).triangle_count == 2


def test_a_broken_glb_is_one_line_naming_the_file(tmp_path):
    raw = bytearray(PROPS.read_bytes())
    length = struct.unpack_from("<I", raw, 12)[0]
    raw[20:20 + length] = b"{" + b" " * (length - 1)  # the JSON chunk, unreadable
    (tmp_path / "broken.glb").write_bytes(bytes(raw))
    with pytest.raises(Exception) as caught:
        load_mesh(tmp_path / "broken.glb", warnings=Warnings())
    assert "broken.glb" in str(caught.value.location) and "\n" not in str(caught.value)


def test_reading_a_glb_does_not_import_trimesh():
    code = ("import sys; from scenerender.mesh import load_mesh; from scenerender.errors import Warnings; "
            f"load_mesh({str(PROPS)!r}, warnings=Warnings()); print('trimesh' in sys.modules, 'scipy' in sys.modules)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.split() == ["False", "False"]
