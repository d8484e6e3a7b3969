"""An object's ``mesh:``: a mesh file, or a built-in primitive chosen by ``primitive``."""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import PlainValidator, ValidationInfo, WithJsonSchema, WrapValidator
from pydantic_core import PydanticCustomError

from scenerender.scene.describe import describe
from scenerender.scene.model.paths import FileKind, file_path
from scenerender.scene.model.unions import mapping_or, tagged_union
from scenerender.scene.strict import StrictModel
from scenerender.scene.values import Positive, check_at, check_number, number


def _segments(lo):
    return number(lo, 4096, integer=True)


def _positive(value):
    return check_number(value, 0.0, lo_open=True)


def _extent(n):
    """A positive size: one number or a per-axis list of ``n``."""

    def validate(value):
        if isinstance(value, (list, tuple)):
            if len(value) != n:
                raise PydanticCustomError("size", "expected a number or a list of {n} numbers, got {got}",
                                          {"n": n, "got": describe(value)})
            return tuple(check_at((i,), _positive, v) for i, v in enumerate(value))
        return _positive(value)

    return Annotated[Union[float, tuple], PlainValidator(validate),
                     WithJsonSchema({"anyOf": [{"type": "number", "exclusiveMinimum": 0},
                                               {"type": "array", "items": {"type": "number", "exclusiveMinimum": 0},
                                                "minItems": n, "maxItems": n}]})]


class PlanePrimitive(StrictModel):
    primitive: Literal["plane"]
    size: _extent(2) = 1.0
    uv_repeat: _extent(2) = 1.0


class BoxPrimitive(StrictModel):
    primitive: Literal["box"]
    size: _extent(3) = 1.0


class SpherePrimitive(StrictModel):
    primitive: Literal["sphere"]
    radius: Positive = 0.5
    segments: _segments(3) = 32
    rings: _segments(2) = 16


class CylinderPrimitive(StrictModel):
    primitive: Literal["cylinder"]
    radius: Positive = 0.5
    height: Positive = 1.0
    segments: _segments(3) = 32


class PrismPrimitive(StrictModel):
    primitive: Literal["prism"]
    radius: Positive = 0.5
    height: Positive = 1.0
    sides: _segments(3) = 6


class ConePrimitive(StrictModel):
    primitive: Literal["cone"]
    radius: Positive = 0.5
    height: Positive = 1.0
    segments: _segments(3) = 32


PrimitiveSpec = tagged_union("primitive", "inline mesh", {
    "plane": PlanePrimitive, "box": BoxPrimitive, "sphere": SpherePrimitive,
    "cylinder": CylinderPrimitive, "prism": PrismPrimitive, "cone": ConePrimitive})


MESH_SUFFIXES = (".obj", ".ply", ".stl", ".glb", ".gltf", ".off")
MESH_FILE = FileKind(MESH_SUFFIXES, "{value}: unsupported mesh format (use one of {kinds})",
                     "OBJ (+MTL), PLY, STL or GLB file")
MeshPath = file_path(MESH_FILE)


def _mesh_from_code(value, handler, info: ValidationInfo):
    """A mesh object made in code passes as it is when validation is told its type
    (``context={"mesh_types": (MeshData,)}``, as ``Scene.from_dict`` does); a YAML file can
    never produce one."""
    mesh_types = info.context.get("mesh_types", ()) if isinstance(info.context, dict) else ()
    return value if mesh_types and isinstance(value, mesh_types) else handler(value)


# a file, an inline primitive, or (from code) a mesh object
MeshSpec = Annotated[mapping_or(PrimitiveSpec, MeshPath), WrapValidator(_mesh_from_code)]
