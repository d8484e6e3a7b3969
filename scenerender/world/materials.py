"""Materials as the renderer uses them: MTL values, scene materials and overrides merged.

Precedence, lowest first: built-in defaults, the MTL file, the object's ``material``
(which replaces the MTL materials entirely), then ``material_overrides[mtl_name]``.

Shading (see shaders/lighting): with base = Kd * map_Kd,
  colour = La * Ka * base + sum over lights of (Ld * base * N.L + Ls * Ks * map_Ks * spec) + Ke
so Ka scales how much ambient light the surface colour receives (1 = all of it).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from scenerender.animation import Track, shared_constant
from scenerender.errors import SourceLocation

DEFAULTS = {
    "ambient": (1.0, 1.0, 1.0, 1.0),
    "diffuse": (0.8, 0.8, 0.8, 1.0),
    "specular": (0.25, 0.25, 0.25, 1.0),
    "emissive": (0.0, 0.0, 0.0, 1.0),
    "shininess": 32.0,
    "opacity": 1.0,
}
COLOR_KEYS = ("ambient", "diffuse", "specular", "emissive")
MAP_KEYS = ("diffuse_map", "specular_map", "normal_map", "opacity_map")
# Colour maps hold sRGB-encoded colours; normal and opacity maps hold plain data.
SRGB_MAPS = {"diffuse_map": True, "specular_map": True, "normal_map": False, "opacity_map": False}


@dataclass(frozen=True)
class TextureSource:
    """A texture a material samples.

    path:      the image file, or None for the placeholder (a texture that could not be read).
    srgb:      decode as sRGB (colour maps) or read values as they are (data maps).
    uv_scale, uv_offset: (2,) float, from MTL ``-s`` / ``-o``.
    strength:  bump multiplier (MTL ``-bm``), normal maps only.
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

    @property
    def is_placeholder(self) -> bool:
        return self.path is None


@dataclass
class Material:
    """One resolved material; colours are RGBA Tracks in linear [0, 1]."""

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

    def features(self) -> frozenset:
        """Shader features this material needs, e.g. {"diffuse_map", "normal_map"}."""
        names = set(self.maps)
        if self.unlit:
            names.add("unlit")
        return frozenset(names)

    @property
    def transparent(self) -> bool:
        """Drawn in the transparent pass: opacity below 1 at any time, or an opacity map."""
        if "opacity_map" in self.maps:
            return True
        if float(np.min(self.opacity.values)) < 1.0:
            return True
        return float(np.min(self.diffuse.values[:, 3])) < 1.0


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
    """Material with the values an ``MtlMaterial`` sets (None fields keep the default)."""
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
    for key in MAP_KEYS:
        ref = getattr(mtl, key, None)
        if ref is not None:
            material.maps[key] = TextureSource(
                path=None if ref.missing else Path(ref.path), srgb=SRGB_MAPS[key],
                uv_scale=tuple(float(v) for v in ref.scale[:2]), uv_offset=tuple(float(v) for v in ref.offset[:2]),
                strength=float(getattr(ref, "bump_scale", 1.0) or 1.0), mtl_location=ref.location)
    return material


def apply_spec(material: Material, spec, where: tuple | None = None) -> Material:
    """Material with the keys a scene ``MaterialSpec`` sets; unset keys stay as they are.
    ``where`` is the key path where the spec is in the scene (for messages about its texture files)."""
    for key in COLOR_KEYS + ("shininess", "opacity"):
        value = getattr(spec, key)
        if value is not None:
            setattr(material, key, value)  # colours validate to RGBA tracks already
    for map_key in MAP_KEYS:
        path = getattr(spec, map_key)
        if path is not None:
            material.maps[map_key] = TextureSource(path=Path(path), srgb=SRGB_MAPS[map_key],
                                                   scene_key=None if where is None else where + (map_key,))
    if spec.wrap is not None:
        material.wrap = spec.wrap
    if spec.filter is not None:
        material.filter = spec.filter
    if spec.unlit is not None:
        material.unlit = spec.unlit
    return material


def resolve(name: str, mtl=None, layers=(), layer_keys=()) -> Material:
    """Defaults, then ``mtl`` (an MtlMaterial or None), then each MaterialSpec in ``layers``;
    ``layer_keys`` gives, in the same order, each layer's key path in the scene."""
    material = default_material(name)
    if mtl is not None:
        apply_mtl(material, mtl)
    keys = list(layer_keys) + [None] * (len(layers) - len(layer_keys))
    for spec, where in zip(layers, keys):
        if spec is not None:
            apply_spec(material, spec, where)
    return material
