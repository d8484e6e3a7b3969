"""The scene format as validated models; docs/scene-format.md is generated from them.

Every mapping rejects unknown keys; every animatable value validates to a
``scenerender.animation.Track``. Paths go through the scene's ``AssetPolicy`` (the scene
file's folder and the allowed roots), which validation receives as ``context={"assets": policy}``.
"""
from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal, Union

from pydantic import (
    BeforeValidator, Discriminator, Field, PlainValidator, Tag, ValidationInfo, WithJsonSchema, WrapValidator, model_validator,
)
from pydantic_core import PydanticCustomError

from scenerender.errors import UserError
from scenerender.scene.assets import AssetPolicy
from scenerender.scene.strict import StrictModel
from scenerender.scene.suggest import did_you_mean
from scenerender.scene.describe import describe
from scenerender.scene.values import (
    AnimatedBool, AnimatedColor, AnimatedDirection, AnimatedFloat, AnimatedScale, AnimatedVec3, Bool, Text, animated_number, choice, number, vector,
    check_number, check_at, vector_item,
)

def mapping_or(mapping_type, other_type):
    """A value written either as a mapping (validated as ``mapping_type``) or as something
    else, e.g. a material name or an inline material. Only the matching branch reports
    errors, so messages stay about what the user wrote."""

    def which(value):
        return "(mapping)" if isinstance(value, dict) else "(value)"

    return Annotated[Union[Annotated[other_type, Tag("(value)")], Annotated[mapping_type, Tag("(mapping)")]],
                     Discriminator(which)]


def tagged_union(key: str, noun: str, members: dict):
    """A union chosen by the value of ``key`` (``type: point``), with clear errors for a
    missing or misspelt tag. ``members`` maps tag value -> model class."""
    names = tuple(members)

    def check(value):
        if not isinstance(value, dict):
            raise PydanticCustomError("mapping", "expected a {noun} mapping with '{key}', got {got}",
                                      {"noun": noun, "key": key, "got": describe(value)})
        kind = value.get(key)
        if kind is None:
            raise PydanticCustomError("tag", "a {noun} needs '{key}' (one of {names})",
                                      {"noun": noun, "key": key, "names": ", ".join(names)})
        if kind not in names:
            raise PydanticCustomError("tag", "unknown {key} {got}{hint} (one of {names})",
                                      {"key": key, "got": describe(kind),
                                       "hint": did_you_mean(str(kind), names), "names": ", ".join(names),
                                       "subpath": (key,)})
        return value

    def which(value):
        return value.get(key) if isinstance(value, dict) else None

    union = Union[tuple(Annotated[model, Tag(tag)] for tag, model in members.items())]
    return Annotated[union, Discriminator(which), BeforeValidator(check)]


# ---------------------------------------------------------------------------------------
# Files named in the scene: checked to exist (relative to the scene file)

IMAGE_SUFFIXES = (".png", ".bmp", ".jpg", ".jpeg", ".tga", ".gif")


def asset_policy(info: ValidationInfo):
    """The run's ``AssetPolicy`` from the validation context (``{"assets": policy}``); a
    policy rooted at ``base_dir`` when only that is given (older callers)."""
    context = info.context if isinstance(info.context, dict) else {}
    policy = context.get("assets")
    if policy is None:
        policy = AssetPolicy(Path(context.get("base_dir", ".")))
        if isinstance(info.context, dict):
            info.context["assets"] = policy  # one policy, one record, for the whole scene
    return policy


def _existing_path(value, info: ValidationInfo, want_dir: bool = False) -> Path:
    """The file (or folder) ``value`` names, through the scene's AssetPolicy: inside the
    allowed folders, symlinks followed, a regular file."""
    if not isinstance(value, str) or not value.strip():
        raise PydanticCustomError("path", "expected a file path, got {got}", {"got": describe(value)})
    policy = asset_policy(info)
    base = policy.roots[0]
    try:
        if want_dir:
            return policy.resolve_folder(value, base)
        return policy.resolve(value, base)
    except UserError as exc:
        raise PydanticCustomError("asset_path", "{message}", {"message": exc.message}) from None


def existing_file(suffixes: tuple, message: str, description: str, check=None):
    """A path type: the file must exist (relative to the scene file, inside the allowed
    folders) and end in one of ``suffixes``, as written and once symlinks are followed;
    ``message`` (with {value} and {kinds}) explains a wrong kind of file. ``check(path,
    info)`` looks inside the file and raises PydanticCustomError when it is unusable."""

    def wrong_kind(value):
        return PydanticCustomError("file_type", message, {"value": value, "kinds": " ".join(suffixes)})

    def validate(value, info: ValidationInfo) -> Path:
        if isinstance(value, str) and not value.lower().endswith(suffixes) and value.strip():
            raise wrong_kind(value)
        path = _existing_path(value, info)
        if path.suffix.lower() not in suffixes:
            raise wrong_kind(value)
        if check is not None:
            check(path, info)
        return path

    return Annotated[Path, PlainValidator(validate), WithJsonSchema({"type": "string", "description": description})]


def image_header_size(path: Path, info: ValidationInfo) -> tuple[int, int]:
    """(width, height) of an image the scene names, from its header (each file read once
    per validation); raises PydanticCustomError when it is not a readable image or is over
    the ``texture_pixels`` limit."""
    from scenerender.scene.image_files import DEFAULT_MAX_PIXELS, ImageError, image_size

    context = info.context if isinstance(info.context, dict) else {}
    sizes = context.setdefault("image_sizes", {})
    if path not in sizes:
        max_pixels = getattr(context.get("limits"), "texture_pixels", DEFAULT_MAX_PIXELS)
        try:
            sizes[path] = image_size(path, max_pixels)
        except ImageError as exc:
            sizes[path] = exc
    found = sizes[path]
    if isinstance(found, Exception):
        raise PydanticCustomError("image", "{reason}", {"reason": found.reason})
    return found


ImagePath = existing_file(IMAGE_SUFFIXES, "{value} is not an image this renderer reads ({kinds})",
                          "image path relative to the scene file (PNG BMP JPG TGA GIF)", check=image_header_size)

# ---------------------------------------------------------------------------------------
# render


class ShadowSettings(StrictModel):
    """Shadow-map parameters; ``render.shadows`` gives the defaults, a light may override."""

    size: number(16, 16384, integer=True) = 2048
    pcf: number(1, 15, integer=True) = 3
    bias: number(0, 1) = 0.002
    slope_bias: number(0, 1) = 0.02


class ShadowOverride(StrictModel):
    """A light's own shadow parameters; keys left out come from ``render.shadows``."""

    size: number(16, 16384, integer=True) | None = None
    pcf: number(1, 15, integer=True) | None = None
    bias: number(0, 1) | None = None
    slope_bias: number(0, 1) | None = None


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


SKY_FACES = ("posx", "negx", "posy", "negy", "posz", "negz")


class SkyboxFaces(StrictModel):
    posx: ImagePath
    negx: ImagePath
    posy: ImagePath
    negy: ImagePath
    posz: ImagePath
    negz: ImagePath

    @model_validator(mode="after")
    def _square_and_equal(self, info: ValidationInfo):
        """A cube map needs six square faces of one size: checked from the headers here,
        so that ``validate`` catches what the upload would refuse."""
        first = image_header_size(self.posx, info)
        for face in SKY_FACES:
            width, height = image_header_size(getattr(self, face), info)
            if width != height or (width, height) != first:
                raise PydanticCustomError(
                    "skybox_size", "skybox faces must be square and all the same size; {face} is {w}x{h}, "
                    "posx {fw}x{fh}", {"face": face, "w": width, "h": height, "fw": first[0], "fh": first[1],
                                       "subpath": (face,)})
        return self


def _skybox_folder(value, info: ValidationInfo) -> SkyboxFaces:
    """A folder holding the six faces, found by stem with any image suffix."""
    folder = _existing_path(value, info, want_dir=True)
    faces = {}
    for face in SKY_FACES:
        found = [p for p in sorted(folder.iterdir()) if p.stem.lower() == face and p.suffix.lower() in IMAGE_SUFFIXES]
        if not found:
            raise PydanticCustomError("skybox_face", "skybox folder {value} has no {face} image ({kinds})",
                                      {"value": value, "face": face, "kinds": " ".join(IMAGE_SUFFIXES)})
        faces[face] = str(found[0])
    return SkyboxFaces.model_validate(faces, context=info.context)


SkyboxFolder = Annotated[SkyboxFaces, PlainValidator(_skybox_folder), WithJsonSchema({"type": "string", "description": "folder with posx negx posy negy posz negz images"})]
Skybox = mapping_or(SkyboxFaces, SkyboxFolder)

# GL multisampled images come in powers of two only (moderngl refuses any other count), so
# a count no device offers is refused here rather than by the driver in the middle of a render
MSAA_SAMPLES = (1, 2, 4, 8, 16, 32, 64)


def _msaa_samples(value) -> int:
    count = check_number(value, integer=True)
    if count not in MSAA_SAMPLES:
        raise PydanticCustomError("samples", "MSAA samples must be one of {counts} (1 = off), got {got}",
                                  {"counts": ", ".join(map(str, MSAA_SAMPLES)), "got": count})
    return count


MsaaSamples = Annotated[int, PlainValidator(_msaa_samples),
                        WithJsonSchema({"type": "integer", "enum": list(MSAA_SAMPLES)})]

SHADINGS = ("phong", "blinn_phong", "unlit")
MODES = ("shaded", "depth", "normals", "wireframe", "points", "ambient_occlusion", "shadow", "light_depth")


class RenderSettings(StrictModel):
    size: Annotated[tuple, PlainValidator(lambda v: _size(v)),
                    WithJsonSchema({"type": "array", "items": {"type": "integer", "minimum": 1, "maximum": 16384},
                                    "minItems": 2, "maxItems": 2})] = (640, 480)
    samples: MsaaSamples = 4
    shading: choice(*SHADINGS) = "blinn_phong"
    mode: choice(*MODES) = "shaded"
    background: AnimatedColor = (0.1, 0.1, 0.12)
    skybox: Skybox | None = None
    fog: Fog | None = None
    ambient_occlusion: AmbientOcclusion | None = None
    shadows: ShadowSettings = ShadowSettings()
    output_transform: choice("srgb", "gamma", "linear") = "srgb"
    gamma: number(0.1, 10) = 2.2
    wireframe_overlay: Bool = False
    line_width: number(0.1, 16) = 1.0
    point_size: number(1, 64) = 3.0


def _size(value):
    if (not isinstance(value, (list, tuple)) or len(value) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) for v in value)):
        raise PydanticCustomError("size", "expected [width, height] in whole pixels, got {got}", {"got": describe(value)})
    if not all(1 <= v <= 16384 for v in value):
        raise PydanticCustomError("size", "width and height must be 1..16384, got {got}", {"got": describe(value)})
    return tuple(value)


# ---------------------------------------------------------------------------------------
# output

FORMATS = ("png", "jpg", "tga", "exr", "mp4", "gif")
VIDEO_FORMATS = ("mp4", "gif")


class OutputSettings(StrictModel):
    fps: number(0, 1000, lo_open=True) = 30.0
    # at most 3.4e38 (every number is), times fps at most 1000: round(duration * fps) stays finite
    duration: number(0, lo_open=True) | None = None
    frames: number(1, integer=True) | None = None  # the upper bound is Limits.frames (--limit frames=N)
    format: choice(*FORMATS) = "png"
    name: Text | None = None
    quality: number(1, 100, integer=True) = 90

    @model_validator(mode="after")
    def _check(self):
        if self.duration is not None and self.frames is not None:
            from_duration = round(self.duration * self.fps)
            if from_duration != self.frames:
                raise PydanticCustomError(
                    "frames_duration", "frames ({f}) and duration x fps ({d}) disagree; give one of them",
                    {"f": self.frames, "d": from_duration, "subpath": ("frames",)})
        if self.name is not None:
            from scenerender.frame_names import name_template_problem

            # parsed, never formatted blindly: '{frame.__class__}' or '../x_{frame}' must
            # neither run attribute lookups nor name files outside -o
            problem = name_template_problem(self.name, self.frame_count)
            if problem is not None:
                raise PydanticCustomError("name_pattern", "{problem}; use e.g. \"frame_{frame:04d}\"",
                                          {"problem": problem, "subpath": ("name",)})
        return self

    @property
    def frame_count(self) -> int:
        if self.frames is not None:
            return self.frames
        if self.duration is not None:
            return max(1, round(self.duration * self.fps))
        return 1


# ---------------------------------------------------------------------------------------
# camera


def _near_far(value):
    if value == "auto":
        return "auto"
    try:
        return check_number(value, 0.0, lo_open=True)
    except PydanticCustomError:
        raise PydanticCustomError("near_far", "expected 'auto' or a positive number, got {got}",
                                  {"got": describe(value)}) from None


NearFar = Annotated[Union[float, str], PlainValidator(_near_far),
                    WithJsonSchema({"anyOf": [{"const": "auto"}, {"type": "number", "exclusiveMinimum": 0}]})]


class CameraSpec(StrictModel):
    position: AnimatedVec3 | None = None
    target: AnimatedVec3 | None = None
    yaw: AnimatedFloat | None = None
    pitch: AnimatedFloat | None = None
    up: vector(3, nonzero=True) = (0.0, 1.0, 0.0)
    fov: animated_number(0.1, 179, hi_open=False) = 60.0
    projection: choice("perspective", "orthographic") = "perspective"
    height: animated_number(0, lo_open=True) | None = None
    near: NearFar = "auto"
    far: NearFar = "auto"

    @model_validator(mode="after")
    def _check(self):
        if self.target is not None and (self.yaw is not None or self.pitch is not None):
            raise PydanticCustomError("camera_aim", "give either target or yaw/pitch, not both",
                                      {"subpath": ("yaw" if self.yaw is not None else "pitch",)})
        if (self.yaw is not None or self.pitch is not None) and self.position is None:
            raise PydanticCustomError("camera_aim", "yaw/pitch need a camera position", {"subpath": ("position",)})
        if self._looks_at_itself():
            raise PydanticCustomError(
                "camera_aim", "camera position and target are the same point {point}: there is no direction to "
                "look in; move the target or give yaw/pitch instead", {"point": _vector_text(self.target(0.0)),
                                                                         "subpath": ("target",)})
        if (isinstance(self.near, float) and isinstance(self.far, float) and self.near >= self.far):
            raise PydanticCustomError("near_far", "near ({n}) must be less than far ({f})",
                                      {"n": f"{self.near:g}", "f": f"{self.far:g}", "subpath": ("far",)})
        return self

    def _looks_at_itself(self) -> bool:
        """Position and target fixed at one point. Animated ones that meet only at some
        instants are left to the renderer, which then looks down -Z for those frames."""
        if self.position is None or self.target is None:
            return False
        if not (self.position.is_constant and self.target.is_constant):
            return False
        return tuple(self.position(0.0)) == tuple(self.target(0.0))


def _vector_text(values) -> str:
    return "[" + ", ".join(f"{float(v):g}" for v in values) + "]"


# ---------------------------------------------------------------------------------------
# lights


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


class _LightBase(StrictModel):
    name: Text | None = None
    color: AnimatedColor = (1.0, 1.0, 1.0)
    intensity: animated_number(0) = 1.0
    enabled: AnimatedBool = True


class DirectionalLight(_LightBase):
    type: Literal["directional"]
    direction: AnimatedDirection = (-1.0, -1.0, -0.5)
    shadows: ShadowsOption = False


class PointLight(_LightBase):
    type: Literal["point"]
    position: AnimatedVec3 = (0.0, 3.0, 0.0)
    attenuation: Attenuation = (1.0, 0.0, 0.0)
    shadows: ShadowsOption = False


class SpotLight(_LightBase):
    type: Literal["spot"]
    position: AnimatedVec3 | None = None
    direction: AnimatedDirection | None = None
    attenuation: Attenuation = (1.0, 0.0, 0.0)
    inner_angle: animated_number(0, 89.9) = 12.5
    outer_angle: animated_number(0, 89.9, lo_open=True) = 17.5
    attach: choice("camera") | None = None
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


class AmbientLight(_LightBase):
    type: Literal["ambient"]
    color: AnimatedColor = (0.25, 0.25, 0.25)


LightSpec = tagged_union("type", "light", {"directional": DirectionalLight, "point": PointLight,
                                           "spot": SpotLight, "ambient": AmbientLight})


# ---------------------------------------------------------------------------------------
# materials


class MaterialSpec(StrictModel):
    """A material; keys left out keep the MTL value (for overrides) or the default."""

    ambient: AnimatedColor | None = None
    diffuse: AnimatedColor | None = None
    specular: AnimatedColor | None = None
    shininess: animated_number(0, 10000) | None = None
    emissive: AnimatedColor | None = None
    opacity: animated_number(0, 1) | None = None
    diffuse_map: ImagePath | None = None
    specular_map: ImagePath | None = None
    normal_map: ImagePath | None = None
    opacity_map: ImagePath | None = None
    wrap: choice("repeat", "clamp", "mirror") | None = None
    filter: choice("linear", "nearest") | None = None
    unlit: Bool | None = None


MaterialRef = mapping_or(MaterialSpec, Text)  # a name from `materials`, or inline

# ---------------------------------------------------------------------------------------
# meshes


def _segments(lo):
    return number(lo, 4096, integer=True)


def _extent(n):
    """A positive size: one number or a per-axis list of ``n``."""

    def positive(v):
        return check_number(v, 0.0, lo_open=True)

    def validate(value):
        if isinstance(value, (list, tuple)):
            if len(value) != n:
                raise PydanticCustomError("size", "expected a number or a list of {n} numbers, got {got}",
                                          {"n": n, "got": describe(value)})
            return tuple(check_at((i,), positive, v) for i, v in enumerate(value))
        return positive(value)

    return Annotated[Union[float, tuple], PlainValidator(validate),
                     WithJsonSchema({"anyOf": [{"type": "number", "exclusiveMinimum": 0},
                                               {"type": "array", "items": {"type": "number", "exclusiveMinimum": 0},
                                                "minItems": n, "maxItems": n}]})]


Positive = number(0, lo_open=True)


class PlanePrimitive(StrictModel):
    primitive: Literal["plane"]
    size: _extent(2) = 1.0
    uv_repeat: _extent(2) = 1.0


class BoxPrimitive(StrictModel):
    primitive: Literal["box"]
    size: _extent(3) = 1.0


class SpherePrimitive(StrictModel):
    primitive: Literal["sphere"]
    radius: Positive = 0.5
    segments: _segments(3) = 32
    rings: _segments(2) = 16


class CylinderPrimitive(StrictModel):
    primitive: Literal["cylinder"]
    radius: Positive = 0.5
    height: Positive = 1.0
    segments: _segments(3) = 32


class PrismPrimitive(StrictModel):
    primitive: Literal["prism"]
    radius: Positive = 0.5
    height: Positive = 1.0
    sides: _segments(3) = 6


class ConePrimitive(StrictModel):
    primitive: Literal["cone"]
    radius: Positive = 0.5
    height: Positive = 1.0
    segments: _segments(3) = 32


PrimitiveSpec = tagged_union("primitive", "inline mesh", {
    "plane": PlanePrimitive, "box": BoxPrimitive, "sphere": SpherePrimitive,
    "cylinder": CylinderPrimitive, "prism": PrismPrimitive, "cone": ConePrimitive})


MESH_SUFFIXES = (".obj", ".ply", ".stl", ".glb", ".gltf", ".off")


MeshPath = existing_file(MESH_SUFFIXES, "{value}: unsupported mesh format (use one of {kinds})", "OBJ (+MTL), PLY, STL or GLB file")




def _in_memory_mesh(value, handler):
    """A ``MeshData`` passes as it is: scenes built in code (``Scene.from_dict``) may hand
    over meshes they made; a YAML file can never produce one."""
    from scenerender.mesh.data import MeshData

    return value if isinstance(value, MeshData) else handler(value)


# a file, an inline primitive, or (from code) a MeshData
MeshSpec = Annotated[mapping_or(PrimitiveSpec, MeshPath), WrapValidator(_in_memory_mesh)]

# ---------------------------------------------------------------------------------------
# objects


class Outline(StrictModel):
    color: AnimatedColor = (1.0, 0.6, 0.1)
    width: number(0, lo_open=True) = 0.02


class InstanceSpec(StrictModel):
    position: AnimatedVec3 = (0.0, 0.0, 0.0)
    rotation: AnimatedVec3 = (0.0, 0.0, 0.0)
    scale: AnimatedScale = 1.0


class Range3(StrictModel):
    min: vector(3)
    max: vector(3)

    @model_validator(mode="after")
    def _ordered(self):
        if any(a > b for a, b in zip(self.min, self.max)):
            raise PydanticCustomError("range", "min must not exceed max on any axis", {"subpath": ("max",)})
        return self


class ScaleRange(StrictModel):
    min: Positive
    max: Positive

    @model_validator(mode="after")
    def _ordered(self):
        if self.min > self.max:
            raise PydanticCustomError("range", "min must not exceed max", {"subpath": ("max",)})
        return self


class RandomInstances(StrictModel):
    count: number(1, 10_000_000, integer=True)
    seed: number(0, 2**63 - 1, integer=True) = 0
    position: Range3 = Range3(min=(0.0, 0.0, 0.0), max=(0.0, 0.0, 0.0))
    rotation: Range3 = Range3(min=(0.0, 0.0, 0.0), max=(0.0, 0.0, 0.0))
    scale: ScaleRange = ScaleRange(min=1.0, max=1.0)


class RandomInstancesWrapper(StrictModel):
    random: RandomInstances


Instances = mapping_or(RandomInstancesWrapper, Annotated[list[InstanceSpec], Field(min_length=1, strict=False)])


class ObjectSpec(StrictModel):
    name: Text | None = None
    mesh: MeshSpec
    normalize: Bool = False
    normals: choice("auto", "smooth", "flat") = "auto"
    position: AnimatedVec3 = (0.0, 0.0, 0.0)
    rotation: AnimatedVec3 = (0.0, 0.0, 0.0)
    scale: AnimatedScale = 1.0
    material: MaterialRef | None = None
    material_overrides: dict[str, MaterialSpec] = {}
    visible: AnimatedBool = True
    cast_shadows: Bool = True
    outline: Outline | None = None
    instances: Instances | None = None


# ---------------------------------------------------------------------------------------
# the scene


class Scene(StrictModel):
    scenerender: Literal[1] | None = None
    render: RenderSettings = RenderSettings()
    output: OutputSettings = OutputSettings()
    camera: CameraSpec | None = None
    lights: list[LightSpec] | None = None
    materials: dict[str, MaterialSpec] = {}
    objects: list[ObjectSpec]  # required: `objects: []` asks for the background alone

    @model_validator(mode="after")
    def _material_names_exist(self):
        for index, obj in enumerate(self.objects):
            if isinstance(obj.material, str) and obj.material not in self.materials:
                known = ", ".join(self.materials) or "none are defined under 'materials'"
                raise PydanticCustomError(
                    "material_name", "no material named '{name}'{hint} (known: {known})",
                    {"name": obj.material, "hint": did_you_mean(obj.material, self.materials), "known": known,
                     "subpath": ("objects", index, "material")})
        return self
