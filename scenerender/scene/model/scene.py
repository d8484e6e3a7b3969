"""The whole scene file: ``SceneSpec``, its sections and the checks between them."""
from __future__ import annotations

from typing import Literal

from pydantic import model_validator
from pydantic_core import PydanticCustomError

from scenerender.scene.model.camera import CameraSpec
from scenerender.scene.model.lights import LightSpec
from scenerender.scene.model.materials import MaterialSpec
from scenerender.scene.model.objects import ObjectSpec
from scenerender.scene.model.output import OutputSettings
from scenerender.scene.model.render import RenderSpec
from scenerender.scene.strict import StrictModel
from scenerender.scene.suggest import did_you_mean


# A validated scene file; scenerender.Scene (api.py) is a loaded scene ready to render.
class SceneSpec(StrictModel):
    scenerender: Literal[1] | None = None
    render: RenderSpec = RenderSpec()
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
