"""glTF 2.0 geometry read with NumPy alone: the common case, without importing trimesh.

Reading a GLB through trimesh imports trimesh and SciPy, about 0.45 s of a 1.2 s one-frame
render. Most files need no more than this module reads: triangle primitives (mode 4) whose
accessors are plain or strided views of a buffer (floats, integer indices, normalized
integer colours), placed by a node hierarchy of matrices or translation,
rotation and scale. What it does not read, ``NotReadHere`` says, and the loader hands the
file to trimesh instead: sparse accessors, other primitive modes (points, lines, strips,
fans), compressed or quantized geometry (Draco, meshopt, KHR_mesh_quantization), GPU
instancing, primitives with extensions. Skins and morph targets are read only for a file
whose clips play (``deformations``, mesh.loader.load_gltf_nodes); otherwise they are
ignored, as trimesh does.

The parts come out as the trimesh path gives them (mesh.loader._raw_parts): vertices,
faces, the normals the file stores (else None), TEXCOORD_0 with v flipped (trimesh's
convention: v = 0 at the image's bottom row), the node's world transform, the material's
name, COLOR_0 as linear RGBA, TEXCOORD_1 as TEXCOORD_0 and TANGENT (else None; its bitangent keeps its meaning
with v flipped, since the flip turns both the texture's v and the frame's handedness). The checks after (mesh.loader._part_arrays) are shared.
"""
from __future__ import annotations

import numpy as np

from scenerender.mesh.gltf import VARIANTS_EXTENSION, GltfProblem, buffer_view_bytes, primitive_material, rgba_colors, GltfSource

_DTYPES = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
# extensions that change how geometry is stored: the file goes to trimesh
_GEOMETRY_EXTENSIONS = ("KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization",
                        "EXT_mesh_gpu_instancing")
_MAX_DEPTH = 64  # node nesting followed; deeper (or a cycle) is a malformed file


class NotReadHere(Exception):
    """The file uses something this reader leaves to trimesh."""


def read_parts(source: GltfSource, read_file, material_names: list, deformations: bool = False,
               variant: str | None = None) -> list[dict]:
    """The triangle parts of the glTF file ``source`` (mesh.gltf.split_glb) in world space order of its
    default scene's nodes, depth first. ``read_file(uri)`` reads an external buffer;
    ``material_names``: the names mesh.gltf gave the file's materials, by index.
    ``deformations``: also read each primitive's JOINTS_0, WEIGHTS_0 and morph targets.
    ``variant``: a KHR_materials_variants name whose materials the primitives use.

    Raises NotReadHere where trimesh must read the file, GltfProblem where it is malformed."""
    header, binary = source
    used = set(header.get("extensionsUsed", []) or []) | set(header.get("extensionsRequired", []) or [])
    if used & set(_GEOMETRY_EXTENSIONS):
        raise NotReadHere("compressed or quantized geometry")
    reader = _Accessors(header, binary, read_file)
    parts = []
    for index, node, transform in placed_nodes(header):
        mesh_index = node.get("mesh")
        if mesh_index is None:
            continue
        meshes = header.get("meshes", [])
        if not (isinstance(mesh_index, int) and 0 <= mesh_index < len(meshes)):
            raise GltfProblem(f"a node names mesh {mesh_index!r}, the file has {len(meshes)}")
        for primitive in meshes[mesh_index].get("primitives", []):
            part = _primitive(primitive, reader, material_names, deformations, primitive_material(primitive, header,
                                                                                                   variant))
            if part is not None:
                parts.append({**part, "transform": transform, "node": index, "skin": node.get("skin"),
                              "morph_weights": node.get("weights", meshes[mesh_index].get("weights"))})
    return parts


def _primitive(primitive: dict, reader: "_Accessors", material_names: list, deformations: bool,
               material) -> dict | None:
    """``material``: the index of the material it uses (mesh.gltf.primitive_material)."""
    if primitive.get("mode", 4) != 4:
        raise NotReadHere("a primitive that is not a triangle list")
    if set(primitive.get("extensions") or ()) - {VARIANTS_EXTENSION}:  # which materials it takes is read here
        raise NotReadHere("a primitive with extensions")
    attributes = primitive.get("attributes", {})
    if "POSITION" not in attributes:
        return None
    vertices = reader.read(attributes["POSITION"], 3)
    count = len(vertices)
    indices = reader.read(primitive["indices"], 1).reshape(-1) if "indices" in primitive else np.arange(count)
    if len(indices) % 3 or not len(indices):
        return None
    normals = reader.read(attributes["NORMAL"], 3) if "NORMAL" in attributes else None
    uv = None
    if "TEXCOORD_0" in attributes:
        uv = reader.read(attributes["TEXCOORD_0"], 2)
        uv = np.column_stack([uv[:, 0], 1.0 - uv[:, 1]])
    colors = rgba_colors(reader.read(attributes["COLOR_0"], None), count) if "COLOR_0" in attributes else None
    tangents = reader.read(attributes["TANGENT"], 4).astype(np.float64) if "TANGENT" in attributes else None
    uv1 = None
    if "TEXCOORD_1" in attributes:
        uv1 = reader.read(attributes["TEXCOORD_1"], 2)
        uv1 = np.column_stack([uv1[:, 0], 1.0 - uv1[:, 1]])
    name = material_names[material] if isinstance(material, int) and 0 <= material < len(material_names) else None
    skinning = {}  # read only where a clip plays the file (mesh.loader.load_gltf_nodes)
    if deformations and "JOINTS_0" in attributes and "WEIGHTS_0" in attributes:
        skinning = {"joints": reader.read(attributes["JOINTS_0"], 4).astype(np.float64),
                    "weights": reader.read(attributes["WEIGHTS_0"], 4).astype(np.float64)}
    if deformations and primitive.get("targets"):
        skinning["targets"] = [_target(target, reader, count) for target in primitive["targets"]]
    return {**skinning, "vertices": vertices.astype(np.float64), "faces": indices.astype(np.int64).reshape(-1, 3),
            "normals": normals.astype(np.float64) if normals is not None and len(normals) == count else None,
            "uv": uv if uv is not None and len(uv) == count else None, "material": name, "colors": colors,
            "tangents": tangents if tangents is not None and len(tangents) == count else None,
            "uv1": uv1 if uv1 is not None and len(uv1) == count else None}


def accessor_reader(header: dict, binary: bytes | None, read_file):
    """``read(index, width)`` -> accessor ``index`` of the file as an array (see
    ``_Accessors.read``), each buffer read once: for the animations' keys."""
    return _Accessors(header, binary, read_file).read


def _target(target: dict, reader: "_Accessors", count: int) -> dict:
    """A morph target's POSITION and NORMAL deltas, (count, 3) float64 each (zeros where absent)."""
    deltas = {}
    for key, name in (("POSITION", "positions"), ("NORMAL", "normals")):
        values = reader.read(target[key], 3).astype(np.float64) if key in target else np.zeros((count, 3))
        if len(values) != count:
            raise GltfProblem(f"a morph target's {key} has {len(values)} values for {count} vertices")
        deltas[name] = values
    return deltas


class _Accessors:
    """Accessor arrays of one file, each buffer read once."""

    def __init__(self, header: dict, binary: bytes | None, read_file):
        self.header, self.binary, self.read_file = header, binary, read_file
        self.buffers: dict = {}

    def read(self, index, width: int | None) -> np.ndarray:
        """(count, width) of accessor ``index``: floats, or integers; normalized integers as
        floats in [0, 1] (unsigned) or [-1, 1] (signed). ``width`` None: the accessor's own."""
        accessors = self.header.get("accessors", [])
        if not (isinstance(index, int) and 0 <= index < len(accessors)):
            raise GltfProblem(f"a primitive names accessor {index!r}, the file has {len(accessors)}")
        accessor = accessors[index]
        if "sparse" in accessor:
            raise NotReadHere("a sparse accessor")
        dtype = _DTYPES.get(accessor.get("componentType"))
        own_width = _WIDTHS.get(accessor.get("type"))
        count = accessor.get("count")
        if dtype is None or own_width is None or not isinstance(count, int) or count < 0:
            raise GltfProblem(f"accessors[{index}] has an unknown type or count")
        if width is not None and own_width != width:
            raise GltfProblem(f"accessors[{index}] is {accessor.get('type')}, {width} components expected")
        values = self._values(accessor, index, np.dtype(dtype).newbyteorder("<"), own_width, count)
        if accessor.get("normalized") and dtype is not np.float32:
            scale = float(np.iinfo(dtype).max)
            return np.maximum(values.astype(np.float64) / scale, -1.0)
        return values

    def _values(self, accessor: dict, index: int, dtype: np.dtype, width: int, count: int) -> np.ndarray:
        if accessor.get("bufferView") is None:  # all zeros, by the specification
            return np.zeros((count, width), dtype)
        view_index = accessor["bufferView"]
        data, stride = buffer_view_bytes(self.header, view_index, self.binary, self.buffers, self.read_file)
        offset = accessor.get("byteOffset", 0)
        element = dtype.itemsize * width
        stride = stride or element
        if not isinstance(offset, int) or offset < 0 or stride < element:
            raise GltfProblem(f"accessors[{index}] has a bad byteOffset or its view a bad byteStride")
        if count and offset + (count - 1) * stride + element > len(data):
            raise GltfProblem(f"accessors[{index}] reaches past its bufferView")
        if count == 0:
            return np.zeros((0, width), dtype)
        view = np.ndarray((count, width), dtype, buffer=data, offset=offset, strides=(stride, dtype.itemsize))
        return np.array(view)  # a copy: the buffer's bytes are not kept alive by the mesh


def placed_nodes(header: dict, changed: dict | None = None):
    """(index, node, world transform (4, 4) float64) for every node of the default scene
    (all root nodes where the file has no scenes), depth first in the file's order.
    ``changed``: node index -> {"translation" | "rotation" | "scale": value} replacing the
    file's own (an animation at one instant). Raises GltfProblem where a node, the scene
    or a transform is malformed."""
    nodes = _json_list(header.get("nodes", []), "nodes")
    scenes = _json_list(header.get("scenes", []), "scenes")
    if scenes:
        scene = header.get("scene", 0)
        if not (isinstance(scene, int) and 0 <= scene < len(scenes) and isinstance(scenes[scene], dict)):
            raise GltfProblem(f"the default scene {scene!r} is not one of the {len(scenes)} scenes")
        roots = _json_list(scenes[scene].get("nodes", []), "a scene's nodes")
    else:
        children = {c for node in nodes if isinstance(node, dict) for c in _children(node) if isinstance(c, int)}
        roots = [i for i in range(len(nodes)) if i not in children]
    stack = [(root, np.eye(4), 0) for root in reversed(roots)]
    while stack:
        index, parent, depth = stack.pop()
        if not (isinstance(index, int) and 0 <= index < len(nodes)) or depth > _MAX_DEPTH:
            raise GltfProblem(f"node {index!r} is not in the file, or the hierarchy runs in a circle")
        node = nodes[index]
        if not isinstance(node, dict):
            raise GltfProblem(f"nodes[{index}] is not an object")
        world = parent @ _local({**node, **changed[index]} if changed and index in changed else node)
        yield index, node, world
        stack.extend((child, world, depth + 1) for child in reversed(_children(node)))


def _json_list(value, what: str) -> list:
    if not isinstance(value, list):
        raise GltfProblem(f"{what} is not a list")
    return value


def _children(node: dict) -> list:
    return _json_list(node.get("children", []), "a node's children")


def _local(node: dict) -> np.ndarray:
    """A node's transform: its matrix (column-major in the file), else T R S."""
    if "matrix" in node:
        return _numbers(node["matrix"], 16, "a node's matrix").reshape(4, 4).T
    transform = np.eye(4)
    quaternion = _numbers(node.get("rotation", (0.0, 0.0, 0.0, 1.0)), 4, "a node's rotation")
    norm = np.linalg.norm(quaternion)
    if not norm > 0.0:
        raise GltfProblem("a node's rotation is not a quaternion")
    x, y, z, w = quaternion / norm
    rotation = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])
    scale = _numbers(node.get("scale", (1.0, 1.0, 1.0)), 3, "a node's scale")
    transform[:3, :3] = rotation * scale[None, :]
    transform[:3, 3] = _numbers(node.get("translation", (0.0, 0.0, 0.0)), 3, "a node's translation")
    return transform


def _numbers(value, count: int, what: str) -> np.ndarray:
    """(count,) float64 of a JSON list of ``count`` finite numbers (an animation's values
    are arrays already)."""
    if isinstance(value, np.ndarray):
        array = value.astype(np.float64).reshape(-1)
    elif isinstance(value, (list, tuple)) and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                  for v in value):
        array = np.asarray(value, dtype=np.float64)
    else:
        raise GltfProblem(f"{what} is not {count} numbers")
    if array.shape != (count,) or not np.isfinite(array).all():
        raise GltfProblem(f"{what} is not {count} finite numbers")
    return array
