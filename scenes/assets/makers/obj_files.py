"""Per-corner normals and OBJ / MTL writing."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .common import HEADER, MODELS
from .geometry import Part


def corner_normals(v: np.ndarray, faces: list, smooth_angle: float) -> np.ndarray:
    """One normal per face corner (faces in order, corners in order), smoothing across
    neighbouring faces that meet at less than `smooth_angle` degrees, like Blender's auto
    smooth: curved surfaces come out smooth and creases stay sharp. Vertices are matched by
    position, so UV seams do not show in the shading. Area-weighted."""
    tri, tri_face = [], []
    for fi, f in enumerate(faces):
        for k in range(1, len(f) - 1):
            tri.append((f[0], f[k], f[k + 1]))
            tri_face.append(fi)
    tri = np.array(tri)
    cross = np.cross(v[tri[:, 1]] - v[tri[:, 0]], v[tri[:, 2]] - v[tri[:, 0]])
    face_vec = np.zeros((len(faces), 3))
    np.add.at(face_vec, np.array(tri_face), cross)
    face_len = np.linalg.norm(face_vec, axis=1, keepdims=True)
    face_dir = face_vec / np.maximum(face_len, 1e-20)

    sizes = np.array([len(f) for f in faces])
    corner_face = np.repeat(np.arange(len(faces)), sizes)
    corner_vert = np.concatenate([np.asarray(f) for f in faces])
    key = np.round(v[corner_vert] * 1e5).astype(np.int64)
    _, group = np.unique(key, axis=0, return_inverse=True)
    group = group.reshape(-1)
    order = np.argsort(group, kind="stable")
    counts = np.bincount(group)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    per_corner = counts[group]
    me = np.repeat(np.arange(len(corner_face)), per_corner)
    offsets = np.arange(per_corner.sum()) - np.repeat(np.cumsum(per_corner) - per_corner, per_corner)
    other = order[starts[group[me]] + offsets]
    agree = np.sum(face_dir[corner_face[me]] * face_dir[corner_face[other]], axis=1)
    keep = agree >= math.cos(math.radians(smooth_angle)) - 1e-9
    acc = np.zeros((len(corner_face), 3))
    np.add.at(acc, me[keep], face_vec[corner_face[other[keep]]])
    length = np.linalg.norm(acc, axis=1, keepdims=True)
    return np.where(length > 1e-20, acc / np.maximum(length, 1e-20), face_dir[corner_face])


def vertex_normals(part: Part) -> np.ndarray:
    """Smooth unit normal per vertex (area-weighted over the faces using it)."""
    corners = corner_normals(part.v, part.faces, 180.0)
    acc = np.zeros_like(part.v)
    np.add.at(acc, np.concatenate([np.asarray(f) for f in part.faces]), corners)
    return acc / np.maximum(np.linalg.norm(acc, axis=1, keepdims=True), 1e-20)


def fmt(x: float, places: int = 4) -> str:
    """Shortest fixed-point text for a coordinate ('1.5', '0', never '-0')."""
    s = f"{x:.{places}f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "", "-") else s


@dataclass
class Material:
    """An MTL material. Colours are linear RGB; texture paths relative to the MTL file."""
    kd: tuple
    ka: tuple | None = None
    ks: tuple = (0.1, 0.1, 0.1)
    ns: float = 16.0
    ke: tuple | None = None
    d: float = 1.0
    illum: int = 2
    map_kd: str | None = None
    map_ks: str | None = None
    map_bump: str | None = None
    bump_scale: float = 1.0
    comment: str = ""


def write_mtl(path: Path, materials: dict) -> None:
    lines = [f"# {HEADER}"]
    for name, m in materials.items():
        lines.append("")
        if m.comment:
            lines.append(f"# {m.comment}")
        lines.append(f"newmtl {name}")
        colour = lambda key, c: lines.append(f"{key} " + " ".join(fmt(x, 4) for x in c))
        colour("Ka", m.ka if m.ka is not None else m.kd)
        colour("Kd", m.kd)
        colour("Ks", m.ks)
        lines.append(f"Ns {fmt(m.ns, 2)}")
        if m.ke is not None:
            colour("Ke", m.ke)
        lines.append(f"d {fmt(m.d, 3)}")
        lines.append(f"illum {m.illum}")
        if m.map_kd:
            lines.append(f"map_Kd {m.map_kd}")
        if m.map_ks:
            lines.append(f"map_Ks {m.map_ks}")
        if m.map_bump:
            lines.append(f"map_Bump -bm {m.bump_scale:.1f} {m.map_bump}")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n", encoding="ascii", newline="\n")


@dataclass
class Model:
    """A model file to write: its parts, its MTL materials and how the OBJ is spelled."""
    name: str
    parts: list
    materials: dict
    normals: bool = True             # write vn (per-corner, auto-smoothed) or leave them out
    triangles_only: bool = False     # split quads and n-gons into triangles on output
    description: str = ""
    extra_header: list = field(default_factory=list)

    @property
    def triangle_count(self) -> int:
        return sum(p.triangle_count for p in self.parts)


def write_obj(model: Model) -> None:
    """Write model.obj (+ model.mtl). Each part writes its v / vt / vn block, then its
    faces. Positions are written once per part even where UV seams and poles split a
    vertex, so v and vt indices differ (as in most exported files); vn lines are shared
    between parts. Parts flagged relative_indices spell their faces with negative indices,
    counted back from the last element written so far."""
    has_uv = {p.uv is not None for p in model.parts}
    if len(has_uv) != 1:
        raise ValueError(f"{model.name}: all parts need UVs, or none")
    has_uv = has_uv.pop()
    lines = [f"# {HEADER}"]
    lines += [f"# {line}" for line in ([model.description] if model.description else []) + model.extra_header]
    lines += [f"# {model.triangle_count} triangles after triangulation", f"mtllib {model.name}.mtl", f"o {model.name}"]
    n_v = n_vt = 0
    normal_ids: dict = {}
    current_material = None
    for part in model.parts:
        base_v, base_vt = n_v, n_vt
        lines.append(f"g {part.name}")
        position_ids: dict = {}
        vertex_position = []
        for p in part.v:
            text = " ".join(fmt(x) for x in p)
            if text not in position_ids:
                position_ids[text] = len(position_ids)
                lines.append("v " + text)
            vertex_position.append(position_ids[text])
        n_v += len(position_ids)
        if has_uv:
            lines.extend("vt " + " ".join(fmt(x) for x in t) for t in part.uv)
            n_vt += len(part.uv)
        corner_vn = []
        if model.normals:
            for n in corner_normals(part.v, part.faces, part.smooth_angle):
                k = tuple(fmt(x, 3) for x in n)
                if k not in normal_ids:
                    normal_ids[k] = len(normal_ids) + 1
                    lines.append("vn " + " ".join(k))
                corner_vn.append(normal_ids[k])
        n_vn = len(normal_ids)
        if part.material != current_material:
            lines.append(f"usemtl {part.material}")
            current_material = part.material
        # Resolve each corner's 1-based (v, vt, vn), relative when the part asks for it.
        rel = part.relative_indices
        corner = 0
        for f in part.faces:
            refs = []
            for vi in f:
                iv = base_v + vertex_position[vi] + 1
                it = base_vt + vi + 1
                inn = corner_vn[corner] if model.normals else None
                corner += 1
                if rel:
                    iv, it = iv - n_v - 1, it - n_vt - 1
                    inn = None if inn is None else inn - n_vn - 1
                if has_uv and inn is not None:
                    refs.append(f"{iv}/{it}/{inn}")
                elif has_uv:
                    refs.append(f"{iv}/{it}")
                elif inn is not None:
                    refs.append(f"{iv}//{inn}")
                else:
                    refs.append(str(iv))
            polygons = [refs] if not model.triangles_only else \
                [[refs[0], refs[k], refs[k + 1]] for k in range(1, len(refs) - 1)]
            lines.extend("f " + " ".join(p) for p in polygons)
    MODELS.mkdir(parents=True, exist_ok=True)
    (MODELS / f"{model.name}.obj").write_text("\n".join(lines) + "\n", encoding="ascii", newline="\n")
    write_mtl(MODELS / f"{model.name}.mtl", model.materials)


def tex(name: str) -> str:
    """Texture path as written in an MTL in models/ (relative to the MTL file)."""
    return f"../textures/{name}"


WHITE = (1.0, 1.0, 1.0)
