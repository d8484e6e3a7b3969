"""The scene format as JSON Schema, for editors (``scenerender schema``)."""
from __future__ import annotations

import json

import numpy as np
from pydantic.json_schema import GenerateJsonSchema

from scenerender.animation import Track


class _SceneSchema(GenerateJsonSchema):
    """Writes defaults that are Tracks (animatable values) as their constant value."""

    def encode_default(self, dft):
        return super().encode_default(_plain(dft))


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
    from scenerender.scene.schema import Scene

    schema = Scene.model_json_schema(schema_generator=_SceneSchema)
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "scenerender scene"
    return json.dumps(schema, indent=2)
