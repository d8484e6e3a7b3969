"""The scene format as JSON Schema, for editors (``scenerender schema``)."""
from __future__ import annotations

import json

import numpy as np
from pydantic.json_schema import GenerateJsonSchema

from scenerender.animation import Track
from scenerender.scene.model.scene import SceneSpec
from scenerender.scene.strict import MappingDefault, StrictModel


class _SceneSchema(GenerateJsonSchema):
    """Writes defaults that are Tracks (animatable values) as their constant value, a
    section's default (``MappingDefault``) as the values of its keys, and
    gives a model that sets a ``title`` that name in ``$defs`` too: the published schema
    keeps its names when a class is renamed (``RenderSpec`` is ``RenderSettings`` there)."""

    def encode_default(self, dft):
        return super().encode_default(_plain(dft))

    def get_default_value(self, schema):
        factory = schema.get("default_factory")
        if isinstance(factory, MappingDefault):  # a section's defaults, shown as every key's value
            return factory.instance()
        return super().get_default_value(schema)

    def get_defs_ref(self, core_mode_ref):
        core_ref, mode = core_mode_ref
        name, _, identity = core_ref.rpartition(":")
        title = _published_names().get(name)
        if title is not None:
            core_ref = f"{name.rpartition('.')[0]}.{title}:{identity}"
        return super().get_defs_ref((core_ref, mode))


def _published_names() -> dict[str, str]:
    """'module.ClassName' -> the title it sets, for every model of the format whose title
    differs from its class name."""
    names, pending = {}, [StrictModel]
    while pending:
        model = pending.pop()
        pending.extend(model.__subclasses__())
        title = model.model_config.get("title")
        if title is not None and title != model.__name__:
            names[f"{model.__module__}.{model.__qualname__}"] = title
    return names


def _plain(value):
    if isinstance(value, Track):
        v = value(0.0)
        return v.tolist() if isinstance(v, np.ndarray) else v
    if hasattr(value, "model_dump"):
        return {k: _plain(v) for k, v in value.__dict__.items()}
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    return value


def scene_json_schema() -> str:
    schema = SceneSpec.model_json_schema(schema_generator=_SceneSchema)
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "scenerender scene"
    return json.dumps(schema, indent=2)
