"""``objects[].animation``: which of a glTF file's clips the object plays, and how, in
scene time (mesh/gltf_animation.py reads the clips; docs/scene-notes.md, "glTF animations")."""
from __future__ import annotations

from typing import Annotated, Union

from pydantic import PlainValidator, WithJsonSchema
from pydantic_core import PydanticCustomError

from scenerender.scene.describe import describe
from scenerender.scene.strict import StrictModel
from scenerender.scene.values import Bool, check_number, number

GLTF_SUFFIXES = (".gltf", ".glb")


def _clip(value):
    """A clip's name (text) or its index in the file's ``animations`` (a whole number >= 0)."""
    if isinstance(value, str):
        if not value:
            raise PydanticCustomError("clip", "expected a clip name or index, got an empty name")
        return value
    if isinstance(value, bool) or not isinstance(value, int):
        raise PydanticCustomError("clip", "expected a clip name or index (0, 1, ...), got {got}",
                                  {"got": describe(value)})
    return int(check_number(value, 0, integer=True))


ClipRef = Annotated[Union[int, str], PlainValidator(_clip),
                    WithJsonSchema({"anyOf": [{"type": "integer", "minimum": 0}, {"type": "string", "minLength": 1}]})]


class AnimationSpec(StrictModel):
    clip: ClipRef = 0
    speed: number() = 1.0
    offset: number() = 0.0
    loop: Bool = True


def check_animated_mesh(obj) -> None:
    """An object's ``animation`` plays a glTF file's clips: its mesh must be one."""
    if obj.animation is None:
        return
    mesh = obj.mesh
    if not (isinstance(mesh, str) and mesh.lower().endswith(GLTF_SUFFIXES)):
        raise PydanticCustomError("animation", "animation plays the clips of a glTF file (.gltf, .glb), and this "
                                  "object's mesh is not one", {"subpath": ("animation",)})
    if obj.normalize:
        raise PydanticCustomError("animation", "normalize rescales the mesh at rest, which the clip's node "
                                  "transforms know nothing of; remove it (give the object a scale instead)",
                                  {"subpath": ("normalize",)})


def check_file_lights(obj) -> None:
    """``lights: true`` brings in a glTF file's lights, placed by the object's own transform
    (not repeated per instance)."""
    if not obj.lights:
        return
    mesh = obj.mesh
    if not (isinstance(mesh, str) and mesh.lower().endswith(GLTF_SUFFIXES)):
        raise PydanticCustomError("lights", "lights: true brings in the lights of a glTF file (.gltf, .glb), and "
                                  "this object's mesh is not one", {"subpath": ("lights",)})
    if obj.instances is not None:
        raise PydanticCustomError("lights", "lights: true places the file's lights by the object's own transform; "
                                  "an object with instances would need one set per instance (remove one of the "
                                  "keys)", {"subpath": ("lights",)})


def check_variant(obj) -> None:
    """``variant`` picks materials of a glTF file's KHR_materials_variants."""
    if obj.variant is None:
        return
    mesh = obj.mesh
    if not (isinstance(mesh, str) and mesh.lower().endswith(GLTF_SUFFIXES)):
        raise PydanticCustomError("variant", "variant picks one of a glTF file's material variants (.gltf, .glb), "
                                  "and this object's mesh is not one", {"subpath": ("variant",)})
