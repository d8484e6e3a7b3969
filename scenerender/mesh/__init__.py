"""CPU-side meshes: the MeshData type, OBJ/MTL and glTF reading, other formats through
trimesh, built-in primitives and geometry helpers. No OpenGL here, so everything is testable
without a GL context.
"""
from __future__ import annotations

import importlib

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

# The OBJ and MTL readers load with the first OBJ file (loader.load_mesh); a glTF or
# primitive scene does not pay for their modules (tests/test_startup.py).
_OBJ_READERS = {"MtlMaterial": "mtl", "TextureRef": "mtl", "parse_mtl": "mtl", "parse_obj": "obj"}


def __getattr__(name: str):
    if name in _OBJ_READERS:
        return getattr(importlib.import_module(f"scenerender.mesh.{_OBJ_READERS[name]}"), name)
    raise AttributeError(f"module 'scenerender.mesh' has no attribute {name!r}")
