"""The whole scene file: ``SceneSpec``, its sections and the checks between them."""
from __future__ import annotations

from typing import Literal

from pydantic import model_validator
from pydantic_core import PydanticCustomError

from scenerender.scene.model.camera import CameraSpec
from scenerender.scene.model.lights import SKY, LightSpec
from scenerender.scene.model.materials import MaterialSpec
from scenerender.scene.model.objects import ObjectSpec
from scenerender.scene.model.output import OutputSettings
from scenerender.scene.model.render import RenderSpec
from scenerender.scene.strict import StrictModel, mapping_default
from scenerender.scene.suggest import did_you_mean


# A validated scene file; scenerender.Scene (api.py) is a loaded scene ready to render.
class SceneSpec(StrictModel):
    scenerender: Literal[1] | None = None
    render: RenderSpec = mapping_default(RenderSpec)
    output: OutputSettings = mapping_default(OutputSettings)
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

    @model_validator(mode="after")
    def _one_environment(self):
        environments = [i for i, light in enumerate(self.lights or ()) if light.type == "environment"]
        if len(environments) > 1:
            raise PydanticCustomError(
                "environment", "a scene has at most one environment light; lights[{first}] is one already",
                {"first": environments[0], "subpath": ("lights", environments[1], "type")})
        for index in environments:
            if self.lights[index].image == SKY and self.render.skybox is None:
                raise PydanticCustomError(
                    "environment_sky", "image: sky lights the scene with render.skybox, and this scene has none; "
                    "set render.skybox, or name an equirectangular .hdr/.exr image",
                    {"subpath": ("lights", index, "image")})
        return self
