"""Read a YAML scene file into plain Python data plus the source position of every value.

PyYAML's loaders follow YAML 1.1, where ``1e6`` is a string and ``yes`` is a boolean. The
contract says YAML 1.2, so plain scalars are resolved here with the YAML 1.2 core schema.
Composing the node tree ourselves also keeps the line and column of every key and value,
which validation messages need, and lets duplicate keys be an error instead of silently
keeping the last one.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from scenerender.errors import SourceLocation, UserError, display_path

# YAML 1.2 core schema, section 10.3.2.
_NULL = re.compile(r"^(?:~|null|Null|NULL|)$")
_BOOL = re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$")
_INT10 = re.compile(r"^[-+]?[0-9]+$")
_INT8 = re.compile(r"^0o[0-7]+$")
_INT16 = re.compile(r"^0x[0-9a-fA-F]+$")
_FLOAT = re.compile(r"^[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?$")
_INF = re.compile(r"^[-+]?\.(?:inf|Inf|INF)$")
_NAN = re.compile(r"^\.(?:nan|NaN|NAN)$")


@dataclass
class SourceMap:
    """Positions of keys and values in one YAML document, by key path.

    ``keys[path]`` is where the mapping key that leads to ``path`` is written;
    ``values[path]`` is where the value at ``path`` starts. Paths use str keys and int indices.
    """

    file: str
    keys: dict = field(default_factory=dict)
    values: dict = field(default_factory=dict)
    overrides: dict = field(default_factory=dict)  # path -> "--set a.b=c" text

    def locate(self, path: tuple) -> SourceLocation:
        """The most precise known position for ``path``: the path itself or its nearest parent."""
        probe = tuple(path)
        for override_path, text in self.overrides.items():
            if override_path[:len(probe)] == probe and probe:  # the error is in what --set wrote
                return SourceLocation(text)
        while True:
            if probe in self.overrides:
                return SourceLocation(self.overrides[probe])
            if probe in self.keys:
                return self._loc(self.keys[probe])
            if probe in self.values:
                return self._loc(self.values[probe])
            if not probe:
                return SourceLocation(self.file)
            probe = probe[:-1]

    def value_location(self, path: tuple) -> SourceLocation:
        """Where the value itself starts (for errors about a list item or a number)."""
        path = tuple(path)
        if path in self.overrides:
            return SourceLocation(self.overrides[path])
        if path in self.values:
            return self._loc(self.values[path])
        return self.locate(path)

    def _loc(self, mark) -> SourceLocation:
        line, column = mark
        return SourceLocation(self.file, line, column)


def resolve_plain_scalar(text: str):
    """Interpret an unquoted scalar by the YAML 1.2 core schema."""
    if _NULL.match(text):
        return None
    if _BOOL.match(text):
        return text.lower() == "true"
    if _INT10.match(text):
        return int(text)
    if _INT8.match(text):
        return int(text[2:], 8)
    if _INT16.match(text):
        return int(text[2:], 16)
    if _FLOAT.match(text):
        return float(text)
    if _INF.match(text):
        return -math.inf if text.startswith("-") else math.inf
    if _NAN.match(text):
        return math.nan
    return text


PLAIN_TAG = "tag:scenerender,plain"  # an untagged plain scalar, resolved by YAML 1.2 rules below


class _Composer(yaml.SafeLoader):
    """SafeLoader's composer; we only use it to build nodes, never to construct objects.

    Untagged plain scalars get PLAIN_TAG instead of PyYAML's YAML 1.1 guess, so explicit
    tags (``!!str 123``) stay distinguishable and are honoured.
    """

    def resolve(self, kind, value, implicit):
        if kind is yaml.ScalarNode and implicit[0]:
            return PLAIN_TAG
        return super().resolve(kind, value, implicit)


def load_yaml(path: Path) -> tuple[object, SourceMap]:
    """Parse ``path`` into plain data (dict/list/str/int/float/bool/None) and its SourceMap.

    Raises UserError with the file and line for unreadable files and YAML syntax errors.
    """
    shown = display_path(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise UserError("scene file not found", SourceLocation(shown)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise UserError(f"cannot read scene file ({exc})", SourceLocation(shown)) from None
    return parse_yaml_text(text, shown)


def parse_yaml_text(text: str, shown_name: str) -> tuple[object, SourceMap]:
    """Like ``load_yaml`` for text already in memory; ``shown_name`` appears in messages."""
    source = SourceMap(shown_name)
    try:
        node = yaml.compose(text, Loader=_Composer)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = SourceLocation(shown_name, mark.line + 1, mark.column + 1) if mark else SourceLocation(shown_name)
        raise UserError(f"YAML syntax error: {exc.problem or exc.context}", where) from None
    except yaml.YAMLError as exc:
        raise UserError(f"YAML error: {exc}", SourceLocation(shown_name)) from None
    if node is None:
        return {}, source
    return _to_data(node, (), source), source


def _mark(node) -> tuple[int, int]:
    return node.start_mark.line + 1, node.start_mark.column + 1


def _to_data(node, path: tuple, source: SourceMap):
    source.values[path] = _mark(node)
    if isinstance(node, yaml.ScalarNode):
        return _scalar(node, source)
    if isinstance(node, yaml.SequenceNode):
        return [_to_data(item, path + (i,), source) for i, item in enumerate(node.value)]
    if isinstance(node, yaml.MappingNode):
        return _mapping(node, path, source)
    raise UserError("unsupported YAML node", source.value_location(path))  # pragma: no cover


def _scalar(node: yaml.ScalarNode, source: SourceMap):
    tag = node.tag
    if tag == PLAIN_TAG:
        return resolve_plain_scalar(node.value)
    if tag in ("tag:yaml.org,2002:str", "tag:yaml.org,2002:binary", "tag:yaml.org,2002:timestamp"):
        return node.value
    if tag == "tag:yaml.org,2002:float":
        return float(resolve_plain_scalar(node.value))
    if tag == "tag:yaml.org,2002:int":
        return int(node.value)
    if tag == "tag:yaml.org,2002:bool":
        return node.value.lower() == "true"
    if tag == "tag:yaml.org,2002:null":
        return None
    raise UserError(f"unsupported YAML tag {tag}", SourceLocation(source.file, *_mark(node)))


def _is_merge_key(node) -> bool:
    return node.tag == "tag:yaml.org,2002:merge" or (isinstance(node, yaml.ScalarNode) and node.style is None
                                                      and node.value == "<<")


def _mapping(node: yaml.MappingNode, path: tuple, source: SourceMap) -> dict:
    result: dict = {}
    merges = []
    for key_node, value_node in node.value:
        if _is_merge_key(key_node):
            merges.append(value_node)
            continue
        key = _key(key_node, path, source)
        if key in result:
            first = source.keys[path + (key,)][0]
            raise UserError(f"duplicate key '{key}' (first given on line {first})",
                            SourceLocation(source.file, *_mark(key_node)))
        source.keys[path + (key,)] = _mark(key_node)
        result[key] = _to_data(value_node, path + (key,), source)
    for value_node in merges:
        _merge_into(result, value_node, path, source)
    return result


def _key(key_node, path: tuple, source: SourceMap) -> str:
    key = _to_data(key_node, path + ("<key>",), source)
    source.values.pop(path + ("<key>",), None)
    if isinstance(key, (int, float, bool)):
        key = str(key)
    if not isinstance(key, str):
        raise UserError("mapping keys must be plain text", SourceLocation(source.file, *_mark(key_node)))
    return key


def _merge_into(result: dict, value_node, path: tuple, source: SourceMap) -> None:
    """YAML merge keys (``<<: *defaults``): keys from the merged mappings that are not set
    here; positions of merged keys point at the anchored mapping they come from."""
    nodes = value_node.value if isinstance(value_node, yaml.SequenceNode) else [value_node]
    for merged in nodes:
        if not isinstance(merged, yaml.MappingNode):
            raise UserError("'<<' merges only mappings", SourceLocation(source.file, *_mark(merged)))
        scratch = SourceMap(source.file)
        data = _mapping(merged, path, scratch)
        for key, value in data.items():
            if key not in result:
                result[key] = value
                _copy_positions(scratch, source, path + (key,))


def _copy_positions(src: SourceMap, dst: SourceMap, prefix: tuple) -> None:
    for table_src, table_dst in ((src.keys, dst.keys), (src.values, dst.values)):
        for key_path, mark in table_src.items():
            if key_path[:len(prefix)] == prefix:
                table_dst.setdefault(key_path, mark)
