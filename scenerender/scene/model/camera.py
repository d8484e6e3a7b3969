"""``camera:``: where it is, where it looks (a target, or yaw and pitch), its lens and its
clipping planes."""
from __future__ import annotations

from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from scenerender.scene.model.camera_data import IntrinsicsSpec, PoseSpec, check_dataset_camera
from scenerender.scene.strict import StrictModel
from scenerender.scene.values import (
    AnimatedFloat, AnimatedVec3, Text, animated_number, auto_or, choice, number, vector,
)

NearFar = auto_or("a positive number", 0, lo_open=True)


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
    # the filmed camera (world/lens.py): shutter, thin lens
    shutter: number(0, 1) = 0.0
    aperture: number(0.5, 1024) | None = None
    focus_distance: animated_number(0, lo_open=True) | None = None
    focus: str | None = None  # an object's name: focus on its centre (world/frame.py)
    sensor_width: number(1, 1000) = 36.0
    intrinsics: IntrinsicsSpec | None = None
    pose: PoseSpec | None = None
    # a glTF file's camera: the object whose file holds it, and its name (world.file_nodes)
    from_object: Text | None = Field(None, alias="from")
    name: Text | None = None

    @model_validator(mode="after")
    def _check(self):
        check_dataset_camera(self)
        check_file_camera(self)
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
        if self.focus is not None and self.focus_distance is not None:
            raise PydanticCustomError("camera_lens", "give either focus (an object) or focus_distance, not both",
                                      {"subpath": ("focus",)})
        if (self.aperture is not None and self.focus_distance is None and self.focus is None
                and (self.yaw is not None or self.pitch is not None)):
            raise PydanticCustomError("camera_lens", "an aperture with yaw/pitch needs a focus_distance or a focus "
                                      "object (where the lens is focused)", {"subpath": ("aperture",)})
        if self.aperture is not None and self.projection == "orthographic":
            raise PydanticCustomError("camera_lens", "depth of field (aperture) needs a perspective camera",
                                      {"subpath": ("aperture",)})
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


# what a glTF file's camera gives itself: the scene may not give it too
FILE_CAMERA_GIVES = ("position", "target", "yaw", "pitch", "up", "fov", "projection", "height", "intrinsics", "pose")


def check_file_camera(camera) -> None:
    """``from`` (an object holding a glTF file) with ``name`` (one of its cameras) places the
    camera and gives its lens; no key may place it again."""
    if camera.from_object is None:
        if camera.name is not None:
            raise PydanticCustomError("file_camera", "name picks a camera of the glTF file of the object `from` "
                                      "names; give from too", {"subpath": ("name",)})
        return
    given = [key for key in FILE_CAMERA_GIVES if key in camera.model_fields_set]
    if given:
        raise PydanticCustomError("file_camera", "the file's camera gives its own {key}; remove {key} or from",
                                  {"key": given[0], "subpath": (given[0],)})
    if camera.aperture is not None and camera.focus_distance is None and camera.focus is None:
        raise PydanticCustomError("camera_lens", "an aperture with a file's camera needs a focus_distance or a focus "
                                  "object (where the lens is focused)", {"subpath": ("aperture",)})


def _vector_text(values) -> str:
    return "[" + ", ".join(f"{float(v):g}" for v in values) + "]"
