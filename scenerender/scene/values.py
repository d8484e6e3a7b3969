"""Value types of the scene format: numbers, vectors, colours and animatable values.

Each type validates with a message a user can act on ("expected a list of 3 numbers, got
'abc'"), and carries the JSON Schema that ``scenerender schema`` prints. Animatable values
come out of validation as ``scenerender.animation.Track`` objects, ready to evaluate.
"""
from __future__ import annotations

import math
from typing import Annotated, Any

from pydantic import PlainValidator, WithJsonSchema
from pydantic_core import PydanticCustomError

from scenerender.animation import INTERPOLATIONS, Track, shared_constant
from scenerender.scene.describe import LARGEST_FLOAT_INT, describe
from scenerender.scene.strict import reject_unknown_keys
from scenerender.scene.suggest import did_you_mean


def is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _bounds_text(lo, hi, lo_open, hi_open) -> str:
    parts = []
    if lo is not None:
        parts.append(f"{'>' if lo_open else '>='} {lo:g}")
    if hi is not None:
        parts.append(f"{'<' if hi_open else '<='} {hi:g}")
    return " and ".join(parts)


FLOAT32_MAX = 3.4028234663852886e38
FLOAT32_TINY = 1.1754943508222875e-38  # the smallest normal float32


def check_number(value, lo=None, hi=None, lo_open=False, hi_open=False, integer=False):
    """Validate one finite number within bounds; returns float (or int when ``integer``)."""
    what = "a whole number" if integer else "a number"
    if not is_number(value):
        raise PydanticCustomError("number", "expected {what}, got {got}", {"what": what, "got": describe(value)})
    if isinstance(value, float) and not math.isfinite(value):
        raise PydanticCustomError("finite", "must be a finite number, got {got}", {"got": describe(value)})
    if isinstance(value, int) and abs(value) > LARGEST_FLOAT_INT:  # float(value) would raise OverflowError
        raise PydanticCustomError("finite", "number too large (more than 1.8e308)")
    if integer and not (isinstance(value, int) or float(value).is_integer()):
        raise PydanticCustomError("integer", "expected a whole number, got {got}", {"got": describe(value)})
    too_low = lo is not None and (value <= lo if lo_open else value < lo)
    too_high = hi is not None and (value >= hi if hi_open else value > hi)
    if too_low or too_high:
        raise PydanticCustomError("range", "must be {bounds}, got {got}",
                                  {"bounds": _bounds_text(lo, hi, lo_open, hi_open), "got": describe(value)})
    if integer:
        return int(value)
    if abs(value) > FLOAT32_MAX or 0 < abs(value) < FLOAT32_TINY:
        # positions, sizes and times reach numpy's float32 casts and the GPU; a size below the
        # smallest normal float32 squares to 0 in a vector length (division by zero)
        raise PydanticCustomError("float32", "must be 0 or between 1.2e-38 and 3.4e38 in size (32-bit floats), "
                                  "got {got}", {"got": f"{float(value):g}"})
    return float(value) + 0.0  # + 0.0 turns -0.0 into 0.0: numpy's uniform(0.0, -0.0) refuses the range


def number(lo=None, hi=None, *, lo_open=False, hi_open=False, integer=False, description=""):
    """An Annotated number type with bounds and a JSON Schema."""
    schema: dict = {"type": "integer" if integer else "number"}
    if lo is not None:
        schema["exclusiveMinimum" if lo_open else "minimum"] = lo
    if hi is not None:
        schema["exclusiveMaximum" if hi_open else "maximum"] = hi
    if description:
        schema["description"] = description

    def validate(value):
        return check_number(value, lo, hi, lo_open, hi_open, integer)

    return Annotated[int if integer else float, PlainValidator(validate), WithJsonSchema(schema)]


def auto_or(what: str, lo=None, hi=None, *, lo_open=False, integer=False):
    """An Annotated type: the word 'auto' or a number with bounds (``what`` names them in
    the error: "expected 'auto' or WHAT, got ...")."""
    number_schema = dict(_schema_of(number(lo, hi, lo_open=lo_open, integer=integer)))

    def validate(value):
        if value == "auto":
            return "auto"
        try:
            return check_number(value, lo, hi, lo_open, False, integer)
        except PydanticCustomError:
            raise PydanticCustomError("auto_or", "expected 'auto' or {what}, got {got}",
                                      {"what": what, "got": describe(value)}) from None

    return Annotated[(int if integer else float) | str, PlainValidator(validate),
                     WithJsonSchema({"anyOf": [{"const": "auto"}, number_schema]})]


def vector(n: int, lo=None, hi=None, *, nonzero=False, description=""):
    """An Annotated type for a list of exactly ``n`` finite numbers -> tuple of floats."""

    def validate(value):
        if not isinstance(value, (list, tuple)) or len(value) != n:
            raise PydanticCustomError("vector", "expected a list of {n} numbers, got {got}",
                                      {"n": n, "got": describe(value)})
        out = tuple(vector_item(v, i, lo, hi) for i, v in enumerate(value))
        if nonzero and not any(out):
            raise PydanticCustomError("zero_vector", "must not be all zeros (it gives a direction)")
        return out

    item = {"type": "number"}
    if lo is not None:
        item["minimum"] = lo
    if hi is not None:
        item["maximum"] = hi
    schema = {"type": "array", "items": item, "minItems": n, "maxItems": n}
    if description:
        schema["description"] = description
    return Annotated[tuple, PlainValidator(validate), WithJsonSchema(schema)]


def vector_item(value, index, lo, hi):
    """Item ``index`` of a list of numbers, checked like ``check_number``; a failure says
    which item ("item 2: must be >= 0, got -1")."""
    try:
        return check_number(value, lo, hi)
    except PydanticCustomError as exc:
        raise PydanticCustomError("vector_item", "item {index}: {message}",
                                  {"index": index, "message": exc.message()}) from None


def _validate_color(value):
    if not isinstance(value, (list, tuple)) or len(value) not in (3, 4):
        raise PydanticCustomError("color", "expected a colour of 3 or 4 numbers in [0, 1], got {got}",
                                  {"got": describe(value)})
    rgba = [vector_item(v, i, 0.0, 1.0) for i, v in enumerate(value)]
    if len(rgba) == 3:
        rgba.append(1.0)
    return tuple(rgba)


Color = Annotated[tuple, PlainValidator(_validate_color), WithJsonSchema({
    "type": "array", "items": {"type": "number", "minimum": 0, "maximum": 1}, "minItems": 3, "maxItems": 4,
    "description": "linear RGB or RGBA in [0, 1]"})]


def _validate_bool(value):
    if not isinstance(value, bool):
        raise PydanticCustomError("bool", "expected true or false, got {got}", {"got": describe(value)})
    return value


Bool = Annotated[bool, PlainValidator(_validate_bool), WithJsonSchema({"type": "boolean"})]


def _validate_text(value):
    if not isinstance(value, str) or not value.strip():
        raise PydanticCustomError("text", "expected text, got {got}", {"got": describe(value)})
    return value


Text = Annotated[str, PlainValidator(_validate_text), WithJsonSchema({"type": "string", "minLength": 1})]

Float = number()
Positive = number(0, lo_open=True)
Vec3 = vector(3)
Direction = vector(3, nonzero=True, description="a direction; need not be unit length")


# ---------------------------------------------------------------------------------------
# Animatable values
#
# A plain validator rather than nested models: building pydantic classes per value type
# costs start-up time, and parsing tracks here lets every message point at the exact key.

TRACK_KEYS = ("keys", "interpolation", "loop")
KEY_MAPPING_KEYS = ("t", "value", "interpolation")  # a key written {t: 1, value: [0, 1, 0]}


def check_at(subpath: tuple, check, value):
    """Run ``check(value)``; on failure re-raise with ``subpath`` appended to the location."""
    try:
        return check(value)
    except PydanticCustomError as exc:
        context = dict(exc.context or {})
        inner = context.pop("subpath", ())
        # pydantic fills only placeholders named in the context, so the formatted message
        # can be reused as a template with a context that holds nothing but the location
        raise PydanticCustomError(exc.type, exc.message(), {"subpath": tuple(subpath) + tuple(inner)}) from None


def _interpolation(value):
    if value not in INTERPOLATIONS:
        raise PydanticCustomError("interpolation", "unknown interpolation {got}{hint} (one of {names})",
                                  {"got": describe(value), "hint": did_you_mean(str(value), INTERPOLATIONS),
                                   "names": ", ".join(INTERPOLATIONS)})
    return value


def _as_row(value) -> tuple:
    if isinstance(value, tuple):
        return tuple(float(v) for v in value)
    if isinstance(value, bool):
        return (1.0 if value else 0.0,)
    return (float(value),)


def _parse_key(index: int, key, check, default_mode: str):
    """One key, ``[t, value]`` or ``{t, value, interpolation}`` -> (t, row, mode)."""
    where = ("keys", index)
    if isinstance(key, (list, tuple)):
        if len(key) != 2:
            raise PydanticCustomError("key", "a key is [time, value], got {got}",
                                      {"got": describe(key), "subpath": where})
        t = check_at(where + (0,), check_number, key[0])
        return t, _as_row(check_at(where + (1,), check, key[1])), default_mode
    if isinstance(key, dict):
        reject_unknown_keys(key, KEY_MAPPING_KEYS, where)
        for name in ("t", "value"):
            if name not in key:
                raise PydanticCustomError("missing", "a key mapping needs '{name}'", {"name": name, "subpath": where})
        t = check_at(where + ("t",), check_number, key["t"])
        mode = check_at(where + ("interpolation",), _interpolation, key.get("interpolation", default_mode))
        return t, _as_row(check_at(where + ("value",), check, key["value"])), mode
    raise PydanticCustomError("key", "a key is [time, value] or {t: ..., value: ...}, got {got}",
                              {"got": describe(key), "subpath": where})


def parse_track(spec: dict, check, kind: str) -> Track:
    """Validate a track mapping and build the Track; errors name the offending key."""
    reject_unknown_keys(spec, TRACK_KEYS)
    keys = spec.get("keys")
    if not isinstance(keys, list) or not keys:
        raise PydanticCustomError("keys", "a track needs 'keys': a non-empty list of [time, value]",
                                  {"subpath": ("keys",) if "keys" in spec else ()})
    default_mode = check_at(("interpolation",), _interpolation, spec.get("interpolation", "linear"))
    loop = spec.get("loop", False)
    if not isinstance(loop, bool):
        raise PydanticCustomError("bool", "expected true or false, got {got}", {"got": describe(loop), "subpath": ("loop",)})
    parsed = [(*_parse_key(i, key, check, default_mode), i) for i, key in enumerate(keys)]
    _check_same_shape(parsed)
    parsed.sort(key=lambda k: k[0])
    for (t1, _, _, i1), (t2, _, _, i2) in zip(parsed, parsed[1:]):
        if t1 == t2:
            raise PydanticCustomError("duplicate_time", "keys {a} and {b} are both at t = {t}; key times must differ",
                                      {"a": min(i1, i2), "b": max(i1, i2), "t": f"{t1:g}", "subpath": ("keys", max(i1, i2))})
    scalar = len(parsed[0][1]) == 1 and kind != "vector"
    values = [row[0] if scalar else row for _, row, _, _ in parsed]
    return Track([k[0] for k in parsed], values, [k[2] for k in parsed], loop=loop, kind=kind)


def _check_same_shape(parsed) -> None:
    first = len(parsed[0][1])
    for _, row, _, index in parsed:
        if len(row) != first:
            raise PydanticCustomError(
                "key_shape", "key {index} has {n} numbers but key 0 has {m}; all keys of a track need the same shape",
                {"index": index, "n": len(row), "m": first, "subpath": ("keys", index)})


def _track_schema(value_schema: dict) -> dict:
    key = {"anyOf": [
        {"type": "array", "prefixItems": [{"type": "number"}, value_schema], "minItems": 2, "maxItems": 2},
        {"type": "object", "required": ["t", "value"], "additionalProperties": False,
         "properties": {"t": {"type": "number"}, "value": value_schema,
                        "interpolation": {"enum": list(INTERPOLATIONS)}}},
    ]}
    return {"type": "object", "required": ["keys"], "additionalProperties": False,
            "properties": {"keys": {"type": "array", "minItems": 1, "items": key},
                           "interpolation": {"enum": list(INTERPOLATIONS)}, "loop": {"type": "boolean"}}}


def animated(check, value_schema: dict, kind: str):
    """A value that is a constant (validated by ``check``) or a keyframe track -> ``Track``.

    ``kind`` is "float", "vector" or "bool" (bool tracks always step).
    """

    def validate(value):
        if isinstance(value, Track):
            return value
        if isinstance(value, dict):
            return parse_track(value, check, kind)
        return _constant_track(check(value), kind)

    schema = {"anyOf": [value_schema, _track_schema(value_schema)]}
    return Annotated[Track, PlainValidator(validate), WithJsonSchema(schema)]


def _constant_track(constant, kind: str) -> Track:
    return shared_constant(constant if kind == "float" else _as_row(constant), kind)


def _validate_scale(value):
    if isinstance(value, (list, tuple)):
        return _validate_vec3(value)
    return check_number(value, 0.0, lo_open=True)


def _validator_of(annotated):
    """The validation function inside an Annotated[..., PlainValidator(f)] type."""
    return next(m.func for m in annotated.__metadata__ if isinstance(m, PlainValidator))


def _schema_of(annotated) -> dict:
    return next(m.json_schema for m in annotated.__metadata__ if isinstance(m, WithJsonSchema))


_validate_vec3 = _validator_of(Vec3)
_validate_direction = _validator_of(Direction)
_NUMBER = {"type": "number"}
_VEC3 = _schema_of(Vec3)
_COLOR = _schema_of(Color)
_SCALE = {"anyOf": [{"type": "number", "exclusiveMinimum": 0}, _VEC3]}

AnimatedFloat = animated(check_number, _NUMBER, "float")
AnimatedVec3 = animated(_validate_vec3, _VEC3, "vector")
AnimatedDirection = animated(_validate_direction, _schema_of(Direction), "vector")
AnimatedColor = animated(_validate_color, _COLOR, "vector")
AnimatedBool = animated(_validate_bool, {"type": "boolean"}, "bool")
AnimatedScale = animated(_validate_scale, _SCALE, "vector")


def animated_number(lo=None, hi=None, *, lo_open=False, hi_open=False):
    plain = number(lo, hi, lo_open=lo_open, hi_open=hi_open)
    return animated(_validator_of(plain), _schema_of(plain), "float")


def choice(*names: str, description: str = ""):
    """One of a fixed set of words, with a did-you-mean on typos."""

    def validate(value):
        if value not in names:
            raise PydanticCustomError("choice", "expected one of {names}, got {got}{hint}",
                                      {"names": ", ".join(names), "got": describe(value),
                                       "hint": did_you_mean(str(value), names)})
        return value

    schema = {"enum": list(names)}
    if description:
        schema["description"] = description
    return Annotated[str, PlainValidator(validate), WithJsonSchema(schema)]
