"""Mesh data on the GPU: one vertex and index buffer per distinct mesh, shared by every
object that uses it, and one instance buffer per object."""
from __future__ import annotations

import numpy as np

from scenerender.mesh import MeshData, smooth_normals, tangents

INSTANCE_FLOATS = 16 + 9  # camera-relative model matrix, normal matrix


class GpuMesh:
    """Interleaved position/normal/uv (8 float32), uint32 indices, optional tangents and
    vertex colours (4 float32 each) and a second uv set (2 float32), in buffers of their own."""

    def __init__(self, ctx, mesh: MeshData, with_tangents: bool):
        uvs = mesh.uvs if mesh.uvs is not None else np.zeros((mesh.vertex_count, 2), dtype=np.float32)
        interleaved = np.hstack([mesh.positions, mesh.normals, uvs]).astype(np.float32)
        self.vertices = ctx.buffer(interleaved.tobytes())
        self.indices = ctx.buffer(np.ascontiguousarray(mesh.indices, dtype=np.uint32).tobytes())
        self.tangents = None
        if with_tangents:
            self.tangents = ctx.buffer(np.ascontiguousarray(tangents(mesh), dtype=np.float32).tobytes())
        self.uvs1 = None
        if mesh.uvs1 is not None:  # glTF TEXCOORD_1, for textures with texCoord: 1
            self.uvs1 = ctx.buffer(np.ascontiguousarray(mesh.uvs1, dtype=np.float32).tobytes())
        self.colors = None
        if mesh.colors is not None:
            self.colors = ctx.buffer(np.ascontiguousarray(mesh.colors, dtype=np.float32).tobytes())
        self.mesh = mesh
        self._ctx = ctx
        self._smooth = None

    def release(self) -> None:
        for buffer in (self.vertices, self.indices, self.tangents, self.colors, self.uvs1, self._smooth):
            if buffer is not None:
                buffer.release()

    def smooth_normals(self):
        """Normals averaged over vertices that share a position (made on first use).

        Outlines inflate the mesh along these: face normals would split a hard-edged mesh
        apart at its corners.
        """
        if self._smooth is None:
            normals = smooth_normals(self.mesh.positions, self.mesh.indices)
            self._smooth = self._ctx.buffer(np.ascontiguousarray(normals, dtype=np.float32).tobytes())
        return self._smooth

    def content(self, program, instances, welded_normals: bool = False) -> list:
        """moderngl vertex_array content for ``program`` with an instance buffer;
        ``welded_normals`` feeds ``smooth_normals()`` as in_normal."""
        names = set(program)
        # Attributes a program does not use must be skipped in the format ("x" = padding).
        fmt, attrs = [], []
        for size, name in ((3, "in_position"), (3, "in_normal"), (2, "in_uv")):
            if name in names:
                fmt.append(f"{size}f")
                attrs.append(name)
            else:
                fmt.append(f"{size * 4}x")
        if welded_normals and "in_normal" in attrs:
            fmt[1], attrs = "12x", [a for a in attrs if a != "in_normal"]
        layout = [(self.vertices, " ".join(fmt), *attrs)]
        if welded_normals and "in_normal" in names:
            layout.append((self.smooth_normals(), "3f", "in_normal"))
        if self.tangents is not None and "in_tangent" in names:
            layout.append((self.tangents, "4f", "in_tangent"))
        if self.colors is not None and "in_color" in names:
            layout.append((self.colors, "4f", "in_color"))
        if self.uvs1 is not None and "in_uv1" in names:
            layout.append((self.uvs1, "2f", "in_uv1"))
        inst_fmt, inst_attrs = [], []
        for size, name in ((16, "in_model"), (9, "in_normal_matrix")):
            if name in names:
                inst_fmt.append(f"{size}f")
                inst_attrs.append(name)
            else:
                inst_fmt.append(f"{size * 4}x")
        layout.append((instances, " ".join(inst_fmt) + "/i", *inst_attrs))
        return layout


def instance_bytes(models_rel: np.ndarray, normals: np.ndarray) -> bytes:
    """Per-instance attributes: (K, 4, 4) and (K, 3, 3) float32 -> K * 25 floats.

    GLSL matrices are column-major, so each matrix is written transposed.
    """
    return _instance_data(models_rel, normals).tobytes()


def instance_rows(models_rel: np.ndarray, normals: np.ndarray) -> list[bytes]:
    """instance_bytes of each instance on its own: K byte strings of 25 floats."""
    data = _instance_data(models_rel, normals)
    return [row.tobytes() for row in data]


def _instance_data(models_rel: np.ndarray, normals: np.ndarray) -> np.ndarray:
    k = len(models_rel)
    data = np.empty((k, INSTANCE_FLOATS), dtype=np.float32)
    data[:, :16] = np.swapaxes(models_rel, 1, 2).reshape(k, 16)
    data[:, 16:] = np.swapaxes(normals, 1, 2).reshape(k, 9)
    return data
