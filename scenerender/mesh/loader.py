"""Load a mesh file into MeshData: OBJ with the built-in reader, other formats via trimesh.

trimesh takes over a second to import, so it is imported only when a non-OBJ file is
actually loaded.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, Warnings, display_path
from scenerender.mesh.data import MeshData
from scenerender.mesh.geometry import NORMAL_MODES, apply_normals_mode, normalize_unit
from scenerender.mesh.obj import parse_obj

TRIMESH_FORMATS = (".ply", ".stl", ".glb", ".gltf", ".off")
MESH_FORMATS = (".obj",) + TRIMESH_FORMATS


def load_mesh(
    path: Path, *, normals: str = "auto", normalize: bool = False, warnings: Warnings
) -> MeshData:
    """Read a mesh file, give it normals according to ``normals`` (auto | smooth | flat)
    and, with ``normalize``, centre it and scale its bounding-box diagonal to 1.

    The result always has finite unit normals. Raises UserError (naming the file) when the
    file is missing, of an unsupported type, unreadable, or holds no triangles.
    """
    if normals not in NORMAL_MODES:
        raise ValueError(f"normals must be one of {', '.join(NORMAL_MODES)}, not {normals!r}")
    path = Path(path)
    shown = display_path(path)
    if not path.is_file():
        problem = "is a folder, not a mesh file" if path.is_dir() else "mesh file not found"
        raise UserError(problem, SourceLocation(shown))
    suffix = path.suffix.lower()
    if suffix == ".obj":
        mesh = parse_obj(path, warnings)
    elif suffix in TRIMESH_FORMATS:
        mesh = _load_with_trimesh(path)
    else:
        raise UserError(
            f"unsupported mesh format '{path.suffix}' (supported: {', '.join(MESH_FORMATS)})",
            SourceLocation(shown),
        )
    if mesh.triangle_count == 0:
        raise UserError("the file contains no triangles", SourceLocation(shown))
    mesh = apply_normals_mode(mesh, normals)
    if normalize:
        mesh = normalize_unit(mesh)
    return mesh


def _load_with_trimesh(path: Path) -> MeshData:
    """Read ``path`` with trimesh and flatten the scene it describes into one mesh.

    Node transforms are applied; UVs are kept when any part has them (parts without get
    (0, 0)); normals are kept only when the file stored them, else left None for the
    normals mode to compute.
    """
    import trimesh  # deliberately lazy: see the module docstring

    shown = display_path(path)
    try:
        if hasattr(trimesh, "load_scene"):
            scene = trimesh.load_scene(str(path), process=False)
        else:  # trimesh < 4.5
            scene = trimesh.load(str(path), force="scene", process=False)
    except Exception as exc:  # trimesh raises many types for malformed files
        raise UserError(f"cannot read mesh: {exc}", SourceLocation(shown)) from exc

    parts = []
    for node in scene.graph.nodes_geometry:
        transform, geometry_name = scene.graph[node]
        geometry = scene.geometry.get(geometry_name)
        if isinstance(geometry, trimesh.Trimesh) and len(geometry.faces):
            parts.append(_part_arrays(geometry, np.asarray(transform, dtype=np.float64)))
    if not parts:
        raise UserError("the file contains no triangles", SourceLocation(shown))
    mesh = _concatenate(parts, shown)
    if not np.isfinite(mesh.positions).all():
        raise UserError("the mesh has vertices that are not finite numbers", SourceLocation(shown))
    return mesh


def _stored_vertex_normals(geometry) -> np.ndarray | None:
    """Vertex normals the file provided, or None.

    trimesh computes vertex normals on demand; ones read from the file are already in its
    cache, which is the only way to tell the two apart.
    """
    cache = getattr(geometry, "_cache", None)
    try:
        stored = cache["vertex_normals"] if "vertex_normals" in cache else None
    except Exception:  # a trimesh without this cache: compute normals ourselves
        return None
    if stored is None or len(stored) != len(geometry.vertices):
        return None
    return np.asarray(stored, dtype=np.float64)


def _part_arrays(geometry, transform: np.ndarray) -> dict:
    """One geometry instance in world space: positions, normals or None, uvs or None, faces."""
    positions = np.asarray(geometry.vertices, dtype=np.float64)
    faces = np.asarray(geometry.faces, dtype=np.int64)
    linear = transform[:3, :3]
    positions = positions @ linear.T + transform[:3, 3]
    normals = _stored_vertex_normals(geometry)
    if normals is not None:
        normals = normals @ np.linalg.inv(linear)  # rows times the inverse transpose
    if np.linalg.det(linear) < 0:  # a mirroring transform turns the winding inside out
        faces = faces[:, ::-1]
    uvs = None
    visual_uv = getattr(getattr(geometry, "visual", None), "uv", None)
    if visual_uv is not None and len(visual_uv) == len(positions):
        uvs = np.asarray(visual_uv, dtype=np.float64)[:, :2]
    return {"positions": positions, "normals": normals, "uvs": uvs, "faces": faces}


def _concatenate(parts: list[dict], shown: str) -> MeshData:
    """Join the parts into one mesh; see _load_with_trimesh for how UVs and normals merge."""
    offsets = np.cumsum([0] + [len(p["positions"]) for p in parts])
    uvs = normals = None
    if any(p["uvs"] is not None for p in parts):
        blank = [np.zeros((len(p["positions"]), 2)) for p in parts]
        uvs = np.concatenate(
            [p["uvs"] if p["uvs"] is not None else zeros for p, zeros in zip(parts, blank)]
        ).astype(np.float32)
    if all(p["normals"] is not None for p in parts):
        normals = np.concatenate([p["normals"] for p in parts]).astype(np.float32)
    faces = [p["faces"] + offset for p, offset in zip(parts, offsets)]
    return MeshData(
        positions=np.concatenate([p["positions"] for p in parts]).astype(np.float32),
        normals=normals,
        uvs=uvs,
        indices=np.concatenate(faces).astype(np.uint32),
        source=shown,
    )
