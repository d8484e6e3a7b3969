"""GLB files written by the tests: a few lines of NumPy, so each test says exactly which
glTF fields its file holds (materials, texture transforms, extensions, vertex colours,
nodes), where trimesh's exporter would choose for it."""
from __future__ import annotations

import io
import json
import struct
from pathlib import Path

import numpy as np
import trimesh
from PIL import Image


def png_bytes(pixels: np.ndarray) -> bytes:
    """PNG of (H, W, 3 or 4) uint8 pixels, top row first."""
    out = io.BytesIO()
    Image.fromarray(np.asarray(pixels, dtype=np.uint8)).save(out, format="PNG")
    return out.getvalue()


class GlbBuilder:
    """Meshes, materials, textures, images and nodes, written as one GLB (``write``)."""

    def __init__(self):
        self.json = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": 0}], "bufferViews": [],
                     "accessors": [], "meshes": [], "nodes": [], "scenes": [{"nodes": []}], "scene": 0}
        self.binary = bytearray()

    def _view(self, data: bytes, target: int | None = None) -> int:
        while len(self.binary) % 4:
            self.binary += b"\0"
        view = {"buffer": 0, "byteOffset": len(self.binary), "byteLength": len(data)}
        if target is not None:
            view["target"] = target
        self.binary += data
        self.json["bufferViews"].append(view)
        return len(self.json["bufferViews"]) - 1

    def accessor(self, array: np.ndarray, kind: str, component: int = 5126, normalized: bool = False,
                 target: int | None = 34962) -> int:
        dtype = {5126: np.float32, 5125: np.uint32, 5121: np.uint8, 5123: np.uint16}[component]
        data = np.ascontiguousarray(array, dtype=dtype)
        accessor = {"bufferView": self._view(data.tobytes(), target), "componentType": component,
                    "count": int(len(data)), "type": kind}
        if normalized:
            accessor["normalized"] = True
        if kind == "VEC3" and component == 5126:
            accessor["min"] = data.min(axis=0).tolist()
            accessor["max"] = data.max(axis=0).tolist()
        self.json["accessors"].append(accessor)
        return len(self.json["accessors"]) - 1

    def primitive(self, mesh: trimesh.Trimesh, material: int | None = None, uv: np.ndarray | None = None,
                  colors: np.ndarray | None = None, color_component: int = 5126) -> dict:
        """A primitive of ``mesh`` (its vertex normals included); uv in glTF's convention
        (v down); colors (N, 3 or 4) floats in [0, 1], stored as ``color_component``."""
        attributes = {"POSITION": self.accessor(mesh.vertices, "VEC3"),
                      "NORMAL": self.accessor(mesh.vertex_normals, "VEC3")}
        if uv is not None:
            attributes["TEXCOORD_0"] = self.accessor(uv, "VEC2")
        if colors is not None:
            colors = np.asarray(colors, dtype=np.float64)
            if color_component == 5126:
                attributes["COLOR_0"] = self.accessor(colors, "VEC4" if colors.shape[1] == 4 else "VEC3")
            else:
                scale = 255.0 if color_component == 5121 else 65535.0
                attributes["COLOR_0"] = self.accessor(np.round(colors * scale), "VEC4" if colors.shape[1] == 4
                                                      else "VEC3", color_component, normalized=True)
        primitive = {"attributes": attributes,
                     "indices": self.accessor(np.asarray(mesh.faces).reshape(-1), "SCALAR", 5125, target=34963)}
        if material is not None:
            primitive["material"] = material
        return primitive

    def mesh(self, *primitives: dict) -> int:
        self.json["meshes"].append({"primitives": list(primitives)})
        return len(self.json["meshes"]) - 1

    def node(self, mesh: int | None = None, root: bool = True, **fields) -> int:
        node = dict(fields)
        if mesh is not None:
            node["mesh"] = mesh
        self.json["nodes"].append(node)
        index = len(self.json["nodes"]) - 1
        if root:
            self.json["scenes"][0]["nodes"].append(index)
        return index

    def image(self, pixels: np.ndarray) -> int:
        self.json.setdefault("images", []).append({"bufferView": self._view(png_bytes(pixels)), "mimeType": "image/png"})
        return len(self.json["images"]) - 1

    def texture(self, pixels: np.ndarray, sampler: dict | None = None) -> int:
        texture = {"source": self.image(pixels)}
        if sampler is not None:
            self.json.setdefault("samplers", []).append(sampler)
            texture["sampler"] = len(self.json["samplers"]) - 1
        self.json.setdefault("textures", []).append(texture)
        return len(self.json["textures"]) - 1

    def material(self, **fields) -> int:
        self.json.setdefault("materials", []).append(fields)
        return len(self.json["materials"]) - 1

    def light(self, **fields) -> int:
        """A KHR_lights_punctual light (``type``, ``intensity``...); a node holds it with
        ``extensions={"KHR_lights_punctual": {"light": index}}``."""
        self.uses("KHR_lights_punctual")
        lights = self.json.setdefault("extensions", {}).setdefault("KHR_lights_punctual", {"lights": []})["lights"]
        lights.append(fields)
        return len(lights) - 1

    def camera(self, **fields) -> int:
        """A camera (``type`` and its ``perspective`` or ``orthographic``); a node holds it with
        ``camera=index``."""
        self.json.setdefault("cameras", []).append(fields)
        return len(self.json["cameras"]) - 1

    def uses(self, extension: str) -> None:
        """List ``extension`` in extensionsUsed."""
        used = self.json.setdefault("extensionsUsed", [])
        if extension not in used:
            used.append(extension)

    def animation(self, name: str | None, channels: list) -> int:
        """A clip of ``channels``: (node, path, times (K,), values (K or 3 K, D), interpolation)."""
        clip = {"channels": [], "samplers": []}
        for node, path, times, values, interpolation in channels:
            values = np.asarray(values, dtype=np.float64)
            kind = "SCALAR" if values.ndim == 1 else f"VEC{values.shape[1]}"
            clip["samplers"].append({"input": self.accessor(np.asarray(times, dtype=np.float64), "SCALAR", target=None),
                                     "output": self.accessor(values, kind, target=None),
                                     "interpolation": interpolation})
            clip["channels"].append({"sampler": len(clip["samplers"]) - 1, "target": {"node": node, "path": path}})
        if name is not None:
            clip["name"] = name
        self.json.setdefault("animations", []).append(clip)
        return len(self.json["animations"]) - 1

    def write(self, path: Path) -> Path:
        while len(self.binary) % 4:
            self.binary += b"\0"
        self.json["buffers"][0]["byteLength"] = len(self.binary)
        text = json.dumps(self.json).encode()
        text += b" " * (-len(text) % 4)
        body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(self.binary), 0x004E4942)
        body += bytes(self.binary)
        Path(path).write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
        return Path(path)


def sphere(radius: float = 1.0, subdivisions: int = 3) -> trimesh.Trimesh:
    return trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)


def sphere_uv(mesh: trimesh.Trimesh) -> np.ndarray:
    """(N, 2) glTF texture coordinates (v down) of a sphere about the origin: u round it from
    the back (-Z, u 0) through the front (+Z, u 0.5), v from the top."""
    direction = mesh.vertices / np.linalg.norm(mesh.vertices, axis=1, keepdims=True)
    return np.stack([0.5 + np.arctan2(direction[:, 0], direction[:, 2]) / (2 * np.pi),
                     0.5 - np.arcsin(np.clip(direction[:, 1], -1, 1)) / np.pi], axis=1)


def quad(size: float = 2.0) -> tuple[trimesh.Trimesh, np.ndarray]:
    """A square in the XY plane facing +Z, and its glTF texture coordinates (v down)."""
    h = size / 2.0
    mesh = trimesh.Trimesh(vertices=[[-h, -h, 0], [h, -h, 0], [h, h, 0], [-h, h, 0]], faces=[[0, 1, 2], [0, 2, 3]],
                           process=False)
    mesh.vertex_normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    uv = np.array([[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]])
    return mesh, uv
