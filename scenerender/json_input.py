"""The guard every JSON file the product reads goes through: the run manifest, a reference
folder's ignore.json, a render's objects.json, a glTF file's JSON.

``parse_json`` accepts UTF-8 only, nesting no deeper than ``JSON_MAX_DEPTH`` (checked
before the decoder runs, so 100,000 nested brackets are a message, not a RecursionError
in the decoder or in whatever walks the value later), and standard JSON only (no NaN or
Infinity). Each file's size is bounded before it is read (the bounds below); the reader
then validates the value into its typed model, so nothing after it meets a wrong type.
"""
from __future__ import annotations

import json
import re

# what each file may weigh: far more than any real one, far less than would exhaust memory
MANIFEST_MAX_BYTES = 512 * 1024 * 1024   # a few hundred bytes a frame: a million frames
IGNORE_MAX_BYTES = 16 * 1024 * 1024      # ignore.json: rectangles
OBJECT_NAMES_MAX_BYTES = 64 * 1024 * 1024  # objects.json: at most 65535 names
GLTF_JSON_MAX_BYTES = 64 * 1024 * 1024   # a glTF file's JSON (its buffers are apart)

JSON_MAX_DEPTH = 64  # nesting of lists and objects; the files read here need a handful
_JSON_STRING = re.compile(r'"[^"\\]*(?:\\.[^"\\]*)*"', re.DOTALL)  # unrolled: linear even when unclosed
_NOT_A_BRACKET = re.compile(r"[^\[\]{}]+")
_INNERMOST_PAIR = re.compile(r"[\[{][\]}]")


class JsonProblem(ValueError):
    """Bytes that are not JSON within the bounds; the message says why in a few words."""


def parse_json(data: bytes, max_depth: int = JSON_MAX_DEPTH):
    """The JSON value of UTF-8 ``data`` (a byte-order mark allowed). Raises JsonProblem for
    text that is not UTF-8 or not JSON, nested deeper than ``max_depth``, or holding the
    non-standard NaN / Infinity."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise JsonProblem(f"not UTF-8 text (byte {exc.start})") from None
    if nested_deeper(text, max_depth):
        raise JsonProblem(f"nested more than {max_depth} deep")
    try:
        return json.loads(text, parse_constant=_not_standard)
    except JsonProblem:
        raise
    except json.JSONDecodeError as exc:
        raise JsonProblem(f"not JSON ({exc.msg}: line {exc.lineno} column {exc.colno})") from None
    except ValueError:  # an integer of more digits than Python converts (sys.get_int_max_str_digits)
        raise JsonProblem("not readable JSON (a number with thousands of digits)") from None


def nested_deeper(text: str, max_depth: int) -> bool:
    """Whether the lists and objects of JSON ``text`` nest deeper than ``max_depth``
    (brackets inside strings do not count). Each pass drops the innermost pairs of brackets,
    linear in C: a text nested d deep empties in d passes. Brackets left unpaired (text that
    is not JSON) count as deep as they could reach, so the decoder never meets more."""
    brackets = _NOT_A_BRACKET.sub("", _JSON_STRING.sub("", text))
    for passes in range(max_depth + 1):
        fewer = _INNERMOST_PAIR.sub("", brackets)
        if fewer == brackets:
            return passes + brackets.count("[") + brackets.count("{") > max_depth
        brackets = fewer
    return True


def _not_standard(constant: str):
    raise JsonProblem(f"not standard JSON ({constant} is no JSON number)")


