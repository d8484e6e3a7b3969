"""Paths a scene names, as written: validation checks their form and never the file.

A path validates to the text the scene wrote: a non-empty string ending in a suffix of its
kind. ``scene/file_checks.py`` looks the file up once the scene has validated (through the
run's ``AssetPolicy``: relative to the scene file, inside the allowed folders, symlinks
followed, a regular file whose real name has a suffix of its kind), reads what it must of
it (image headers), and puts the resolved ``Path`` in the text's place.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, get_args

from pydantic import PlainValidator, WithJsonSchema
from pydantic_core import PydanticCustomError

from scenerender.scene.describe import describe


@dataclass(frozen=True)
class FileKind:
    """A kind of file a scene names.

    suffixes:    the accepted suffixes (lower case), checked as written and again once
                 symlinks are followed;
    message:     the error for any other suffix, with ``{value}`` (the path as written)
                 and ``{kinds}`` (the suffixes);
    description: the path's description in the JSON Schema.
    """

    suffixes: tuple[str, ...]
    message: str
    description: str

    def wrong_kind(self, value: str) -> PydanticCustomError:
        return PydanticCustomError("file_type", self.message, {"value": value, "kinds": " ".join(self.suffixes)})


def written_path(value) -> str:
    """``value`` when it is a non-empty string, else the "expected a file path" error."""
    if not isinstance(value, str) or not value.strip():
        raise PydanticCustomError("path", "expected a file path, got {got}", {"got": describe(value)})
    return value


def file_path(kind: FileKind):
    """The type of a path to a file of ``kind``: validates to the text as written."""

    def validate(value) -> str:
        if isinstance(value, str) and value.strip() and not value.lower().endswith(kind.suffixes):
            raise kind.wrong_kind(value)
        return written_path(value)

    return Annotated[str, PlainValidator(validate), WithJsonSchema({"type": "string", "description": kind.description}),
                     kind]


def folder_path(description: str):
    """The type of a path to a folder: validates to the text as written."""
    return Annotated[str, PlainValidator(written_path), WithJsonSchema({"type": "string", "description": description})]


def keys_holding(model, kind: FileKind) -> tuple[str, ...]:
    """The keys of ``model`` whose value is a path to a file of ``kind`` (or may be one), in
    the model's order: what the file checks look up."""

    def holds(annotation) -> bool:
        return kind in getattr(annotation, "__metadata__", ()) or any(holds(arg) for arg in get_args(annotation))

    return tuple(name for name, field in model.model_fields.items()
                 if kind in field.metadata or holds(field.annotation))


IMAGE_SUFFIXES = (".png", ".bmp", ".jpg", ".jpeg", ".tga", ".gif")
IMAGE_FILE = FileKind(IMAGE_SUFFIXES, "{value} is not an image this renderer reads ({kinds})",
                      "image path relative to the scene file (PNG BMP JPG TGA GIF)")
ImagePath = file_path(IMAGE_FILE)

ENVIRONMENT_SUFFIXES = (".hdr", ".exr") + IMAGE_SUFFIXES
ENVIRONMENT_FILE = FileKind(ENVIRONMENT_SUFFIXES,
                            "{value} is not an environment image this renderer reads ({kinds})",
                            "equirectangular image relative to the scene file: Radiance .hdr or OpenEXR .exr "
                            "(linear), or PNG BMP JPG TGA GIF (sRGB)")
EnvironmentPath = file_path(ENVIRONMENT_FILE)
