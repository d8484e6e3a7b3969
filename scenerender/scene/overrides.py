"""``--set key.path=value``: change any key of the scene from the command line.

Paths use dots and indices: ``render.samples=8``, ``objects[1].position=[0,1,0]`` or
``objects.1.position=[0,1,0]``. Values are YAML (``[1, 2, 3]``, ``1e6``, ``true``, ``"text"``).
"""
from __future__ import annotations

import copy
import re

from scenerender.errors import SourceLocation, UserError
from scenerender.scene.messages import format_key
from scenerender.scene.yaml_source import SourceMap, parse_yaml_text

_STEP = re.compile(r"([^.\[\]]+)|\[(\d+)\]")


def parse_key_path(text: str) -> tuple:
    """'objects[1].position' -> ('objects', 1, 'position'); digits alone become indices."""
    steps = []
    for name, index in _STEP.findall(text):
        if index:
            steps.append(int(index))
        elif name.isdigit():
            steps.append(int(name))
        else:
            steps.append(name)
    rebuilt = "".join(f"[{s}]" if isinstance(s, int) else f".{s}" for s in steps).lstrip(".")
    if not steps or rebuilt.replace("[", ".[").replace("..", ".") == "":
        raise ValueError(text)
    return tuple(steps)


def apply_overrides(data: dict, overrides, source: SourceMap) -> dict:
    """A copy of ``data`` with each ``key=value`` applied in order; records their origin."""
    if not overrides:
        return data
    data = copy.deepcopy(data) if isinstance(data, dict) else {}
    for text in overrides:
        key, value = _split(text)
        path = _path(key, text)
        _set(data, path, value, text)
        source.overrides[path] = f"--set {text}"
    return data


def _split(text: str):
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:  # undecodable bytes in the argument (Python keeps them as surrogates)
        shown = text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
        raise UserError("not valid UTF-8 text", SourceLocation(f"--set {shown}")) from None
    key, sep, raw = text.partition("=")
    if not sep or not key.strip():
        raise UserError(f"--set expects key=value, got '{text}' (e.g. --set render.samples=8)",
                        SourceLocation("--set"))
    try:
        value, _ = parse_yaml_text(raw.strip() or '""', f"--set {text}")
    except UserError as exc:  # a line and column inside one option's value would only confuse
        raise UserError(exc.message, SourceLocation(f"--set {text}")) from None
    return key.strip(), value


def _path(key: str, text: str) -> tuple:
    try:
        return parse_key_path(key)
    except ValueError:
        raise UserError(f"cannot read key path '{key}'", SourceLocation(f"--set {text}")) from None


def _set(data, path: tuple, value, text: str) -> None:
    node = data
    for depth, step in enumerate(path[:-1]):
        nxt = path[depth + 1]
        if isinstance(step, int):
            if not isinstance(node, list) or step >= len(node):
                raise UserError(f"no item {step} at '{_show(path[:depth])}'", SourceLocation(f"--set {text}"))
            if node[step] is None:
                node[step] = [] if isinstance(nxt, int) else {}
            node = node[step]
        else:
            if not isinstance(node, dict):
                raise UserError(f"'{_show(path[:depth])}' is not a mapping", SourceLocation(f"--set {text}"))
            if node.get(step) is None:
                node[step] = [] if isinstance(nxt, int) else {}
            node = node[step]
    last = path[-1]
    if isinstance(last, int):
        if not isinstance(node, list) or last > len(node):
            raise UserError(f"no item {last} at '{_show(path[:-1])}'", SourceLocation(f"--set {text}"))
        if last == len(node):
            node.append(value)
        else:
            node[last] = value
    else:
        if not isinstance(node, dict):
            raise UserError(f"'{_show(path[:-1])}' is not a mapping", SourceLocation(f"--set {text}"))
        node[last] = value


def _show(path: tuple) -> str:
    return format_key(path) or "(top level)"
