"""CPU-side meshes: the MeshData type, OBJ/MTL and glTF reading, other formats through
trimesh, built-in primitives and geometry helpers. No OpenGL here, so everything is testable
without a GL context.
"""
from __future__ import annotations

from scenerender.mesh.data import MeshData, MeshGroup
from scenerender.mesh.geometry import (
    NORMAL_MODES,
    apply_normals_mode,
    flat_shaded,
    normalize_unit,
    smooth_normals,
    tangents,
)
from scenerender.mesh.loader import MESH_FORMATS, load_mesh
from scenerender.mesh.mtl import MtlMaterial, TextureRef, parse_mtl
from scenerender.mesh.obj import parse_obj
from scenerender.mesh.primitives import (
    PRIMITIVES,
    box,
    cone,
    cylinder,
    make_primitive,
    plane,
    prism,
    sphere,
)

__all__ = [
    "MESH_FORMATS",
    "NORMAL_MODES",
    "PRIMITIVES",
    "MeshData",
    "MeshGroup",
    "MtlMaterial",
    "TextureRef",
    "apply_normals_mode",
    "box",
    "cone",
    "cylinder",
    "flat_shaded",
    "load_mesh",
    "make_primitive",
    "normalize_unit",
    "parse_mtl",
    "parse_obj",
    "plane",
    "prism",
    "smooth_normals",
    "sphere",
    "tangents",
]
