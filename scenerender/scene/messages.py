"""Turn pydantic validation errors into one-line messages with file, line, column and key.

A pydantic location mixes real keys with union tags such as "(track)" or "point"; walking
it against the data keeps only the steps that exist there, which gives the user's key path.
"""
from __future__ import annotations

from pydantic import ValidationError

from scenerender.errors import SceneErrors, SourceLocation, UserError
from scenerender.scene.describe import describe
from scenerender.scene.yaml_source import SourceMap

_GENERIC = {
    "list_type": "expected a list, got {got}",
    "dict_type": "expected a mapping (key: value), got {got}",
    "model_type": "expected a mapping (key: value), got {got}",
    "greater_than": "must be greater than {gt}, got {got}",
    "string_type": "expected text, got {got}",
    "too_short": "needs at least {min_length} item(s)",
    "too_long": "allows at most {max_length} item(s)",
    "literal_error": "expected {expected}, got {got}",
    "bool_type": "expected true or false, got {got}",
    "int_type": "expected a whole number, got {got}",
    "float_type": "expected a number, got {got}",
}


def data_path(loc: tuple, data) -> tuple:
    """The steps of ``loc`` that exist in ``data`` (drops union tags and validator names)."""
    path = []
    node = data
    for step in loc:
        if isinstance(node, dict) and step in node:
            path.append(step)
            node = node[step]
        elif isinstance(node, list) and isinstance(step, int) and 0 <= step < len(node):
            path.append(step)
            node = node[step]
    return tuple(path)


def format_key(path: tuple) -> str:
    """('objects', 2, 'mesh') -> 'objects[2].mesh'."""
    text = ""
    for step in path:
        if isinstance(step, int):
            text += f"[{step}]"
        else:
            text += ("." if text else "") + str(step)
    return text


def to_user_errors(exc: ValidationError, data, source: SourceMap) -> SceneErrors:
    """One UserError per validation problem, located in the scene file."""
    errors = []
    seen = set()
    for item in exc.errors(include_url=False):
        error = _one(item, data, source)
        if str(error) not in seen:
            seen.add(str(error))
            errors.append(error)
    return SceneErrors(errors)


class _NoLines:
    """Locates no key: a JSON file is read without a map of lines."""

    def locate(self, path: tuple) -> None:
        return None


def first_problem(exc: ValidationError, data) -> tuple[str | None, str]:
    """(key, message) of the first problem pydantic found in the JSON value ``data``."""
    error = to_user_errors(exc, data, _NoLines()).errors[0]
    return error.key, error.message


def json_file_error(exc: ValidationError, data, file: str) -> UserError:
    """The first problem pydantic found in the value ``data`` of the JSON file ``file``
    (as shown to the user): one line naming the file and the key."""
    key, message = first_problem(exc, data)
    return UserError(message, SourceLocation(file), key)


# top-level keys whose absence needs more than its name
MISSING_HINTS = {"objects": " (list what to draw; `objects: []` renders the background alone)"}


def _one(item: dict, data, source: SourceMap) -> UserError:
    context = item.get("ctx") or {}
    path = data_path(item["loc"], data) + tuple(context.get("subpath", ()))
    kind = item["type"]
    # the same mistake in many list items (objects[0].mesh, objects[1].mesh...) is one kind
    repeat = (kind, tuple("[]" if isinstance(step, int) else step for step in path))
    if kind == "missing":
        missing = item["loc"][-1]
        hint = MISSING_HINTS.get(missing, "") if len(item["loc"]) == 1 else ""
        return UserError(f"missing required key '{missing}'{hint}", source.locate(path), format_key(path) or None,
                         kind=repeat)
    message = _message(kind, item, context)
    location = source.locate(path)
    return UserError(message, location, _shortened(format_key(path)) or None, kind=repeat)


def _shortened(text: str, most: int = 100) -> str:
    """A key path through a user's megabyte-long key still fits on a line."""
    return text if len(text) <= most else text[:most - 3] + "..."


def _message(kind: str, item: dict, context: dict) -> str:
    template = _GENERIC.get(kind)
    if template is None:
        return item["msg"]
    values = dict(context)
    values["got"] = describe(item.get("input"))
    try:
        return template.format(**values)
    except (KeyError, IndexError):
        return item["msg"]


def single_error(message: str, path: tuple, source: SourceMap) -> UserError:
    """A UserError for a problem found after validation (e.g. while loading an asset)."""
    return UserError(message, source.locate(path), format_key(path) or None)
