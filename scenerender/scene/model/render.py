"""``render:``: image size, sampling, shading and mode, sky, fog, ambient occlusion, the
shadow-map defaults, and how linear light becomes stored values (exposure, tone curve,
output transform)."""
from __future__ import annotations

from typing import Annotated

from pydantic import ConfigDict, PlainValidator, WithJsonSchema, model_validator
from pydantic_core import PydanticCustomError

from scenerender.colorspace import TONE_MAPS
from scenerender.option_rules import MSAA_SAMPLES
from scenerender.scene.describe import describe
from scenerender.scene.model.paths import ImagePath, folder_path
from scenerender.scene.model.unions import mapping_or
from scenerender.scene.strict import StrictModel, mapping_default
from scenerender.scene.values import AnimatedColor, Bool, animated_number, check_number, choice, number


class ShadowSettings(StrictModel):
    """Shadow-map parameters; ``render.shadows`` gives the defaults, a light may override."""

    size: number(16, 16384, integer=True) = 2048
    pcf: number(1, 15, integer=True) = 3
    bias: number(0, 1) = 0.002
    slope_bias: number(0, 1) = 0.02
    blocker_samples: number(4, 64, integer=True) = 16
    filter_samples: number(4, 128, integer=True) = 32
    casters: choice("surface", "solid") = "surface"


class ShadowOverride(StrictModel):
    """A light's own shadow parameters; keys left out come from ``render.shadows``."""

    size: number(16, 16384, integer=True) | None = None
    pcf: number(1, 15, integer=True) | None = None
    bias: number(0, 1) | None = None
    slope_bias: number(0, 1) | None = None
    blocker_samples: number(4, 64, integer=True) | None = None
    filter_samples: number(4, 128, integer=True) | None = None
    casters: choice("surface", "solid") | None = None


class Fog(StrictModel):
    color: AnimatedColor = (0.5, 0.5, 0.5)
    density: animated_number(0) = 0.03
    mode: choice("exp", "exp2", "linear") = "exp2"
    start: number(0) = 0.0
    end: number(0, lo_open=True) = 100.0

    @model_validator(mode="after")
    def _start_before_end(self):
        if self.mode == "linear" and self.start >= self.end:
            raise PydanticCustomError("fog_range", "linear fog needs start < end, got start {s} and end {e}",
                                      {"s": f"{self.start:g}", "e": f"{self.end:g}", "subpath": ("end",)})
        return self


class AmbientOcclusion(StrictModel):
    radius: number(0, lo_open=True) = 0.5
    samples: number(1, 64, integer=True) = 16
    strength: number(0, 4) = 1.0


class IndirectLight(StrictModel):
    bounces: number(1, 32, integer=True) = 8
    probe_spacing: number(0, lo_open=True) | None = None
    capture_size: number(4, 64, integer=True) = 16
    probe_budget: number(1, 4096, integer=True) = 32


class Bloom(StrictModel):
    strength: number(0, 1) = 0.05
    radius: number(0, 0.25, lo_open=True) = 0.02


SKY_FACES = ("posx", "negx", "posy", "negy", "posz", "negz")


# The six faces of a cube map. That they are images, square and all of one size is read
# from their headers by the file checks (scene/file_checks.py). (A model's docstring is
# its description in the published JSON Schema, hence comments here.)
class SkyboxFaces(StrictModel):
    posx: ImagePath
    negx: ImagePath
    posy: ImagePath
    negy: ImagePath
    posz: ImagePath
    negz: ImagePath


# a folder holding the six faces, found by stem with any image suffix (by the file checks)
SkyboxFolder = folder_path("folder with posx negx posy negy posz negz images")
Skybox = mapping_or(SkyboxFaces, SkyboxFolder)

def _msaa_samples(value) -> int:
    """The scene file's door to the one rule of MSAA sample counts (option_rules.MSAA_SAMPLES)."""
    count = check_number(value, integer=True)
    problem = MSAA_SAMPLES.problem(count)
    if problem is not None:
        raise PydanticCustomError("samples", problem)
    return count


MsaaSamples = Annotated[int, PlainValidator(_msaa_samples),
                        WithJsonSchema({"type": "integer", "enum": list(MSAA_SAMPLES.choices)})]


def _size(value):
    if (not isinstance(value, (list, tuple)) or len(value) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) for v in value)):
        raise PydanticCustomError("size", "expected [width, height] in whole pixels, got {got}", {"got": describe(value)})
    if not all(1 <= v <= 16384 for v in value):
        raise PydanticCustomError("size", "width and height must be 1..16384, got {got}", {"got": describe(value)})
    return tuple(value)


RenderSize = Annotated[tuple, PlainValidator(_size),
                       WithJsonSchema({"type": "array", "items": {"type": "integer", "minimum": 1, "maximum": 16384},
                                       "minItems": 2, "maxItems": 2})]

SHADINGS = ("phong", "blinn_phong", "pbr", "unlit")
MODES = ("shaded", "depth", "normals", "wireframe", "points", "ambient_occlusion", "shadow", "light_depth")


# The render: section; world.settings.RenderSettings is what the renderer takes of it.
class RenderSpec(StrictModel):
    # the name the published JSON Schema has always given this mapping (scene.schema.json)
    model_config = ConfigDict(title="RenderSettings")

    size: RenderSize = (640, 480)
    samples: MsaaSamples = 4
    shading: choice(*SHADINGS) = "blinn_phong"
    mode: choice(*MODES) = "shaded"
    background: AnimatedColor = (0.1, 0.1, 0.12)
    skybox: Skybox | None = None
    fog: Fog | None = None
    ambient_occlusion: AmbientOcclusion | None = None
    indirect: IndirectLight | None = None
    shadows: ShadowSettings = mapping_default(ShadowSettings)
    exposure: animated_number(-20, 20) = 0.0
    tone_map: choice(*TONE_MAPS) = "none"
    output_transform: choice("srgb", "gamma", "linear") = "srgb"
    gamma: number(0.1, 10) = 2.2
    wireframe_overlay: Bool = False
    line_width: number(0.1, 16) = 1.0
    point_size: number(1, 64) = 3.0
    bloom: Bloom | None = None
    film_samples: number(1, 1024, integer=True) = 16
    depth_of_field: choice("sub_frames", "gather") = "sub_frames"
    motion_blur: choice("sub_frames", "velocity") = "sub_frames"
