"""glTF 2.0 materials: what the renderer needs of a GLB or .gltf file's JSON beyond its
geometry (which mesh.gltf_geometry reads, or trimesh where that cannot).

trimesh, where it reads the geometry, keeps part of each material. What it drops is read here from the file's JSON: ``normalTexture.scale``,
``occlusionTexture.strength``, ``KHR_texture_transform``, ``KHR_materials_emissive_strength``,
``KHR_materials_unlit``, the samplers' wrap and filter modes, ``texCoord``, and which
material each primitive uses (trimesh's geometries are matched to the primitives in file
order, their vertex counts checked against the accessors). Images are taken as the file
stores them (encoded bytes); the world decodes them like any texture.

Nothing here trusts the JSON: a value of the wrong type or out of range is a
``GltfProblem``, which the loader turns into one warning, and the file is drawn with the
scene's (or the default) material instead.
"""
from __future__ import annotations

import base64
import math
import struct
from dataclasses import dataclass, field
from typing import NamedTuple
from urllib.parse import unquote

import numpy as np
from pydantic import ValidationError

from scenerender.json_input import GLTF_JSON_MAX_BYTES, JsonProblem, parse_json
from scenerender.mesh.gltf_document import GltfDocument
from scenerender.scene.messages import first_problem

from scenerender.scene.model.materials import MAX_IOR  # the largest index of refraction a material takes

GLB_MAGIC = 0x46546C67  # "glTF"
_JSON_CHUNK = 0x4E4F534A
_BIN_CHUNK = 0x004E4942

# primitive modes trimesh turns into a geometry of the scene, in file order: POINTS,
# LINES, TRIANGLES, TRIANGLE_STRIP (LINE_LOOP, LINE_STRIP and TRIANGLE_FAN it skips)
_GEOMETRY_MODES = (0, 1, 4, 5)
_TRIANGLE_MODES = (4, 5)
_WRAP = {10497: "repeat", 33071: "clamp", 33648: "mirror"}
_NEAREST_FILTERS = (9728, 9984, 9986)  # NEAREST, NEAREST_MIPMAP_NEAREST, NEAREST_MIPMAP_LINEAR
# the denominators of normalized integer COLOR_0 components, by componentType
_NORMALIZED = {5121: 255.0, 5123: 65535.0}


# extensions read somewhere: here (materials, textures), by mesh.gltf_scene (lights), or
# left to trimesh with the geometry (mesh.gltf_geometry). Any other a file uses is named in
# a warning: drawn without it, never dropped silently.
READ_EXTENSIONS = (
    "KHR_texture_transform", "KHR_materials_emissive_strength", "KHR_materials_unlit", "KHR_lights_punctual",
    "KHR_materials_ior", "KHR_materials_specular", "KHR_materials_clearcoat", "KHR_materials_sheen",
    "KHR_materials_variants", "KHR_materials_transmission", "KHR_materials_volume",
    "KHR_materials_pbrSpecularGlossiness", "KHR_materials_anisotropy", "KHR_materials_iridescence",
    "KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization", "EXT_mesh_gpu_instancing",
)


VARIANTS_EXTENSION = "KHR_materials_variants"
SPECULAR_GLOSSINESS = "KHR_materials_pbrSpecularGlossiness"
# the dielectric F0 of ior 1.5, which KHR_materials_specular's specular colour scales
_DIELECTRIC_F0 = 0.04


class GltfProblem(Exception):
    """The file's JSON says something about materials that cannot be used."""


class GltfStructureProblem(GltfProblem):
    """The file's JSON is no glTF document: not JSON within the bounds, or a part of the
    wrong type (``key`` names it: ``materials[1]``). Bad input whatever reads the file."""

    def __init__(self, message: str, key: str | None = None):
        super().__init__(f"{key}: {message}" if key else message)
        self.message = message
        self.key = key


@dataclass(frozen=True)
class GltfTexture:
    """A texture a glTF material names.

    image:     the key of its encoded image in ``MeshData.images``, or None where the file
               names an image it does not hold (drawn as the placeholder).
    uv_scale, uv_offset, uv_skew: the affine map from the mesh's texture coordinates (GL
               convention, v up) to the image's: ``(s.x u + k.x v + o.x, k.y u + s.y v + o.y)``,
               ``KHR_texture_transform`` carried over from glTF's v-down coordinates.
    scale:     ``normalTexture.scale`` or ``occlusionTexture.strength`` (1 elsewhere).
    wrap:      "repeat" | "clamp" | "mirror", from the sampler's ``wrapS``.
    nearest:   the sampler's ``magFilter`` is NEAREST.
    tex_coord: the ``texCoord`` set it asks for (0 or 1; a file asking for more reads 0).
    """

    image: str | None
    uv_scale: tuple = (1.0, 1.0)
    uv_offset: tuple = (0.0, 0.0)
    uv_skew: tuple = (0.0, 0.0)
    scale: float = 1.0
    wrap: str = "repeat"
    nearest: bool = False
    tex_coord: int = 0


@dataclass(frozen=True)
class GltfMaterial:
    """One glTF material, with glTF's defaults for what the file leaves out. Colours are
    linear; ``emissive`` already times ``KHR_materials_emissive_strength``."""

    name: str
    base_color: tuple = (1.0, 1.0, 1.0, 1.0)
    metallic: float = 1.0
    roughness: float = 1.0
    emissive: tuple = (0.0, 0.0, 0.0)
    emissive_strength: float = 1.0
    alpha_mode: str = "opaque"
    alpha_cutoff: float = 0.5
    double_sided: bool = False
    unlit: bool = False
    base_color_map: GltfTexture | None = None
    metallic_roughness_map: GltfTexture | None = None
    normal_map: GltfTexture | None = None
    occlusion_map: GltfTexture | None = None
    emissive_map: GltfTexture | None = None
    # KHR_materials_ior, KHR_materials_specular, KHR_materials_clearcoat (their factors)
    ior: float = 1.5
    specular_factor: float = 1.0
    specular_color: tuple = (1.0, 1.0, 1.0)
    clearcoat: float = 0.0
    clearcoat_roughness: float = 0.0
    sheen_color: tuple = (0.0, 0.0, 0.0)  # KHR_materials_sheen
    sheen_roughness: float = 0.0
    anisotropy: float = 0.0  # KHR_materials_anisotropy: strength, and rotation in degrees
    anisotropy_rotation: float = 0.0
    iridescence: float = 0.0  # KHR_materials_iridescence: weight, film ior, thickness (nm)
    iridescence_ior: float = 1.3
    iridescence_thickness: float = 400.0
    iridescence_thickness_min: float = 100.0  # where the thickness texture is 0
    # the layers' textures (LAYER_TEXTURES: clearcoatTexture, clearcoatRoughnessTexture,
    # sheenColorTexture, sheenRoughnessTexture, specularTexture, specularColorTexture, ...)
    clearcoat_map: GltfTexture | None = None
    clearcoat_roughness_map: GltfTexture | None = None
    sheen_color_map: GltfTexture | None = None
    sheen_roughness_map: GltfTexture | None = None
    specular_factor_map: GltfTexture | None = None
    specular_color_map: GltfTexture | None = None
    specular_glossiness_map: GltfTexture | None = None  # KHR_materials_pbrSpecularGlossiness
    anisotropy_map: GltfTexture | None = None
    transmission_map: GltfTexture | None = None  # transmissionTexture, thicknessTexture
    thickness_map: GltfTexture | None = None
    clearcoat_normal_map: GltfTexture | None = None  # clearcoatNormalTexture (its scale in .scale)
    iridescence_map: GltfTexture | None = None  # iridescenceTexture, iridescenceThicknessTexture
    iridescence_thickness_map: GltfTexture | None = None
    # KHR_materials_transmission, KHR_materials_volume (their factors)
    transmission: float = 0.0
    thickness: float = 0.0
    attenuation_color: tuple = (1.0, 1.0, 1.0)
    attenuation_distance: float = float("inf")

    def textures(self) -> dict:
        """{map name: GltfTexture} of the maps it has."""
        names = ("base_color_map", "metallic_roughness_map", "normal_map", "occlusion_map", "emissive_map",
                 *LAYER_TEXTURES.values(), "specular_glossiness_map")
        return {name: getattr(self, name) for name in names if getattr(self, name) is not None}


@dataclass
class GltfFile:
    """What the renderer reads of a glTF file itself.

    materials:  GltfMaterial per material of the file, in file order, their names unique.
    slots:      per geometry trimesh makes, in its order: (material index or None, vertex
                count of POSITION, COLOR_0's componentType or None).
    images:     {key: encoded bytes} of the images the materials use.
    unsupported: notes for one warning (texture sets other than 0...).
    """

    materials: list = field(default_factory=list)
    slots: list = field(default_factory=list)
    images: dict = field(default_factory=dict)
    unsupported: list = field(default_factory=list)


class GltfSource(NamedTuple):
    """A glTF file split and checked once (split_glb), handed to every reader of it."""

    header: dict  # the JSON, validated into mesh.gltf_document's model
    binary: bytes | None  # the GLB's BIN chunk; None for a .gltf text file


def split_glb(raw: bytes) -> GltfSource:
    """(JSON header, BIN chunk or None) of a GLB container, or of a .gltf file's text.

    The root guard of every glTF reader: the JSON is read with bounded size and depth
    (json_input) and validated into mesh.gltf_document's model, so no reader after meets
    a part of the wrong type. Raises GltfStructureProblem where it fails."""
    if len(raw) >= 12 and struct.unpack_from("<I", raw, 0)[0] == GLB_MAGIC:
        offset, binary, header = 12, None, None
        while offset + 8 <= len(raw):
            length, kind = struct.unpack_from("<II", raw, offset)
            chunk = raw[offset + 8: offset + 8 + length]
            if kind == _JSON_CHUNK and header is None:
                header = _json(chunk)
            elif kind == _BIN_CHUNK and binary is None:
                binary = chunk
            offset += 8 + length + (-length % 4)
        if header is None:
            raise GltfStructureProblem("no JSON chunk")
        return GltfSource(header, binary)
    return GltfSource(_json(raw), None)


def _json(data: bytes) -> dict:
    if len(data) > GLTF_JSON_MAX_BYTES:
        raise GltfStructureProblem(f"its JSON is {len(data):,} bytes, over the limit of {GLTF_JSON_MAX_BYTES:,}")
    try:
        header = parse_json(data)
    except JsonProblem as exc:
        raise GltfStructureProblem(f"its JSON is {exc}") from None
    try:
        GltfDocument.model_validate(header)
    except ValidationError as exc:
        key, message = first_problem(exc, header)
        raise GltfStructureProblem(message, key) from None
    return header


def read_gltf(source: GltfSource, label: str, read_file, variant: str | None = None) -> GltfFile:
    """The materials, primitive slots and images of the glTF file ``source`` (split_glb).

    label: the file's name, prefixed to image keys. read_file(uri) -> bytes reads a file
    the glTF names (an external buffer or image), through the scene's asset policy.
    variant: a KHR_materials_variants name: the primitives use its materials.
    Raises GltfProblem for anything unusable."""
    header, binary = source
    result = GltfFile()
    used = header.get("extensionsUsed", [])
    for extension in used if isinstance(used, list) else ():
        if isinstance(extension, str) and extension not in READ_EXTENSIONS:
            result.unsupported.append(f"extension {extension} is not supported: drawn without it")
    names: dict[str, int] = {}
    materials = _list(header, "materials")
    for index, material in enumerate(materials):
        name = _unique(_text(material.get("name")) or f"material{index}", names)
        result.materials.append(_material(name, json_object(material, f"materials[{index}]"), header, result, label))
    for mesh_index, mesh in enumerate(_list(header, "meshes")):
        for primitive in _list(json_object(mesh, f"meshes[{mesh_index}]"), "primitives"):
            primitive = json_object(primitive, "a primitive")
            mode = primitive.get("mode", 4)
            if mode not in _GEOMETRY_MODES:
                continue
            attributes = json_object(primitive.get("attributes", {}), "a primitive's attributes")
            count = _accessor_count(header, attributes.get("POSITION"))
            material = primitive_material(primitive, header, variant) if mode in _TRIANGLE_MODES else None
            if material is not None and not (is_index(material) and material < len(materials)):
                raise GltfProblem(f"a primitive names material {material!r}, the file has {len(materials)}")
            color = attributes.get("COLOR_0")
            color_type = _accessor(header, color).get("componentType") if color is not None else None
            result.slots.append((material, count, color_type))
    _load_images(header, binary, result, label, read_file)
    return result


def file_extension_list(header: dict, extension: str, key: str) -> list:
    """The list ``key`` of the file-level ``extension`` (KHR_lights_punctual's lights,
    KHR_materials_variants' variants): empty where the file has none. Raises GltfProblem
    where the extension is no object or the list no list."""
    found = json_object(json_object(header.get("extensions", {}), "extensions").get(extension, {}), extension)
    values = found.get(key, [])
    if not isinstance(values, list):
        raise GltfProblem(f"{extension}.{key} is not a list")
    return values


def variant_names(header: dict) -> list[str]:
    """The names of the file's KHR_materials_variants, in its order (empty without any)."""
    variants = file_extension_list(header, VARIANTS_EXTENSION, "variants")
    return [_text(json_object(v, "a variant").get("name")) or f"variant{i}" for i, v in enumerate(variants)]


def primitive_material(primitive: dict, header: dict, variant: str | None):
    """The material index ``primitive`` uses: its own ``material``, or, under ``variant``
    (a name of ``variant_names``), the one its KHR_materials_variants mappings give that
    variant (its own where no mapping names it)."""
    material = primitive.get("material")
    if variant is None:
        return material
    index = variant_names(header).index(variant)
    extension = json_object(json_object(primitive.get("extensions", {}), "a primitive's extensions").get(
        VARIANTS_EXTENSION, {}), f"a primitive's {VARIANTS_EXTENSION}")
    for mapping in _list(extension, "mappings"):
        mapping = json_object(mapping, f"a {VARIANTS_EXTENSION} mapping")
        if index in _list(mapping, "variants"):
            return mapping.get("material")
    return material


def vertex_colors(visual, component_type, vertex_count: int):
    """(N, 4) float linear RGBA of a primitive's COLOR_0 as trimesh kept it, or None.

    trimesh keeps the accessor's raw values where the primitive has a material
    (``visual.vertex_attributes['color']``) and 8-bit colours where it has none."""
    attributes = getattr(visual, "vertex_attributes", None)
    raw = attributes["color"] if attributes is not None and "color" in attributes else None
    scale = _NORMALIZED.get(component_type, 1.0)
    if raw is None and getattr(visual, "kind", None) == "vertex":
        raw, scale = visual.vertex_colors, 255.0
    if raw is None:
        return None
    return rgba_colors(np.asarray(raw, dtype=np.float64) / scale, vertex_count)


def rgba_colors(colors: np.ndarray, vertex_count: int):
    """(N, 4) RGBA in [0, 1] of COLOR_0 values already in [0, 1] units (N, 3 or 4), or None
    where they are not one finite colour per vertex."""
    colors = np.asarray(colors, dtype=np.float64)
    if colors.ndim != 2 or colors.shape[1] not in (3, 4) or len(colors) != vertex_count:
        return None
    if colors.shape[1] == 3:
        colors = np.hstack([colors, np.ones((len(colors), 1))])
    if not np.isfinite(colors).all():
        return None
    return np.clip(colors, 0.0, 1.0)


# -- materials ------------------------------------------------------------------------------

def _material(name: str, material: dict, header: dict, result: GltfFile, label: str) -> GltfMaterial:
    pbr = json_object(material.get("pbrMetallicRoughness", {}), f"material {name!r}: pbrMetallicRoughness")
    extensions = json_object(material.get("extensions", {}), f"material {name!r}: extensions")
    strength = json_object(extensions.get("KHR_materials_emissive_strength", {}), "KHR_materials_emissive_strength")
    alpha_mode = material.get("alphaMode", "OPAQUE")
    if alpha_mode not in ("OPAQUE", "MASK", "BLEND"):
        raise GltfProblem(f"material {name!r}: alphaMode {alpha_mode!r} is not OPAQUE, MASK or BLEND")
    textures = {
        "base_color_map": _texture(pbr.get("baseColorTexture"), header, result, label, "baseColorTexture"),
        "metallic_roughness_map": _texture(pbr.get("metallicRoughnessTexture"), header, result, label,
                                           "metallicRoughnessTexture"),
        "normal_map": _texture(material.get("normalTexture"), header, result, label, "normalTexture", "scale"),
        "occlusion_map": _texture(material.get("occlusionTexture"), header, result, label, "occlusionTexture",
                                  "strength"),
        "emissive_map": _texture(material.get("emissiveTexture"), header, result, label, "emissiveTexture"),
    }
    fields = dict(
        base_color=_numbers(pbr.get("baseColorFactor", (1.0, 1.0, 1.0, 1.0)), 4, "baseColorFactor", 0.0, 1.0),
        metallic=_numbers([pbr.get("metallicFactor", 1.0)], 1, "metallicFactor", 0.0, 1.0)[0],
        roughness=_numbers([pbr.get("roughnessFactor", 1.0)], 1, "roughnessFactor", 0.0, 1.0)[0],
        **_layers(name, extensions, header, result, label),
        **textures,
    )
    if SPECULAR_GLOSSINESS in extensions:  # the specification: it takes the place of pbrMetallicRoughness
        fields.update(_specular_glossiness(
            json_object(extensions[SPECULAR_GLOSSINESS], f"material {name!r}: {SPECULAR_GLOSSINESS}"),
            header, result, label))
    return GltfMaterial(
        name=name,
        emissive=_numbers(material.get("emissiveFactor", (0.0, 0.0, 0.0)), 3, "emissiveFactor", 0.0, 1.0),
        emissive_strength=_numbers([strength.get("emissiveStrength", 1.0)], 1, "emissiveStrength", 0.0, 1e6)[0],
        alpha_mode=alpha_mode.lower(),
        alpha_cutoff=_numbers([material.get("alphaCutoff", 0.5)], 1, "alphaCutoff", 0.0, 1e6)[0],
        double_sided=_bool(material.get("doubleSided", False), "doubleSided"),
        unlit="KHR_materials_unlit" in extensions,
        **_transmission(name, extensions),
        **fields,
    )


def _specular_glossiness(values: dict, header: dict, result: GltfFile, label: str) -> dict:
    """The GltfMaterial fields of KHR_materials_pbrSpecularGlossiness, as the metallic-roughness
    model with KHR_materials_specular, exactly: its BRDF inputs c_diff = diffuse (1 -
    max(specular)), F0 = specular, alpha = (1 - glossiness)^2 (F90 1) are those of metallic 0,
    base colour c_diff, roughness 1 - glossiness, ior 1.5 and specular colour specular / 0.04
    (F0 = min(0.04 specular colour, 1) specular factor = specular, F90 = specular factor = 1).
    diffuseTexture is the base colour texture. specularGlossinessTexture is the
    specular_glossiness_map, which the shading applies per texel (F0 = its rgb times the
    specular colour's F0, roughness = 1 - (1 - roughness) times its alpha, the base times
    1 - max(F0)): the base colour is then the diffuse factor alone."""
    diffuse = _numbers(values.get("diffuseFactor", (1.0, 1.0, 1.0, 1.0)), 4, "diffuseFactor", 0.0, 1.0)
    specular = _numbers(values.get("specularFactor", (1.0, 1.0, 1.0)), 3, "specularFactor", 0.0, 1.0)
    glossiness = _numbers([values.get("glossinessFactor", 1.0)], 1, "glossinessFactor", 0.0, 1.0)[0]
    specular_glossiness = _texture(values.get("specularGlossinessTexture"), header, result, label,
                                   "specularGlossinessTexture")
    through = 1.0 if specular_glossiness is not None else 1.0 - max(specular)
    return {
        "base_color": (*(c * through for c in diffuse[:3]), diffuse[3]),
        "metallic": 0.0, "roughness": 1.0 - glossiness,
        "ior": 1.5, "specular_factor": 1.0, "specular_color": tuple(c / _DIELECTRIC_F0 for c in specular),
        "base_color_map": _texture(values.get("diffuseTexture"), header, result, label, "diffuseTexture"),
        "metallic_roughness_map": None, "specular_glossiness_map": specular_glossiness,
    }


# the layer extensions' textures: (extension, its key) -> the GltfMaterial map
LAYER_TEXTURES = {("KHR_materials_specular", "specularTexture"): "specular_factor_map",
                  ("KHR_materials_specular", "specularColorTexture"): "specular_color_map",
                  ("KHR_materials_clearcoat", "clearcoatTexture"): "clearcoat_map",
                  ("KHR_materials_clearcoat", "clearcoatRoughnessTexture"): "clearcoat_roughness_map",
                  ("KHR_materials_clearcoat", "clearcoatNormalTexture"): "clearcoat_normal_map",
                  ("KHR_materials_sheen", "sheenColorTexture"): "sheen_color_map",
                  ("KHR_materials_sheen", "sheenRoughnessTexture"): "sheen_roughness_map",
                  ("KHR_materials_anisotropy", "anisotropyTexture"): "anisotropy_map",
                  ("KHR_materials_transmission", "transmissionTexture"): "transmission_map",
                  ("KHR_materials_volume", "thicknessTexture"): "thickness_map",
                  ("KHR_materials_iridescence", "iridescenceTexture"): "iridescence_map",
                  ("KHR_materials_iridescence", "iridescenceThicknessTexture"): "iridescence_thickness_map"}


def _layers(name: str, extensions: dict, header: dict, result: GltfFile, label: str) -> dict:
    """The GltfMaterial fields of KHR_materials_ior, _specular, _clearcoat, _sheen,
    _anisotropy and _iridescence (glTF's defaults where absent), their textures included,
    and the textures of _transmission and _volume (LAYER_TEXTURES). An ior of 0 is the specification's
    "infinitely high" index (a dielectric that reflects all), taken here as the largest the
    scene format takes."""
    ior = json_object(extensions.get("KHR_materials_ior", {}), f"material {name!r}: KHR_materials_ior")
    specular = json_object(extensions.get("KHR_materials_specular", {}), f"material {name!r}: KHR_materials_specular")
    coat = json_object(extensions.get("KHR_materials_clearcoat", {}), f"material {name!r}: KHR_materials_clearcoat")
    sheen = json_object(extensions.get("KHR_materials_sheen", {}), f"material {name!r}: KHR_materials_sheen")
    anisotropy = json_object(extensions.get("KHR_materials_anisotropy", {}),
                             f"material {name!r}: KHR_materials_anisotropy")
    iridescence = json_object(extensions.get("KHR_materials_iridescence", {}),
                              f"material {name!r}: KHR_materials_iridescence")
    values = {"KHR_materials_specular": specular, "KHR_materials_clearcoat": coat, "KHR_materials_sheen": sheen,
              "KHR_materials_anisotropy": anisotropy, "KHR_materials_iridescence": iridescence}
    values.update({extension: json_object(extensions.get(extension, {}), f"material {name!r}: {extension}")
                   for extension in ("KHR_materials_transmission", "KHR_materials_volume")})
    maps = {field: _texture(values[extension].get(key), header, result, label, key,
                            "scale" if key == "clearcoatNormalTexture" else None)
            for (extension, key), field in LAYER_TEXTURES.items()}
    index = _numbers([ior.get("ior", 1.5)], 1, "ior", 0.0, MAX_IOR)[0]
    return {
        **maps,
        "ior": MAX_IOR if index == 0.0 else max(index, 1.0),
        "specular_factor": _numbers([specular.get("specularFactor", 1.0)], 1, "specularFactor", 0.0, 1.0)[0],
        "specular_color": _numbers(specular.get("specularColorFactor", (1.0, 1.0, 1.0)), 3, "specularColorFactor",
                                   0.0, 1e6),
        "clearcoat": _numbers([coat.get("clearcoatFactor", 0.0)], 1, "clearcoatFactor", 0.0, 1.0)[0],
        "clearcoat_roughness": _numbers([coat.get("clearcoatRoughnessFactor", 0.0)], 1, "clearcoatRoughnessFactor",
                                        0.0, 1.0)[0],
        "sheen_color": _numbers(sheen.get("sheenColorFactor", (0.0, 0.0, 0.0)), 3, "sheenColorFactor", 0.0, 1.0),
        "sheen_roughness": _numbers([sheen.get("sheenRoughnessFactor", 0.0)], 1, "sheenRoughnessFactor", 0.0, 1.0)[0],
        "anisotropy": _numbers([anisotropy.get("anisotropyStrength", 0.0)], 1, "anisotropyStrength", 0.0, 1.0)[0],
        "anisotropy_rotation": math.degrees(_numbers([anisotropy.get("anisotropyRotation", 0.0)], 1,
                                                     "anisotropyRotation", -1e6, 1e6)[0]) % 360.0,
        "iridescence": _numbers([iridescence.get("iridescenceFactor", 0.0)], 1, "iridescenceFactor", 0.0, 1.0)[0],
        "iridescence_ior": _numbers([iridescence.get("iridescenceIor", 1.3)], 1, "iridescenceIor", 1.0, MAX_IOR)[0],
        # the film's thickness without a thickness texture (the specification); with one,
        # mix(minimum, maximum, its green)
        "iridescence_thickness": _numbers([iridescence.get("iridescenceThicknessMaximum", 400.0)], 1,
                                          "iridescenceThicknessMaximum", 0.0, 10000.0)[0],
        "iridescence_thickness_min": _numbers([iridescence.get("iridescenceThicknessMinimum", 100.0)], 1,
                                              "iridescenceThicknessMinimum", 0.0, 10000.0)[0],
    }


def _transmission(name: str, extensions: dict) -> dict:
    """The GltfMaterial fields of KHR_materials_transmission and KHR_materials_volume
    (glTF's defaults where absent: no transmission, thin-walled, no attenuation), their
    textures aside (_layers reads them). The volume's thickness is read in the scene's units."""
    values = {extension: json_object(extensions.get(extension, {}), f"material {name!r}: {extension}")
              for extension in ("KHR_materials_transmission", "KHR_materials_volume")}
    transmission, volume = values["KHR_materials_transmission"], values["KHR_materials_volume"]
    distance = volume.get("attenuationDistance")
    return {
        "transmission": _numbers([transmission.get("transmissionFactor", 0.0)], 1, "transmissionFactor", 0.0, 1.0)[0],
        "thickness": _numbers([volume.get("thicknessFactor", 0.0)], 1, "thicknessFactor", 0.0, 1e6)[0],
        "attenuation_color": _numbers(volume.get("attenuationColor", (1.0, 1.0, 1.0)), 3, "attenuationColor", 0.0, 1.0),
        "attenuation_distance": float("inf") if distance is None else _numbers([distance], 1, "attenuationDistance",
                                                                               1e-9, 1e30)[0],
    }


def _texture(info, header: dict, result: GltfFile, label: str, what: str, scale_key: str | None = None):
    if info is None:
        return None
    info = json_object(info, what)
    index = info.get("index")
    textures = _list(header, "textures")
    if not (is_index(index) and index < len(textures)):
        raise GltfProblem(f"{what} names texture {index!r}, the file has {len(textures)}")
    texture = json_object(textures[index], f"textures[{index}]")
    source = texture.get("source")
    image = None
    if source is not None:
        if not (is_index(source) and source < len(_list(header, "images"))):
            raise GltfProblem(f"textures[{index}] names image {source!r}")
        image = f"{label}#image{source}"
    sampler = {}
    if texture.get("sampler") is not None:
        samplers = _list(header, "samplers")
        if not (is_index(texture["sampler"]) and texture["sampler"] < len(samplers)):
            raise GltfProblem(f"textures[{index}] names sampler {texture['sampler']!r}")
        sampler = json_object(samplers[texture["sampler"]], "a sampler")
    tex_coord = info.get("texCoord", 0)
    transform = json_object(json_object(info.get("extensions", {}), f"{what}: extensions").get("KHR_texture_transform", {}),
                        "KHR_texture_transform")
    tex_coord = transform.get("texCoord", tex_coord)
    if not is_index(tex_coord):
        raise GltfProblem(f"{what}: texCoord {tex_coord!r}")
    if tex_coord > 1:
        note = f"texture coordinate set {tex_coord} (sets 0 and 1 are read; it reads set 0)"
        if note not in result.unsupported:
            result.unsupported.append(note)
    scale, offset, skew = _uv_affine(transform)
    return GltfTexture(
        image=image, uv_scale=scale, uv_offset=offset, uv_skew=skew,
        scale=_numbers([info.get(scale_key, 1.0)], 1, f"{what}.{scale_key}", -1e6, 1e6)[0] if scale_key else 1.0,
        wrap=_WRAP.get(sampler.get("wrapS", 10497), "repeat"),
        nearest=sampler.get("magFilter") in _NEAREST_FILTERS, tex_coord=tex_coord if tex_coord <= 1 else 0)


def _uv_affine(transform: dict) -> tuple:
    """KHR_texture_transform (uv' = T R S uv in glTF's v-down coordinates) as the affine map
    of GL coordinates (v_gl = 1 - v): (scale (diagonal), offset, skew (off-diagonal))."""
    sx, sy = _numbers(transform.get("scale", (1.0, 1.0)), 2, "KHR_texture_transform.scale", -1e6, 1e6)
    ox, oy = _numbers(transform.get("offset", (0.0, 0.0)), 2, "KHR_texture_transform.offset", -1e6, 1e6)
    rotation = _numbers([transform.get("rotation", 0.0)], 1, "KHR_texture_transform.rotation", -1e6, 1e6)[0]
    c, s = math.cos(rotation), math.sin(rotation)
    a00, a01, a10, a11 = c * sx, s * sy, -s * sx, c * sy
    # flip v on both sides: A_gl = F A F with F = diag(1, -1); o_gl = F o + e - A_gl e, e = (0, 1)
    g00, g01, g10, g11 = a00, -a01, -a10, a11
    return (g00, g11), (ox - g01, 1.0 - oy - g11), (g01, g10)


# -- images ---------------------------------------------------------------------------------

def _load_images(header: dict, binary: bytes | None, result: GltfFile, label: str, read_file) -> None:
    """The encoded bytes of each image a material uses, into ``result.images``; an image
    that cannot be had is left out (its textures draw the placeholder)."""
    used = {texture.image for material in result.materials for texture in material.textures().values()
            if texture.image is not None}
    images = _list(header, "images")
    buffers: dict = {}
    for key in sorted(used):
        index = int(key.rsplit("#image", 1)[1])
        image = json_object(images[index], f"images[{index}]")
        try:
            if image.get("bufferView") is not None:
                data = bytes(buffer_view_bytes(header, image["bufferView"], binary, buffers, read_file)[0])
            elif isinstance(image.get("uri"), str):
                data = _uri_bytes(image["uri"], read_file)
            else:
                continue
        except FileNotFoundError:
            continue
        result.images[key] = data


def buffer_view_bytes(header: dict, index, binary, buffers: dict, read_file) -> tuple[memoryview, int | None]:
    """(the bytes of bufferView ``index``, its byteStride or None); ``buffers`` caches the
    buffers read, by index."""
    views = _list(header, "bufferViews")
    if not (is_index(index) and index < len(views)):
        raise GltfProblem(f"a reference to bufferView {index!r}, the file has {len(views)}")
    view = json_object(views[index], f"bufferViews[{index}]")
    buffer_index = view.get("buffer")
    all_buffers = _list(header, "buffers")
    if not (is_index(buffer_index) and buffer_index < len(all_buffers)):
        raise GltfProblem(f"bufferViews[{index}] names buffer {buffer_index!r}")
    if buffer_index not in buffers:
        uri = json_object(all_buffers[buffer_index], "a buffer").get("uri")
        if uri is None:
            if binary is None:
                raise GltfProblem(f"buffers[{buffer_index}] has no uri and the file no BIN chunk")
            buffers[buffer_index] = binary
        else:
            buffers[buffer_index] = _uri_bytes(_text(uri) or "", read_file)
    start, length = view.get("byteOffset", 0), view.get("byteLength")
    data = buffers[buffer_index]
    if not (is_index(start) and is_index(length) and start + length <= len(data)):
        raise GltfProblem(f"bufferViews[{index}] reaches past its buffer")
    stride = view.get("byteStride")
    if stride is not None and not (is_index(stride) and 4 <= stride <= 252):
        raise GltfProblem(f"bufferViews[{index}] has byteStride {stride!r}")
    return memoryview(data)[start: start + length], stride


def _uri_bytes(uri: str, read_file) -> bytes:
    if uri.startswith("data:"):
        head, _, payload = uri.partition(",")
        try:
            return base64.b64decode(payload, validate=False) if head.endswith(";base64") else payload.encode()
        except ValueError:
            raise GltfProblem("a data URI is not base64") from None
    return read_file(unquote(uri))


# -- checked JSON values ----------------------------------------------------------------------

def _accessor(header: dict, index) -> dict:
    accessors = _list(header, "accessors")
    if not (is_index(index) and index < len(accessors)):
        raise GltfProblem(f"a primitive names accessor {index!r}, the file has {len(accessors)}")
    return json_object(accessors[index], f"accessors[{index}]")


def _accessor_count(header: dict, index) -> int:
    count = _accessor(header, index).get("count")
    if not is_index(count):
        raise GltfProblem(f"accessors[{index}] has count {count!r}")
    return count


def _list(container: dict, key: str) -> list:
    value = container.get(key, [])
    if not isinstance(value, list):
        raise GltfProblem(f"'{key}' is not a list")
    return value


def json_object(value, what: str) -> dict:
    """``value`` where it is a JSON object (a dict); else a GltfProblem naming ``what``."""
    if not isinstance(value, dict):
        raise GltfProblem(f"{what} is not an object")
    return value


def is_index(value) -> bool:
    """Whether ``value`` is a whole number that can index a glTF array (not a bool)."""
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _text(value) -> str | None:
    return value if isinstance(value, str) and value.strip() else None


def _bool(value, what: str) -> bool:
    if not isinstance(value, bool):
        raise GltfProblem(f"{what} is not true or false")
    return value


def _numbers(values, count: int, what: str, lo: float, hi: float) -> tuple:
    """``count`` finite numbers, clamped to [lo, hi] (glTF's ranges are [0, 1] for colours)."""
    if not isinstance(values, (list, tuple)) or len(values) != count:
        raise GltfProblem(f"{what} is not {count} number(s)")
    out = []
    for value in values:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise GltfProblem(f"{what} holds {value!r}, not a finite number")
        out.append(min(max(float(value), lo), hi))
    return tuple(out)


def _unique(name: str, seen: dict) -> str:
    """``name``, or ``name.2``, ``name.3``... where the file used it already."""
    if name not in seen:
        seen[name] = 1
        return name
    seen[name] += 1
    candidate = f"{name}.{seen[name]}"
    while candidate in seen:
        seen[name] += 1
        candidate = f"{name}.{seen[name]}"
    seen[candidate] = 1
    return candidate

