"""The base class of every scene-format mapping: unknown keys are errors, with a hint."""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator
from pydantic_core import PydanticCustomError

from scenerender.errors import SceneErrors
from scenerender.scene.describe import describe
from scenerender.scene.suggest import did_you_mean


class StrictModel(BaseModel):
    """A mapping of the scene format. Keys outside the model are an error, never ignored.

    Validators are built on first use (``defer_build``), and only for the model validated:
    loading a scene builds ``SceneSpec``'s alone, with every section inside it, instead of one
    validator per class at import (a third of the start-up of a one-frame render)."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=True,
                              arbitrary_types_allowed=True, validate_default=True, defer_build=True)

    @model_validator(mode="before")
    @classmethod
    def _only_known_keys(cls, data):
        if isinstance(data, cls):
            return data
        if not isinstance(data, dict):
            raise PydanticCustomError("mapping", "expected a mapping (key: value), got {got}",
                                      {"got": describe(data)})
        reject_unknown_keys(data, [field.alias or name for name, field in cls.model_fields.items()])
        return data


class MappingDefault:
    """The default of a key whose value is a mapping (``render:``, ``shadows:``), written as
    the keys it sets. Each validation gets those keys as a fresh mapping, validated by the
    enclosing model like one the scene wrote; a default instance made at import instead
    would build the section's own validator before any scene is read. ``instance()`` is the
    validated value the JSON Schema shows (``scene/json_schema.py``)."""

    def __init__(self, model: type[StrictModel], **values):
        self.model = model
        self.values = values

    def __call__(self) -> dict:
        return dict(self.values)

    def instance(self) -> StrictModel:
        return self.model(**self.values)


def mapping_default(model: type[StrictModel], **values):
    """``shadows: ShadowSettings = mapping_default(ShadowSettings)``: see ``MappingDefault``."""
    return Field(default_factory=MappingDefault(model, **values))


# The errors of a scene print at most SceneErrors.MAX_LINES lines, each mistake on its own,
# so no unknown key after this many in one mapping is ever shown: those skip the "did you
# mean" search, which would otherwise dominate loading a file of thousands of bad keys.
HINTED_UNKNOWN_KEYS = SceneErrors.MAX_LINES


def reject_unknown_keys(data: dict, known, where: tuple = ()) -> None:
    """Raise when ``data`` has keys outside ``known``: one error for each of them, with its
    own location and hint, so that one run lists every typo of a mapping. ``where`` is the
    mapping's path inside the value being validated (a track's key, say)."""
    unknown = [key for key in data if key not in known]
    if unknown:
        # a ValidationError raised in a validator keeps its errors apart, each at its own key
        raise ValidationError.from_exception_data("unknown keys", [
            {"type": unknown_key_error(key, known, where, hinted=index < HINTED_UNKNOWN_KEYS), "loc": (),
             "input": data} for index, key in enumerate(unknown)])


def unknown_key_error(key, known, where: tuple = (), hinted: bool = True) -> PydanticCustomError:
    shown = key if len(str(key)) <= 60 else str(key)[:57] + "..."
    hint = did_you_mean(str(key), known) if hinted else ""
    return PydanticCustomError("unknown_key", "unknown key '{key}'{hint}",
                               {"key": shown, "hint": hint or f" (known keys: {', '.join(known)})",
                                "subpath": where + (key,)})
