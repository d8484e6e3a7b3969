"""``objects:``: what to draw, where, with which material, and how many instances."""
from __future__ import annotations

from typing import Annotated

from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from scenerender.scene.model.materials import MaterialRef, MaterialSpec
from scenerender.scene.model.meshes import MeshSpec
from scenerender.scene.model.object_animation import AnimationSpec, check_animated_mesh, check_file_lights, check_variant
from scenerender.scene.model.unions import mapping_or
from scenerender.scene.strict import StrictModel, mapping_default
from scenerender.scene.values import (
    AnimatedBool, AnimatedColor, AnimatedScale, AnimatedVec3, Bool, Positive, Text, choice, number, vector,
)


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
    position: Range3 = mapping_default(Range3, min=(0.0, 0.0, 0.0), max=(0.0, 0.0, 0.0))
    rotation: Range3 = mapping_default(Range3, min=(0.0, 0.0, 0.0), max=(0.0, 0.0, 0.0))
    scale: ScaleRange = mapping_default(ScaleRange, min=1.0, max=1.0)


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
    animation: AnimationSpec | None = None
    lights: Bool = False  # the KHR_lights_punctual lights of its glTF file join the scene's (world.file_nodes)
    variant: Text | None = None  # a KHR_materials_variants name of its glTF file

    @model_validator(mode="after")
    def _check_animation(self):
        check_animated_mesh(self)
        check_file_lights(self)
        check_variant(self)
        return self
