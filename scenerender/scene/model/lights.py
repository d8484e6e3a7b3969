"""``lights:``: directional, point, spot, rectangle, disk, ambient and environment lights,
chosen by ``type``."""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import PlainValidator, WithJsonSchema, model_validator
from pydantic_core import PydanticCustomError

from scenerender.scene.describe import describe
from scenerender.scene.model.paths import EnvironmentPath
from scenerender.scene.model.render import ShadowOverride
from scenerender.scene.model.unions import mapping_or, tagged_union
from scenerender.scene.strict import StrictModel
from scenerender.scene.values import (
    AnimatedBool, AnimatedColor, AnimatedDirection, AnimatedVec3, Bool, Text, animated_number, auto_or, choice, number,
    vector_item,
)

# true / false, or a mapping overriding render.shadows for this light
ShadowsOption = mapping_or(ShadowOverride, Bool)


def _attenuation(value):
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise PydanticCustomError("attenuation", "expected [constant, linear, quadratic], got {got}",
                                  {"got": describe(value)})
    out = tuple(vector_item(v, i, 0.0, None) for i, v in enumerate(value))
    if out[0] == 0 and out[1] == 0 and out[2] == 0:
        raise PydanticCustomError("attenuation", "attenuation [0, 0, 0] divides by zero; use [1, 0, 0] for no falloff")
    return out


Attenuation = Annotated[tuple, PlainValidator(_attenuation),
                        WithJsonSchema({"type": "array", "items": {"type": "number", "minimum": 0},
                                        "minItems": 3, "maxItems": 3, "description": "1 / (c + l d + q d^2)"})]


# pixels a side of the block that shares the environment visibility's directions out:
# 'auto' picks by the image's size (world.environment_light.visibility_blocks)
Interleave = auto_or("a whole number from 1 to 8", 1, 8, integer=True)


class _LightBase(StrictModel):
    name: Text | None = None
    color: AnimatedColor = (1.0, 1.0, 1.0)
    intensity: animated_number(0) = 1.0
    enabled: AnimatedBool = True


class DirectionalLight(_LightBase):
    type: Literal["directional"]
    direction: AnimatedDirection = (-1.0, -1.0, -0.5)
    angular_diameter: number(0, 20) = 0.0  # degrees the light's disc spans (the sun: 0.53); 0 a point
    shadows: ShadowsOption = False


class PointLight(_LightBase):
    type: Literal["point"]
    position: AnimatedVec3 = (0.0, 3.0, 0.0)
    attenuation: Attenuation = (1.0, 0.0, 0.0)
    radius: number(0) = 0.0  # a sphere light of this radius; 0 a point
    range: number(0, lo_open=True) | None = None  # KHR_lights_punctual's window: no light at range and beyond
    shadows: ShadowsOption = False


class SpotLight(_LightBase):
    type: Literal["spot"]
    position: AnimatedVec3 | None = None
    direction: AnimatedDirection | None = None
    attenuation: Attenuation = (1.0, 0.0, 0.0)
    inner_angle: animated_number(0, 89.9) = 12.5
    outer_angle: animated_number(0, 89.9, lo_open=True) = 17.5
    # between the cones: smoothstep of the linear ramp, or its square (KHR_lights_punctual's)
    cone_falloff: choice("smooth", "gltf") = "smooth"
    attach: choice("camera") | None = None
    radius: number(0) = 0.0  # a sphere light of this radius; 0 a point
    range: number(0, lo_open=True) | None = None  # KHR_lights_punctual's window: no light at range and beyond
    shadows: ShadowsOption = False

    @model_validator(mode="after")
    def _check(self):
        if self.attach is None and self.position is None:
            raise PydanticCustomError("spot_position", "a spot light needs a position (or attach: camera)",
                                      {"subpath": ()})
        inner, outer = self.inner_angle, self.outer_angle
        if inner.is_constant and outer.is_constant and inner(0) > outer(0):
            raise PydanticCustomError("cone", "inner_angle ({i}) must not exceed outer_angle ({o})",
                                      {"i": f"{inner(0):g}", "o": f"{outer(0):g}", "subpath": ("inner_angle",)})
        return self


class RectLight(_LightBase):
    """A one-sided rectangle of light facing ``direction``; ``width`` runs along the world's
    X axis turned with it (for a light facing straight down, along X), ``height`` across."""

    type: Literal["rect"]
    position: AnimatedVec3 = (0.0, 3.0, 0.0)
    direction: AnimatedDirection = (0.0, -1.0, 0.0)
    width: number(0, lo_open=True) = 1.0
    height: number(0, lo_open=True) = 1.0
    shadows: ShadowsOption = False


class DiskLight(_LightBase):
    """A one-sided disk of light facing ``direction``."""

    type: Literal["disk"]
    position: AnimatedVec3 = (0.0, 3.0, 0.0)
    direction: AnimatedDirection = (0.0, -1.0, 0.0)
    radius: number(0, lo_open=True) = 0.5
    shadows: ShadowsOption = False


class AmbientLight(_LightBase):
    type: Literal["ambient"]
    color: AnimatedColor = (0.25, 0.25, 0.25)


# ``image: sky``: the environment is render.skybox
SKY = "sky"
# the environment's prefiltered specular image: roughness 0 (a mirror, one lookup a texel),
# 0.2 .. 1 (``samples`` lookups a texel), each prefilter_size x prefilter_size / 2 texels
# (rendering.features.specular_layout)
PREFILTER_LEVELS = 6


def prefilter_lookups(size: int, samples: int) -> int:
    """Texture lookups the environment light's prefilter makes at ``prefilter_size`` ``size``
    and ``samples``: what its time on a software renderer grows with (Limits.prefilter_lookups)."""
    return size * max(size // 2, 1) * (1 + (PREFILTER_LEVELS - 1) * samples)
EnvironmentImage = choice(SKY) | EnvironmentPath


class EnvironmentLight(_LightBase):
    """Light from every direction, as an image of the surroundings: the skybox, or an
    equirectangular image (world.environment_light). Radiance from a direction is the image's
    linear value there x colour x intensity; ``rotation`` turns the image about +Y."""

    type: Literal["environment"]
    image: EnvironmentImage = SKY
    rotation: animated_number() = 0.0
    classic: Bool = False  # Phong and Blinn-Phong materials get its diffuse term too, as an ambient
    prefilter_size: number(8, 2048, integer=True) = 128
    sh_order: number(0, 4, integer=True) = 4
    samples: number(1, 4096, integer=True) = 512
    footprint: Bool = False  # reflections averaged over the pixel's spread of directions (an option)
    # the pbr specular term: the prefiltered image at the reflection direction (split_sum),
    # or GGX samples of the image at shading time around the real normal and view (sampled)
    specular: choice("split_sum", "sampled") = "split_sum"
    specular_samples: number(1, 256, integer=True) = 32  # a pixel's samples, with specular: sampled
    # the scene blocks the environment's light (world.environment_visibility); false: not
    visibility: Bool = True
    visibility_directions: number(1, 64, integer=True) = 32  # directions, each with a shadow map
    visibility_map_size: number(32, 4096, integer=True) = 512  # texels per side of each map
    # pixels a side of the block that shares the directions out (each pixel looks up about
    # directions / interleave^2 of them, a blur puts them together); 1: every pixel all;
    # auto: by the image's size
    visibility_interleave: Interleave = "auto"
    visibility_half_resolution: Bool = True  # those lookups at half the image's resolution, a side
    background: Bool = False  # the image drawn behind the scene (in place of render.skybox), turned by rotation


LightSpec = tagged_union("type", "light", {"directional": DirectionalLight, "point": PointLight,
                                           "spot": SpotLight, "rect": RectLight, "disk": DiskLight,
                                           "ambient": AmbientLight,
                                           "environment": EnvironmentLight})
