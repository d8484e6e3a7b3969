"""glTF: the PBR props of the gltf_pbr scene (one GLB, its textures inside)."""
from __future__ import annotations

import io
import json
import math
import struct
from pathlib import Path

import numpy as np
from PIL import Image

from .common import linear, mix, MODELS, smoothstep, srgb
from .geometry import bevelled_box, ellipsoid, lathe, Part
from .noise import normal_map_from_height, texture_uv, tiling_fbm


def make_props_crate_maps() -> dict:
    """A sci-fi crate face, 256 px, as glTF's maps: base colour (sRGB), ORM (linear: red
    occlusion, green roughness, blue metallic, one image for the occlusion and the
    metallic-roughness textures), tangent-space normals and emission (sRGB). A frame of
    dark grey-blue paint around a teal panel, grooved seams between them, rivets, an
    orange glowing strip across the panel, and bare metal where paint has worn off at the
    edges and in scratches."""
    size = 256
    u, v = texture_uv(size, size)
    x, y = u * size, v * size
    edge = np.minimum.reduce([x, size - x, y, size - y])
    frame = edge < 34.0
    seam = np.abs(edge - 34.0) < 2.5
    strip = (np.abs(y - size / 2) < 7.0) & (np.abs(x - size / 2) < 72.0)
    grain = tiling_fbm(size, size, 8, seed=601, octaves=5)
    wear_noise = tiling_fbm(size, size, 16, seed=602, octaves=4)
    # bare metal: near the outer edge where the noise is high, and a few scratches
    worn = (wear_noise + 0.9 * (1.0 - smoothstep(2.0, 14.0, edge))) > 0.75
    gen = np.random.default_rng(603)
    for _ in range(9):
        cx, cy, angle = gen.uniform(40, 216), gen.uniform(40, 216), gen.uniform(0, math.pi)
        length = gen.uniform(20, 60)
        along = (x - cx) * math.cos(angle) + (y - cy) * math.sin(angle)
        across = -(x - cx) * math.sin(angle) + (y - cy) * math.cos(angle)
        worn |= (np.abs(along) < length / 2) & (np.abs(across) < 0.9)
    rivet_height = np.zeros((size, size))
    for cx, cy in [(17, 17), (17, size - 17), (size - 17, 17), (size - 17, size - 17),
                   (size / 2, 17), (size / 2, size - 17), (17, size / 2), (size - 17, size / 2)]:
        d = np.hypot(x - cx, y - cy)
        rivet_height = np.maximum(rivet_height, np.sqrt(np.clip(1.0 - (d / 5.0) ** 2, 0.0, 1.0)))
    rivet = rivet_height > 0.0
    paint = np.where(frame[..., None], srgb("#3c4654"), srgb("#2f8a8f"))
    paint = mix(paint, paint * 0.82, np.clip(grain * 0.5 + 0.5, 0, 1))
    metal = srgb("#b9bcc0") * (0.92 + 0.08 * grain[..., None])
    base = np.where((worn | rivet)[..., None], metal, paint)
    base = np.where(strip[..., None], srgb("#2a2118"), base)
    base = np.where(seam[..., None], base * 0.45, base)
    metallic = np.where(worn | rivet, 1.0, 0.0)
    roughness = np.where(worn | rivet, 0.3 + 0.1 * grain, np.where(frame, 0.7, 0.45) + 0.08 * grain)
    occlusion = 1.0 - 0.6 * (1.0 - smoothstep(0.0, 4.0, np.abs(edge - 34.0))) - 0.25 * strip
    height = np.where(frame, 1.0, 0.8) - 0.35 * (1.0 - smoothstep(0.0, 2.5, np.abs(edge - 34.0)))
    height = height - 0.15 * strip + 0.25 * rivet_height + 0.01 * grain
    emission = np.where(strip[..., None], mix(srgb("#ff6a1a"), srgb("#ffc56a"),
                                              1.0 - smoothstep(0.0, 7.0, np.abs(y - size / 2))), 0.0)
    return {"base": base, "orm": np.stack([occlusion, np.clip(roughness, 0, 1), metallic], axis=-1),
            "normal": normal_map_from_height(height * 12.0, strength=0.7), "emissive": emission}


def make_grille_map() -> np.ndarray:
    """One cell of a perforated steel sheet, 64 px RGBA: brushed grey, a round hole
    (alpha 0) of radius 22 px, anti-aliased; the sheet repeats it by texture transform."""
    size = 64
    u, v = texture_uv(size, size)
    brushed = tiling_fbm(size, size, (2, 16), seed=611, octaves=3)
    colour = srgb("#8d9299") * (0.9 + 0.1 * brushed[..., None])
    alpha = smoothstep(21.0, 23.0, np.hypot(u * size - size / 2, v * size - size / 2))
    return np.concatenate([colour, alpha[..., None]], axis=-1)


def png(pixels: np.ndarray) -> bytes:
    """PNG bytes of a float image in [0, 1] (RGB or RGBA, top row first)."""
    data = np.clip(np.round(np.asarray(pixels) * 255.0), 0, 255).astype(np.uint8)
    out = io.BytesIO()
    Image.fromarray(data, "RGBA" if data.shape[-1] == 4 else "RGB").save(out, "PNG", optimize=True)
    return out.getvalue()


def triangles(part: Part, normals: np.ndarray | None = None):
    """(positions, normals, uv in glTF's v-down convention, indices) of a part, faces split
    into fans. Without ``normals``, each vertex gets the mean of its faces' normals (parts
    whose faces own their vertices come out flat)."""
    tris = [(f[0], f[i], f[i + 1]) for f in part.faces for i in range(1, len(f) - 1)]
    indices = np.array(tris, dtype=np.uint32)
    if normals is None:
        a, b, c = (part.v[indices[:, k]] for k in range(3))
        face = np.cross(b - a, c - a)
        normals = np.zeros_like(part.v)
        for k in range(3):
            np.add.at(normals, indices[:, k], face)
    normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    uv = None if part.uv is None else np.column_stack([part.uv[:, 0], 1.0 - part.uv[:, 1]])
    return part.v, normals, uv, indices


class GlbWriter:
    """A glTF 2.0 binary file built up piece by piece: accessors into one buffer, images
    as PNG buffer views, textures, samplers, materials, meshes and a node tree."""

    def __init__(self):
        self.json = {"asset": {"version": "2.0", "generator": "scenes/assets/make_assets.py"},
                     "extensionsUsed": [], "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [],
                     "materials": [], "textures": [], "images": [], "samplers": [], "accessors": [],
                     "bufferViews": [], "buffers": [{"byteLength": 0}]}
        self.binary = bytearray()

    def _add(self, key: str, item: dict) -> int:
        self.json[key].append(item)
        return len(self.json[key]) - 1

    def view(self, data: bytes, target: int | None = None) -> int:
        self.binary += b"\0" * (-len(self.binary) % 4)
        view = {"buffer": 0, "byteOffset": len(self.binary), "byteLength": len(data)}
        if target is not None:
            view["target"] = target
        self.binary += data
        return self._add("bufferViews", view)

    def accessor(self, values: np.ndarray, kind: str, component: int = 5126) -> int:
        dtype = {5126: "<f4", 5125: "<u4"}[component]
        data = np.ascontiguousarray(values, dtype=dtype)
        accessor = {"bufferView": self.view(data.tobytes(), 34963 if component == 5125 else 34962),
                    "componentType": component, "count": len(data), "type": kind}
        if kind == "VEC3":
            accessor["min"] = [round(float(x), 6) for x in data.min(axis=0)]
            accessor["max"] = [round(float(x), 6) for x in data.max(axis=0)]
        return self._add("accessors", accessor)

    def geometry(self, part: Part, normals=None, colors=None) -> dict:
        """Attributes and indices of a part, to share between primitives."""
        positions, normals, uv, indices = triangles(part, normals)
        attributes = {"POSITION": self.accessor(positions, "VEC3"), "NORMAL": self.accessor(normals, "VEC3")}
        if uv is not None:
            attributes["TEXCOORD_0"] = self.accessor(uv, "VEC2")
        if colors is not None:
            attributes["COLOR_0"] = self.accessor(colors, "VEC4")
        return {"attributes": attributes, "indices": self.accessor(indices.reshape(-1), "SCALAR", 5125)}

    def texture(self, pixels: np.ndarray, sampler: dict) -> int:
        image = self._add("images", {"bufferView": self.view(png(pixels)), "mimeType": "image/png"})
        return self._add("textures", {"source": image, "sampler": self._add("samplers", sampler)})

    def material(self, **fields) -> int:
        for name in fields.get("extensions", {}):
            if name not in self.json["extensionsUsed"]:
                self.json["extensionsUsed"].append(name)
        return self._add("materials", fields)

    def mesh(self, name: str, geometry: dict, material: int) -> int:
        return self._add("meshes", {"name": name, "primitives": [{**geometry, "material": material}]})

    def node(self, name: str, mesh: int | None = None, children=None, **transform) -> int:
        node = {"name": name, **{k: [round(float(x), 6) for x in v] for k, v in transform.items()}}
        if mesh is not None:
            node["mesh"] = mesh
        if children:
            node["children"] = list(children)
        return self._add("nodes", node)

    def write(self, path: Path, roots) -> None:
        self.json["scenes"][0]["nodes"] = list(roots)
        self.binary += b"\0" * (-len(self.binary) % 4)
        self.json["buffers"][0]["byteLength"] = len(self.binary)
        text = json.dumps(self.json, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        body = (struct.pack("<II", len(text), 0x4E4F534A) + text
                + struct.pack("<II", len(self.binary), 0x004E4942) + bytes(self.binary))
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def y_rotation(degrees: float) -> list:
    """glTF quaternion (x, y, z, w) turning ``degrees`` about +Y."""
    half = math.radians(degrees) / 2.0
    return [0.0, math.sin(half), 0.0, math.cos(half)]


def write_props_glb() -> int:
    """models/pbr_props.glb: a metallic-roughness material chart (gold metal and red
    plastic spheres, roughness 0.1 to 0.9, under one parent node), a sci-fi crate with
    every texture glTF has (base colour, metallic-roughness and occlusion in one ORM image,
    normals, emission with KHR_materials_emissive_strength) on a pedestal coloured by
    COLOR_0, and a perforated steel sheet (alpha MASK, double-sided, its one-hole texture
    repeated by KHR_texture_transform). Returns the triangle count."""
    glb = GlbWriter()
    linear_sampler = {"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}
    roots, triangle_count = [], 0

    sphere = ellipsoid((0.16, 0.16, 0.16), segments=48, rings=24, uv=True)
    sphere_geometry = glb.geometry(sphere, normals=sphere.v / 0.16)
    triangle_count_sphere = sphere.triangle_count
    chart = []
    for row, (colour, metallic, kind) in enumerate((((1.0, 0.766, 0.336, 1.0), 1.0, "gold"),
                                                    ((0.8, 0.05, 0.04, 1.0), 0.0, "plastic"))):
        for column, roughness in enumerate((0.1, 0.3, 0.5, 0.7, 0.9)):
            material = glb.material(name=f"{kind}_{roughness:.1f}", pbrMetallicRoughness={
                "baseColorFactor": list(colour), "metallicFactor": metallic, "roughnessFactor": roughness})
            mesh = glb.mesh(f"{kind}_sphere_{column}", sphere_geometry, material)
            chart.append(glb.node(f"{kind}_{column}", mesh, translation=(0.4 * column - 0.8, 0.16, 0.42 * row)))
            triangle_count += triangle_count_sphere
    roots.append(glb.node("chart", children=chart, translation=(0.75, 0.0, 0.15), rotation=y_rotation(-12.0)))

    maps = make_props_crate_maps()
    orm = glb.texture(maps["orm"], linear_sampler)
    crate_material = glb.material(
        name="crate", pbrMetallicRoughness={
            "baseColorTexture": {"index": glb.texture(maps["base"], linear_sampler)},
            "metallicRoughnessTexture": {"index": orm}, "metallicFactor": 1.0, "roughnessFactor": 1.0},
        normalTexture={"index": glb.texture(maps["normal"], linear_sampler), "scale": 1.0},
        occlusionTexture={"index": orm, "strength": 1.0},
        emissiveTexture={"index": glb.texture(maps["emissive"], linear_sampler)}, emissiveFactor=[1.0, 1.0, 1.0],
        extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 3.0}})
    crate = bevelled_box(0.6, 0.035)
    crate_node = glb.node("crate", glb.mesh("crate", glb.geometry(crate), crate_material),
                          translation=(0.0, 0.25 + 0.3, 0.0), rotation=y_rotation(28.0))
    triangle_count += crate.triangle_count
    pedestal = lathe([(0.0, 0.0), (0.45, 0.0), (0.45, 0.2), (0.42, 0.25), (0.0, 0.25)], segments=48,
                     smooth_angle=30.0, name="pedestal")
    heights = pedestal.v[:, 1] / 0.25
    angle = np.arctan2(pedestal.v[:, 0], pedestal.v[:, 2])
    low, high = np.array(linear("#14233a")), np.array(linear("#3aa6b0"))
    colors = low + (high - low) * (0.25 + 0.75 * heights[:, None]) * (0.85 + 0.15 * np.cos(3 * angle)[:, None])
    pedestal_material = glb.material(name="pedestal", pbrMetallicRoughness={
        "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.35})
    pedestal_node = glb.node("pedestal", glb.mesh("pedestal", glb.geometry(
        pedestal, colors=np.column_stack([colors, np.ones(len(colors))])), pedestal_material))
    triangle_count += pedestal.triangle_count
    roots.append(glb.node("crate_stand", children=[pedestal_node, crate_node], translation=(-1.0, 0.0, 0.1)))

    sheet = Part("grille", np.array([[-0.65, -0.4, 0.0], [0.65, -0.4, 0.0], [0.65, 0.4, 0.0], [-0.65, 0.4, 0.0]]),
                 [(0, 1, 2, 3)], uv=np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]))
    grille_material = glb.material(
        name="grille", alphaMode="MASK", alphaCutoff=0.5, doubleSided=True,
        pbrMetallicRoughness={"baseColorTexture": {"index": glb.texture(make_grille_map(), {
            "magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}), "extensions": {
                "KHR_texture_transform": {"scale": [13.0, 8.0]}}}, "metallicFactor": 1.0, "roughnessFactor": 0.4})
    glb.json["extensionsUsed"].append("KHR_texture_transform")
    roots.append(glb.node("grille", glb.mesh("grille", glb.geometry(sheet), grille_material),
                          translation=(0.55, 0.55, -0.75), rotation=y_rotation(-8.0)))
    triangle_count += 2
    glb.write(MODELS / "pbr_props.glb", roots)
    return triangle_count
