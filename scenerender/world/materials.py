"""Materials as the renderer uses them: MTL values, scene materials and overrides merged.

Precedence, lowest first: built-in defaults, the MTL file, the object's ``material``
(which replaces the MTL materials entirely), then ``material_overrides[mtl_name]``.

Shading (see shaders/lighting): with base = Kd * map_Kd,
  colour = La * Ka * base + sum over lights of (Ld * base * N.L + Ls * Ks * map_Ks * spec) + Ke
so Ka scales how much ambient light the surface colour receives (1 = all of it). The
``pbr`` model reads the same base colour (Kd is glTF's baseColorFactor) with ``metallic``
and ``roughness`` instead of Ks and Ns (docs/scene-notes.md, "The pbr model").

A glTF file's material (mesh.gltf.GltfMaterial) takes the MTL's place in the precedence.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from scenerender.animation import Track, shared_constant
from scenerender.errors import SourceLocation
from scenerender.mesh.gltf import GltfMaterial

DEFAULTS = {
    "ambient": (1.0, 1.0, 1.0, 1.0),
    "diffuse": (0.8, 0.8, 0.8, 1.0),
    "specular": (0.25, 0.25, 0.25, 1.0),
    "emissive": (0.0, 0.0, 0.0, 1.0),
    "shininess": 32.0,
    "opacity": 1.0,
    "metallic": 0.0,
    "roughness": 0.5,
}
COLOR_KEYS = ("ambient", "diffuse", "specular", "emissive")
SCALAR_KEYS = ("shininess", "opacity", "metallic", "roughness")
# the maps a material may have; diffuse_map is also the pbr model's base colour map. The
# roughness and metallic maps (MTL map_Pr, map_Pm) are single-channel (red); the
# metallic_roughness map is glTF's (blue = metallic, green = roughness).
MAP_KEYS = ("diffuse_map", "specular_map", "normal_map", "opacity_map", "metallic_roughness_map", "occlusion_map",
            "emissive_map", "roughness_map", "metallic_map")
# the pbr layers' maps (glTF's KHR_materials_clearcoat, _sheen and _specular textures): each
# multiplies its layer's factor by one channel (clearcoat red, clearcoat_roughness green,
# sheen_roughness and specular_factor alpha) or by its colour (sheen_color, specular_color);
# specular_glossiness is KHR_materials_pbrSpecularGlossiness's texture (mesh.gltf); anisotropy's
# red and green are a direction in the tangent frame (0..1 for -1..1), blue its strength;
# KHR_materials_transmission's red multiplies transmission, KHR_materials_volume's green thickness;
# KHR_materials_iridescence's red multiplies iridescence, its thickness map's green mixes the
# film's thickness from iridescence_thickness_min to iridescence_thickness; clearcoat_normal is
# the coat's own tangent-space normal map (KHR_materials_clearcoat clearcoatNormalTexture)
LAYER_MAP_KEYS = ("clearcoat_map", "clearcoat_roughness_map", "sheen_color_map", "sheen_roughness_map",
                  "specular_factor_map", "specular_color_map", "specular_glossiness_map", "anisotropy_map",
                  "transmission_map", "thickness_map", "iridescence_map", "iridescence_thickness_map",
                  "clearcoat_normal_map")
MAP_KEYS += LAYER_MAP_KEYS
# the maps that change the dielectric's F0 (PBR_DIELECTRIC_SPECULAR)
SPECULAR_MAPS = ("specular_factor_map", "specular_color_map", "specular_glossiness_map")
# Colour maps hold sRGB-encoded colours; the others hold plain data.
SRGB_MAPS = {"diffuse_map": True, "specular_map": True, "normal_map": False, "opacity_map": False,
             "metallic_roughness_map": False, "occlusion_map": False, "emissive_map": True, "roughness_map": False,
             "metallic_map": False,
             "clearcoat_map": False, "clearcoat_roughness_map": False, "sheen_color_map": True,
             "sheen_roughness_map": False, "specular_factor_map": False, "specular_color_map": True,
             "specular_glossiness_map": True, "anisotropy_map": False, "transmission_map": False,
             "thickness_map": False, "iridescence_map": False, "iridescence_thickness_map": False,
             "clearcoat_normal_map": False}
# a scene's key for a map, where it is not the map's own name
SPEC_MAP_ALIASES = {"base_color_map": "diffuse_map"}
SHADINGS = ("phong", "blinn_phong", "pbr", "unlit")
# the pbr model's layer values, alike in glTF materials, scene materials and Material
LAYER_KEYS = ("ior", "specular_factor", "specular_color", "clearcoat", "clearcoat_roughness", "sheen_color",
              "sheen_roughness")
LAYER_KEYS += ("anisotropy", "anisotropy_rotation")  # KHR_materials_anisotropy
LAYER_KEYS += ("iridescence", "iridescence_ior", "iridescence_thickness",  # KHR_materials_iridescence
               "iridescence_thickness_min")
# light through the surface and its volume (KHR_materials_transmission, KHR_materials_volume)
TRANSMISSION_KEYS = ("transmission", "thickness", "attenuation_color", "attenuation_distance")


@dataclass(frozen=True)
class TextureSource:
    """A texture a material samples.

    path:      the image file, or None for the placeholder (a texture that could not be read).
    srgb:      decode as sRGB (colour maps) or read values as they are (data maps).
    uv_scale, uv_offset: (2,) float, from MTL ``-s`` / ``-o``.
    uv_skew:   (2,) float, the off-diagonal terms of a rotated texture transform (glTF's
               ``KHR_texture_transform``): coordinates become
               ``(s.x u + k.x v + o.x, k.y u + s.y v + o.y)``.
    strength:  bump multiplier (MTL ``-bm``; the coat's normal map: glTF's ``scale``), normal maps only.
    embedded:  the image is held by the mesh file (a glTF), keyed by ``path``, which names no
               file; it was decoded with the mesh.
    uv_set:    the mesh's texture coordinates it reads: 0 (``uvs``) or 1 (``uvs1``, glTF
               ``texCoord: 1``).
    mtl_location: the MTL file and line that named it (None when the scene named it). An
               unreadable texture an MTL names becomes the placeholder with a warning.
    scene_key: the scene's key path that named it, e.g. ("materials", "stone", "diffuse_map");
               an unreadable texture the scene names is an error there.
    """

    path: Path | None
    srgb: bool
    uv_scale: tuple = (1.0, 1.0)
    uv_offset: tuple = (0.0, 0.0)
    strength: float = 1.0
    mtl_location: SourceLocation | None = None
    scene_key: tuple | None = None
    uv_skew: tuple = (0.0, 0.0)
    embedded: bool = False
    uv_set: int = 0

    @property
    def is_placeholder(self) -> bool:
        return self.path is None


@dataclass
class Material:
    """One resolved material; colours are RGBA Tracks in linear [0, 1].

    shading:     "phong" | "blinn_phong" | "pbr" | "unlit", or None for ``render.shading``
                 (see ``model``); a glTF material is "pbr".
    metallic, roughness: the pbr model's factors (Tracks of floats in [0, 1]).
    emissive_strength: multiplies ``emissive`` (glTF's KHR_materials_emissive_strength).
    normal_scale: multiplies the normal map's tangent-plane part (glTF normalTexture.scale).
    occlusion_strength: how much the occlusion map darkens ambient light (0 none, 1 all).
    alpha_mode:  "auto" (transparent when anything makes alpha below 1), or glTF's
                 "opaque" (alpha ignored), "mask" (pixels below ``alpha_cutoff`` cut
                 away, the rest opaque) or "blend" (the transparent pass).
    double_sided: both faces drawn and lit; False: back faces are not drawn (glTF).
    vertex_colors: the mesh's vertex colours multiply the base colour.
    """

    name: str
    ambient: Track
    diffuse: Track
    specular: Track
    emissive: Track
    shininess: Track
    opacity: Track
    maps: dict = field(default_factory=dict)  # key in MAP_KEYS -> TextureSource
    wrap: str = "repeat"
    filter: str = "linear"
    unlit: bool = False
    shading: str | None = None
    metallic: Track = field(default_factory=lambda: shared_constant(DEFAULTS["metallic"]))
    roughness: Track = field(default_factory=lambda: shared_constant(DEFAULTS["roughness"]))
    emissive_strength: float = 1.0
    normal_scale: float = 1.0
    occlusion_strength: float = 1.0
    alpha_mode: str = "auto"
    alpha_cutoff: float = 0.5
    double_sided: bool = True
    vertex_colors: bool = False
    # the pbr model's layers (docs/scene-notes.md, "Layers of the pbr model"); glTF's
    # defaults draw as the model always has
    ior: float = 1.5
    specular_factor: float = 1.0
    specular_color: tuple = (1.0, 1.0, 1.0)
    clearcoat: float = 0.0
    clearcoat_roughness: float = 0.0
    sheen_color: tuple = (0.0, 0.0, 0.0)
    sheen_roughness: float = 0.0
    # KHR_materials_anisotropy: its strength, and its direction in degrees from the tangent
    # towards the bitangent
    anisotropy: float = 0.0
    anisotropy_rotation: float = 0.0
    # KHR_materials_iridescence: its weight, the thin film's index of refraction and
    # thickness in nanometres
    iridescence: float = 0.0
    iridescence_ior: float = 1.3
    iridescence_thickness: float = 400.0
    iridescence_thickness_min: float = 100.0  # the thickness map's 0 (its 1 is iridescence_thickness)
    # light through it (docs/scene-notes.md, "Transmission and volume"): the share of the
    # diffuse part that passes through; a volume's thickness (0: thin-walled) and its
    # Beer-Lambert colour reached after attenuation_distance (inf: clear)
    transmission: float = 0.0
    thickness: float = 0.0
    attenuation_color: tuple = (1.0, 1.0, 1.0)
    attenuation_distance: float = float("inf")

    @property
    def transmissive(self) -> bool:
        """Light passes through it (``transmission`` above 0): drawn in the transparent pass
        over a copy of the opaque scene (rendering/passes/transmission.py)."""
        return self.transmission > 0.0

    @property
    def sheen(self) -> bool:
        """It has a sheen (a sheen colour other than black)."""
        return max(self.sheen_color) > 0.0

    @property
    def layered(self) -> bool:
        """It has any of the pbr model's layers."""
        return (self.dielectric_specular or self.clearcoat > 0.0 or self.sheen or self.anisotropy > 0.0
                or self.iridescence > 0.0 or self.transmissive)

    @property
    def needs_tangents(self) -> bool:
        """It reads the mesh's tangent frame: a normal map (the coat's too), or an anisotropy's
        direction."""
        return "normal_map" in self.maps or "clearcoat_normal_map" in self.maps or self.anisotropy > 0.0

    def anisotropy_direction(self) -> tuple[float, float]:
        """(cos, sin) of ``anisotropy_rotation``: the direction in the tangent frame."""
        angle = np.radians(self.anisotropy_rotation)
        return float(np.cos(angle)), float(np.sin(angle))

    @property
    def dielectric_specular(self) -> bool:
        """Its dielectric reflection differs from the model's F0 0.04, F90 1 (an ior other
        than 1.5, a specular factor or colour other than 1, or a map of either)."""
        return (self.ior != 1.5 or self.specular_factor != 1.0
                or tuple(self.specular_color) != (1.0, 1.0, 1.0)
                or any(key in self.maps for key in SPECULAR_MAPS))

    def dielectric_reflectance(self) -> np.ndarray:
        """(3,) ((ior - 1) / (ior + 1))^2 specular_color: F0 before the clamp and the specular
        factor, which a specular colour map multiplies first."""
        return ((self.ior - 1.0) / (self.ior + 1.0)) ** 2 * np.asarray(self.specular_color, dtype=np.float64)

    def dielectric_f0_f90(self) -> tuple[np.ndarray, float]:
        """((3,) F0, F90) of the dielectric part: KHR_materials_specular's
        min(((ior - 1) / (ior + 1))^2 specular_color, 1) specular_factor, and specular_factor."""
        reflectance = ((self.ior - 1.0) / (self.ior + 1.0)) ** 2
        f0 = np.minimum(reflectance * np.asarray(self.specular_color, dtype=np.float64), 1.0) * self.specular_factor
        return f0, float(self.specular_factor)

    def model(self, scene_shading: str) -> str:
        """The shading model this material is drawn with: "unlit" when ``unlit``, else its
        own ``shading``, else the scene's ``render.shading``."""
        if self.unlit:
            return "unlit"
        return self.shading or scene_shading

    @property
    def transparent(self) -> bool:
        """Drawn in the transparent pass: blended (``blended``), or transmissive, seeing
        what the opaque pass drew behind it."""
        return self.transmissive or self.blended

    @property
    def blended(self) -> bool:
        """Blended over what lies behind by its alpha: alpha mode "blend"; or, with "auto",
        opacity below 1 at any time, an opacity map, or a base colour alpha below 1."""
        if self.alpha_mode != "auto":
            return self.alpha_mode == "blend"
        if "opacity_map" in self.maps:
            return True
        if float(np.min(self.opacity.values)) < 1.0:
            return True
        return float(np.min(self.diffuse.values[:, 3])) < 1.0

    @property
    def masked(self) -> bool:
        """Pixels whose alpha is below ``alpha_cutoff`` are cut away (glTF MASK)."""
        return self.alpha_mode == "mask"


def _color_track(rgb_or_rgba) -> Track:
    values = tuple(float(v) for v in rgb_or_rgba)
    if len(values) == 3:
        values += (1.0,)
    return shared_constant(values, kind="vector")


def default_material(name: str = "default") -> Material:
    return Material(
        name=name,
        ambient=_color_track(DEFAULTS["ambient"]),
        diffuse=_color_track(DEFAULTS["diffuse"]),
        specular=_color_track(DEFAULTS["specular"]),
        emissive=_color_track(DEFAULTS["emissive"]),
        shininess=shared_constant(float(DEFAULTS["shininess"])),
        opacity=shared_constant(float(DEFAULTS["opacity"])),
    )


def apply_mtl(material: Material, mtl) -> Material:
    """Material with the values an ``MtlMaterial`` sets (None fields keep the default).
    An MTL material with any of the PBR statements (Pr, Pm, map_Pr, map_Pm) is a ``pbr``
    material."""
    for key in COLOR_KEYS:
        value = getattr(mtl, key, None)
        if value is not None:
            setattr(material, key, _color_track(value))
    if mtl.shininess is not None:
        material.shininess = Track.constant(float(mtl.shininess))
    if mtl.opacity is not None:
        material.opacity = Track.constant(float(min(max(mtl.opacity, 0.0), 1.0)))
    if mtl.illum == 0:
        material.unlit = True
    pbr_values = (mtl.roughness, mtl.metallic, mtl.roughness_map, mtl.metallic_map)
    for key in ("roughness", "metallic"):
        if getattr(mtl, key) is not None:
            setattr(material, key, Track.constant(float(getattr(mtl, key))))
    if any(value is not None for value in pbr_values):
        material.shading = "pbr"
    for key in MAP_KEYS:
        ref = getattr(mtl, key, None)
        if ref is not None:
            material.maps[key] = TextureSource(
                path=None if ref.missing else Path(ref.path), srgb=SRGB_MAPS[key],
                uv_scale=tuple(float(v) for v in ref.scale[:2]), uv_offset=tuple(float(v) for v in ref.offset[:2]),
                strength=float(getattr(ref, "bump_scale", 1.0) or 1.0), mtl_location=ref.location)
    return material


def apply_gltf(material: Material, gltf, location: SourceLocation | None = None) -> Material:
    """Material with the values of a glTF material (``mesh.gltf.GltfMaterial``), all of them
    (glTF's defaults stand for what the file leaves out): a ``pbr`` material, or ``unlit``
    with KHR_materials_unlit. Its textures are images the file holds (``embedded``); one
    that cannot be decoded becomes the placeholder with a warning at ``location``. The
    wrap and filter of the base colour texture's sampler (else of the first texture's)
    apply to all its maps."""
    material.diffuse = _color_track(gltf.base_color)
    material.metallic = Track.constant(float(gltf.metallic))
    material.roughness = Track.constant(float(gltf.roughness))
    material.emissive = _color_track(gltf.emissive)
    material.emissive_strength = float(gltf.emissive_strength)
    material.alpha_mode = gltf.alpha_mode
    material.alpha_cutoff = float(gltf.alpha_cutoff)
    material.double_sided = bool(gltf.double_sided)
    material.shading = "unlit" if gltf.unlit else "pbr"
    for key in LAYER_KEYS + TRANSMISSION_KEYS:
        setattr(material, key, getattr(gltf, key))
    textures = gltf.textures()
    keys = {"base_color_map": "diffuse_map"}
    for name, texture in textures.items():
        key = keys.get(name, name)
        material.maps[key] = TextureSource(
            path=None if texture.image is None else Path(texture.image), srgb=SRGB_MAPS[key],
            uv_scale=tuple(texture.uv_scale), uv_offset=tuple(texture.uv_offset), uv_skew=tuple(texture.uv_skew),
            mtl_location=location, embedded=True, uv_set=texture.tex_coord,
            strength=float(texture.scale) if key == "clearcoat_normal_map" else 1.0)
    if "normal_map" in textures:
        material.normal_scale = float(textures["normal_map"].scale)
    if "occlusion_map" in textures:
        material.occlusion_strength = float(textures["occlusion_map"].scale)
    sampled = textures.get("base_color_map") or next(iter(textures.values()), None)
    if sampled is not None:
        material.wrap = sampled.wrap
        material.filter = "nearest" if sampled.nearest else "linear"
    return material


def apply_spec(material: Material, spec, where: tuple | None = None) -> Material:
    """Material with the keys a scene ``MaterialSpec`` sets; unset keys stay as they are.
    ``where`` is the key path where the spec is in the scene (for messages about its texture files)."""
    for key in COLOR_KEYS + SCALAR_KEYS:
        value = getattr(spec, key)
        if value is not None:
            setattr(material, key, value)  # colours validate to RGBA tracks already
    if spec.base_color is not None:  # the pbr name of `diffuse` (the model refuses both)
        material.diffuse = spec.base_color
    for spec_key in MAP_KEYS + tuple(SPEC_MAP_ALIASES):
        path = getattr(spec, spec_key, None)
        if path is not None:
            map_key = SPEC_MAP_ALIASES.get(spec_key, spec_key)
            material.maps[map_key] = TextureSource(path=Path(path), srgb=SRGB_MAPS[map_key],
                                                   scene_key=None if where is None else where + (spec_key,))
    for key in ("wrap", "filter", "unlit", "shading", "emissive_strength", "normal_scale", "occlusion_strength",
                "alpha_mode", "alpha_cutoff", "double_sided") + LAYER_KEYS + TRANSMISSION_KEYS:
        value = getattr(spec, key)
        if value is not None:
            setattr(material, key, value)
    return material


def resolve(name: str, mtl=None, layers=(), layer_keys=(), location: SourceLocation | None = None) -> Material:
    """Defaults, then ``mtl`` (the file's material: an MtlMaterial, a GltfMaterial, or
    None), then each MaterialSpec in ``layers``; ``layer_keys`` gives, in the same order,
    each layer's key path in the scene; ``location`` is the mesh file (for a glTF's images)."""
    material = default_material(name)
    if isinstance(mtl, GltfMaterial):
        apply_gltf(material, mtl, location)
    elif mtl is not None:
        apply_mtl(material, mtl)
    keys = list(layer_keys) + [None] * (len(layers) - len(layer_keys))
    for spec, where in zip(layers, keys):
        if spec is not None:
            apply_spec(material, spec, where)
    return material
