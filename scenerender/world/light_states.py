"""Lights as the renderer evaluates them each frame.

Directions are the way light travels (a sun at noon has direction (0, -1, 0)). A spot
light with ``attach: camera`` takes position and direction in camera space: by default it
sits at the camera and points where the camera looks, like a torch.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scenerender.animation import Track
from scenerender.world.camera import unit_direction
from scenerender.world.settings import ShadowMapSettings

DEFAULT_AMBIENT = (0.12, 0.12, 0.12)


@dataclass(frozen=True)
class LightDef:
    """One light of the scene, its animatable values as Tracks.

    kind: "directional" | "point" | "spot" | "rect" | "disk" | "ambient".  path: its key
    path in the scene (for messages). shadow: its ShadowMapSettings when it casts shadows,
    else None. extent: an area light's (half width, half height), a disk's (radius, radius).
    """

    kind: str
    name: str
    path: tuple
    color: Track
    intensity: Track
    enabled: Track
    position: Track | None = None
    direction: Track | None = None
    attenuation: tuple = (1.0, 0.0, 0.0)
    inner_angle: Track | None = None
    outer_angle: Track | None = None
    attach_camera: bool = False
    shadow: ShadowMapSettings | None = None
    # the light's size: a sphere's radius (point, spot: scene units), or the tangent of
    # the half angle its disc spans (directional); 0 a point, as it always was
    size: float = 0.0
    extent: tuple = (0.0, 0.0)
    # point, spot: the distance where KHR_lights_punctual's window ends its light
    # (range_window); None: no window, as it always was
    range: float | None = None
    # spot: between the cones "smooth" (smoothstep of the linear ramp t, as it always was)
    # or "gltf" (t^2, KHR_lights_punctual's implementation note)
    cone_falloff: str = "smooth"

    @property
    def sized(self) -> bool:
        return self.size > 0.0

    @property
    def solid_casters(self) -> bool:
        """Whether its soft shadow reads the casters' back faces too (render.shadows.casters:
        solid): a sized light seen in perspective (point, spot, rect, disk). A directional
        light's soft shadow is left as filtered (its map is orthographic)."""
        return (self.sized and self.shadow is not None and self.kind != "directional"
                and self.shadow.casters == "solid")

    @property
    def area(self) -> bool:
        """A one-sided rectangle or disk (AREA_KINDS)."""
        return self.kind in AREA_KINDS


# one-sided lights with a surface: a rectangle (width x height) and a disk
AREA_KINDS = ("rect", "disk")
# a spot's falloff between its cones (LightDef.cone_falloff), in the order the GPU numbers them
CONE_FALLOFFS = ("smooth", "gltf")


def area_axes(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(u, v) unit axes of an area light facing ``direction``: u (its width) is the world's
    X turned with it, Z where the light faces along X; v = direction x u."""
    reference = np.array([1.0, 0.0, 0.0]) if abs(direction[0]) < 0.99 else np.array([0.0, 0.0, 1.0])
    v = np.cross(direction, reference)
    v /= np.linalg.norm(v)
    u = np.cross(v, direction)
    return u / np.linalg.norm(u), v


@dataclass(frozen=True)
class LightState:
    """A light at one instant, in world space (float64).

    color: (3,) linear RGB times intensity, zero when disabled.
    position: (3,) world position (point, spot). direction: (3,) unit travel direction.
    cos_inner / cos_outer: spot cone cosines (inner >= outer).
    """

    definition: LightDef
    color: np.ndarray
    position: np.ndarray | None
    direction: np.ndarray | None
    cos_inner: float = 1.0
    cos_outer: float = 1.0

    @property
    def kind(self) -> str:
        return self.definition.kind


# where an animated direction passes through zero: straight down
_NO_DIRECTION = np.array([0.0, -1.0, 0.0])


def _unit(v) -> np.ndarray:
    return unit_direction(np.asarray(v, dtype=np.float64)[:3], _NO_DIRECTION)


def light_defs(spec, shadows_default, brought: list = ()) -> list[LightDef]:
    """LightDefs from the validated ``lights`` list, then ``brought`` (LightDefs of glTF
    files' lights, world.file_nodes); neither gives the default rig (a headlight that
    follows the camera plus a weak ambient)."""
    if spec is None and not brought:
        return _default_rig()
    # the environment light is world.environment's
    return [_from_spec(i, light, shadows_default) for i, light in enumerate(spec or ())
            if light.type != "environment"] + list(brought)


def _default_rig() -> list[LightDef]:
    white = Track.constant((1.0, 1.0, 1.0, 1.0), kind="vector")
    on = Track.constant(True, kind="bool")
    one = Track.constant(1.0)
    return [
        # light from just above and left of the viewer, so faces facing the camera are lit
        LightDef("directional", "headlight", ("lights",), white, one, on,
                 direction=Track.constant((0.25, -0.35, -1.0), kind="vector"), attach_camera=True),
        LightDef("ambient", "ambient", ("lights",), Track.constant(DEFAULT_AMBIENT + (1.0,), kind="vector"), one, on),
    ]


# A spot light's own defaults where neither render.shadows nor the light sets the key.
# Chosen by `scenerender bench benchmarks/quality/scenes/spot.yaml`: a spot's map covers
# only its cone, so 1024 px with pcf 5 gives the error of 2048 px with pcf 3 (whole image
# 1.25 against 1.26 %) at about half the time, while for point and directional lights
# 1024 px costs accuracy (0.86 -> 1.02 %), so their default stays 2048 px.
SPOT_SHADOW_DEFAULTS = {"size": 1024, "pcf": 5}
# A light with a size: its soft shadow blurs what a larger map would sharpen. Chosen by
# `scenerender bench benchmarks/quality/scenes/sized_lights.yaml` (sized_lights.md): a
# 1024 px map leaves the penumbra band's error where 2048 px has it (7.3 %) at well under
# half the time of drawing the map, 512 px too (7.2 %), kept for contacts finer than that
# scene's. More blocker or filter reads than 16 and 32 gain nothing measurable there.
SIZED_SHADOW_DEFAULTS = {"size": 1024}


def _merged_shadow(option, defaults, kind: str, sized: bool = False):
    """``shadows: true`` -> render.shadows; a mapping -> render.shadows with its keys over
    it. Keys nobody set take the light type's own default (SPOT_SHADOW_DEFAULTS), and a
    light with a size SIZED_SHADOW_DEFAULTS."""
    if option is False or option is None:
        return None
    values = defaults.model_dump()
    if kind == "spot":
        values.update({k: v for k, v in SPOT_SHADOW_DEFAULTS.items() if k not in defaults.model_fields_set})
    if sized:
        values.update({k: v for k, v in SIZED_SHADOW_DEFAULTS.items() if k not in defaults.model_fields_set})
    if option is not True:
        values.update({k: v for k, v in option.model_dump().items() if v is not None})
    merged = type(defaults).model_validate(values)  # checks the combination
    return ShadowMapSettings(merged.size, merged.pcf, merged.bias, merged.slope_bias, merged.blocker_samples,
                             merged.filter_samples, merged.casters)


def _from_spec(index: int, light, shadows_default) -> LightDef:
    path = ("lights", index)
    name = light.name or f"{light.type}{index}"
    common = dict(kind=light.type, name=name, path=path, color=light.color, intensity=light.intensity,
                  enabled=light.enabled)
    if light.type == "ambient":
        return LightDef(**common)
    sized = (light.type in AREA_KINDS or getattr(light, "radius", 0.0) > 0.0
             or getattr(light, "angular_diameter", 0.0) > 0.0)
    shadow = _merged_shadow(light.shadows, shadows_default, light.type, sized)
    if light.type == "directional":
        return LightDef(**common, direction=light.direction, shadow=shadow,
                        size=math.tan(math.radians(0.5 * light.angular_diameter)))
    if light.type == "point":
        return LightDef(**common, position=light.position, attenuation=light.attenuation, shadow=shadow,
                        size=float(light.radius), range=light.range)
    if light.type in AREA_KINDS:
        return _area_from_spec(light, common, shadow)
    attach = light.attach == "camera"
    position = light.position or Track.constant((0.0, 0.0, 0.0), kind="vector")
    direction = light.direction or Track.constant((0.0, 0.0, -1.0), kind="vector")
    return LightDef(**common, position=position, direction=direction, attenuation=light.attenuation,
                    inner_angle=light.inner_angle, outer_angle=light.outer_angle, attach_camera=attach,
                    shadow=shadow, size=float(light.radius), range=light.range, cone_falloff=light.cone_falloff)


def _area_from_spec(light, common: dict, shadow) -> LightDef:
    """A rectangle or disk; its size for soft shadows is the radius of the disk of the same
    area."""
    if light.type == "rect":
        extent = (0.5 * float(light.width), 0.5 * float(light.height))
        size = math.sqrt(light.width * light.height / math.pi)
    else:
        extent = (float(light.radius), float(light.radius))
        size = float(light.radius)
    return LightDef(**common, position=light.position, direction=light.direction, shadow=shadow, size=size,
                    extent=extent)


def split_ambient(defs: list[LightDef]) -> tuple[list[LightDef], list[LightDef]]:
    """(directional, point and spot lights, ambient lights), each in scene order. The first
    list is ``World.lights``: one index runs through it, the shadow atlas's tiles, the
    shadow views and the packed light data alike; ambient lights only add up to one colour."""
    return [d for d in defs if d.kind != "ambient"], [d for d in defs if d.kind == "ambient"]


def evaluate_lights(defs: list[LightDef], t: float, camera) -> list[LightState]:
    """The states of ``defs`` (directional, point and spot lights) at time ``t``."""
    return [_state(light, t, camera, _color(light, t)) for light in defs]


def ambient_light(defs: list[LightDef], t: float) -> np.ndarray:
    """The ambient lights ``defs`` summed at time ``t``: (3,) linear RGB."""
    ambient = np.zeros(3)
    for light in defs:
        ambient += _color(light, t)
    return ambient


def _color(light: LightDef, t: float) -> np.ndarray:
    """(3,) linear RGB times intensity, zero while disabled."""
    on = light.enabled(t)
    return np.asarray(light.color(t), dtype=np.float64)[:3] * light.intensity(t) * (1.0 if on else 0.0)


def _state(light: LightDef, t: float, camera, color: np.ndarray) -> LightState:
    position = np.asarray(light.position(t), dtype=np.float64) if light.position is not None else None
    direction = _unit(light.direction(t)) if light.direction is not None else None
    if light.attach_camera:
        to_world = camera.rotation.T  # view -> world
        if position is not None:
            position = camera.position + to_world @ position
        direction = _unit(to_world @ direction)
    if light.kind != "spot":
        return LightState(light, color, position, direction)
    outer = light.outer_angle(t)
    inner = min(light.inner_angle(t), outer)
    return LightState(light, color, position, direction,
                      cos_inner=math.cos(math.radians(inner)), cos_outer=math.cos(math.radians(outer)))
