"""The base class of every scene-format mapping: unknown keys are errors, with a hint."""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, model_validator
from pydantic_core import PydanticCustomError

from scenerender.scene.suggest import did_you_mean


class StrictModel(BaseModel):
    """A mapping of the scene format. Keys outside the model are an error, never ignored."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=True,
                              arbitrary_types_allowed=True, validate_default=True)

    @model_validator(mode="before")
    @classmethod
    def _only_known_keys(cls, data):
        if isinstance(data, cls):
            return data
        if not isinstance(data, dict):
            from scenerender.scene.values import describe

            raise PydanticCustomError("mapping", "expected a mapping (key: value), got {got}",
                                      {"got": describe(data)})
        known = cls.model_fields.keys()
        for key in data:
            if key not in known:
                raise PydanticCustomError(
                    "unknown_key", "unknown key '{key}'{hint}",
                    {"key": key if len(str(key)) <= 60 else str(key)[:57] + "...",
                     "hint": did_you_mean(str(key), known) or f" (known keys: {', '.join(known)})",
                     "subpath": (key,)})
        return data
