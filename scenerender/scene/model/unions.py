"""Values of more than one shape: a mapping or something else, or a mapping whose kind a
key chooses (``type: point``). Only the chosen branch reports errors, so messages stay
about what the user wrote."""
from __future__ import annotations

from typing import Annotated, Union

from pydantic import BeforeValidator, Discriminator, Tag
from pydantic_core import PydanticCustomError

from scenerender.scene.describe import describe
from scenerender.scene.suggest import did_you_mean


def mapping_or(mapping_type, other_type):
    """A value written either as a mapping (validated as ``mapping_type``) or as something
    else, e.g. a material name or an inline material."""

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
