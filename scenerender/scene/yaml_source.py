"""Read a YAML scene file into plain Python data plus the source position of every value.

This is the boundary where an untrusted scene file becomes data, so everything here is
bounded: the file must be a regular file no larger than ``Limits.yaml_bytes``; nesting is
at most ``Limits.yaml_depth`` deep; aliases may be used ``Limits.yaml_aliases`` times and
may copy at most ``Limits.yaml_alias_nodes`` values in all (a "billion laughs" document
fails after that much work, whether or not the scene uses the alias); an alias inside the
value it names is an error. Every problem is a ``UserError`` with the file and line.

PyYAML's loaders follow YAML 1.1, where ``1e6`` is a string and ``yes`` is a boolean. The
contract says YAML 1.2, so plain scalars are resolved here with the YAML 1.2 core schema.
The document is built from the parser's event stream (libyaml's when PyYAML has it, which
is many times faster than the pure-Python scanner) by a loop with an explicit stack, so
no input can exhaust Python's recursion limit; the same loop records the line and column of
every key and value, which validation messages need, and makes duplicate keys an error
instead of silently keeping the last one.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.limits import Limits
from scenerender.scene.files import read_regular_file

# YAML 1.2 core schema, section 10.3.2.
_NULL = re.compile(r"^(?:~|null|Null|NULL|)$")
_BOOL = re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$")
_INT10 = re.compile(r"^[-+]?[0-9]+$")
_INT8 = re.compile(r"^0o[0-7]+$")
_INT16 = re.compile(r"^0x[0-9a-fA-F]+$")
_FLOAT = re.compile(r"^[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?$")
_INF = re.compile(r"^[-+]?\.(?:inf|Inf|INF)$")
_NAN = re.compile(r"^\.(?:nan|NaN|NAN)$")

# Whole numbers beyond what a float can hold are refused here, so that no later
# float(value) anywhere in scenerender can raise OverflowError on user input.
_LARGEST_INT = int(1.7976931348623157e308)
_MAX_INT_DIGITS = 400  # int() of more digits than Python allows would raise ValueError

_YAML = "tag:yaml.org,2002:"
_LOADER = yaml.CSafeLoader if getattr(yaml, "__with_libyaml__", False) else yaml.SafeLoader


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


# ---------------------------------------------------------------------------------------
# Reading the file


def load_yaml(path: Path, limits: Limits | None = None) -> tuple[object, SourceMap]:
    """Parse ``path`` into plain data (dict/list/str/int/float/bool/None) and its SourceMap.

    The data is None for an empty document (nothing, or only comments). Raises UserError
    with the file and line for unreadable files, files that are not regular files, files
    over ``limits.yaml_bytes``, bad UTF-8 and YAML errors.
    """
    limits = limits or Limits()
    shown = display_path(path)
    raw = read_regular_file(Path(path), "scene file", limits.yaml_bytes, "yaml_bytes")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise UserError(f"the scene file is not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start})",
                        SourceLocation(shown, line)) from None
    return parse_yaml_text(text, shown, limits)


# ---------------------------------------------------------------------------------------
# Scalars


def resolve_plain_scalar(text: str):
    """Interpret an unquoted scalar by the YAML 1.2 core schema (ints of any size)."""
    if _NULL.match(text):
        return None
    if _BOOL.match(text):
        return text.lower() == "true"
    if _INT10.match(text):
        return int(text) if len(text) <= _MAX_INT_DIGITS else _TOO_LONG
    if _INT8.match(text):
        return int(text[2:], 8) if len(text) <= _MAX_INT_DIGITS * 2 else _TOO_LONG
    if _INT16.match(text):
        return int(text[2:], 16) if len(text) <= _MAX_INT_DIGITS else _TOO_LONG
    if _FLOAT.match(text):
        return float(text)
    if _INF.match(text):
        return -math.inf if text.startswith("-") else math.inf
    if _NAN.match(text):
        return math.nan
    return text


_TOO_LONG = object()  # a whole number with more digits than anything meaningful


def _scalar(event, name: str):
    """The Python value of one scalar event; explicit tags are honoured and checked."""
    tag = event.tag
    if tag is None and event.implicit[0]:
        return _plain(event, name)
    if tag is None or tag == "!" or tag in (_YAML + "str", _YAML + "binary", _YAML + "timestamp"):
        return event.value
    if tag == _YAML + "float":
        value = _checked_number(resolve_plain_scalar(event.value.strip()), event, name)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise _error(f"!!float needs a number, got {event.value!r}", event, name)
        return float(value)
    if tag == _YAML + "int":
        value = _checked_number(resolve_plain_scalar(event.value.strip()), event, name)
        if isinstance(value, bool) or not isinstance(value, int):
            raise _error(f"!!int needs a whole number (like 42, 0o17 or 0x1F), got {event.value!r}", event, name)
        return value
    if tag == _YAML + "bool":
        if not _BOOL.match(event.value.strip()):
            raise _error(f"!!bool needs true or false, got {event.value!r}", event, name)
        return event.value.strip().lower() == "true"
    if tag == _YAML + "null":
        if not _NULL.match(event.value.strip()):
            raise _error(f"!!null needs null or ~, got {event.value!r}", event, name)
        return None
    raise _error(f"unsupported YAML tag {_show_tag(tag)}", event, name)


def _show_tag(tag: str) -> str:
    return "!!" + tag[len(_YAML):] if tag.startswith(_YAML) else tag


_PLAIN_CACHE: dict = {}


def _plain(event, name: str):
    """``resolve_plain_scalar`` for an untagged plain scalar event, checked, with a cache:
    large scenes repeat the same few words and numbers many times."""
    text = event.value
    try:
        return _PLAIN_CACHE[text]
    except KeyError:
        pass
    value = _checked_number(resolve_plain_scalar(text), event, name)
    if len(text) <= 32:
        if len(_PLAIN_CACHE) >= 65536:
            _PLAIN_CACHE.clear()
        _PLAIN_CACHE[text] = value
    return value


def _checked_number(value, event, name: str):
    if value is _TOO_LONG or (isinstance(value, int) and not isinstance(value, bool) and abs(value) > _LARGEST_INT):
        raise _error("number too large (more than 1.8e308)", event, name)
    return value


def _error(message: str, event, name: str) -> UserError:
    return UserError(message, _location(name, event.start_mark))


def _location(name: str, mark) -> SourceLocation:
    return SourceLocation(name, mark.line + 1, mark.column + 1)


def _mark(event) -> tuple[int, int]:
    return event.start_mark.line + 1, event.start_mark.column + 1


# ---------------------------------------------------------------------------------------
# The document


def parse_yaml_text(text: str, shown_name: str, limits: Limits | None = None) -> tuple[object, SourceMap]:
    """Like ``load_yaml`` for text already in memory; ``shown_name`` appears in messages."""
    limits = limits or Limits()
    source = SourceMap(shown_name)
    if len(text) > limits.yaml_bytes:  # characters, not bytes: close enough for text from a CLI or a test
        raise UserError(f"the scene text is {len(text):,} characters, over the limit of {limits.yaml_bytes:,} "
                        "(raise with --limit yaml_bytes=N)", SourceLocation(shown_name))
    try:
        builder = _build(text, shown_name, limits, _LOADER)
    except _LibraryDepthLimit as refusal:
        if _LOADER is yaml.SafeLoader:
            raise refusal.error from None
        # libyaml (PyYAML 6.0.4 and later) stops at its own nesting limit while it scans ahead,
        # before our builder sees the level past ours; the pure-Python parser scans as far as
        # our builder asks, so our limit acts first and says where and how to raise it.
        try:
            builder = _build(text, shown_name, limits, yaml.SafeLoader)
        except _LibraryDepthLimit as again:
            raise again.error from None
    for is_key, path, mark in builder.entries:
        (source.keys if is_key else source.values)[path] = mark
    return builder.root, source


class _LibraryDepthLimit(Exception):
    """The YAML library refused a nesting depth of its own accord; ``error`` is what a user reads."""

    def __init__(self, error: UserError):
        super().__init__(str(error))
        self.error = error


def _is_depth_refusal(exc: yaml.MarkedYAMLError) -> bool:
    return "nesting" in (exc.problem or "")  # libyaml: "exceeded maximum nesting depth"


def _build(text: str, shown_name: str, limits: Limits, loader) -> "_Builder":
    """Feed the parser's events for ``text`` to a new builder; library errors become UserError."""
    builder = _Builder(shown_name, limits)
    try:
        for event in yaml.parse(text, Loader=loader):
            builder.feed(event)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = _location(shown_name, mark) if mark else SourceLocation(shown_name)
        if _is_depth_refusal(exc):
            raise _LibraryDepthLimit(UserError(
                f"nested deeper than the YAML reader allows (PyYAML {yaml.__version__}: {exc.problem}), "
                f"whatever --limit yaml_depth says", where)) from None
        raise UserError(f"YAML syntax error: {exc.problem or exc.context}", where) from None
    except yaml.reader.ReaderError as exc:
        raise _reader_error(exc, text, shown_name) from None
    except UnicodeEncodeError as exc:  # text from outside a file (an argument) holding undecodable bytes
        raise UserError(f"not valid UTF-8 text (at character {exc.start})", SourceLocation(shown_name)) from None
    except yaml.YAMLError as exc:
        raise UserError(f"YAML error: {exc}", SourceLocation(shown_name)) from None
    return builder


def _reader_error(exc, text: str, name: str) -> UserError:
    """A character YAML does not allow (NUL, other control characters), located by line."""
    position = max(0, min(exc.position, len(text)))
    line = text.count("\n", 0, position) + 1
    column = position - (text.rfind("\n", 0, position) + 1) + 1
    what = f"#x{exc.character:04x}" if isinstance(exc.character, int) else repr(exc.character)
    return UserError(f"character {what} is not allowed in YAML ({exc.reason})", SourceLocation(name, line, column))


class _Anchor:
    """A finished anchored value: what an alias copies, with its positions and cost."""

    __slots__ = ("value", "path", "entries", "size", "depth")

    def __init__(self, value, path, entries, size, depth):
        self.value, self.path, self.entries, self.size, self.depth = value, path, entries, size, depth


class _Open:
    """A mapping or sequence being built; ``key`` is the mapping key waiting for its value."""

    __slots__ = ("data", "path", "anchor", "first_entry", "size", "depth", "is_map", "key", "key_lines", "merges")

    def __init__(self, data, path, anchor, first_entry):
        self.data, self.path, self.anchor, self.first_entry = data, path, anchor, first_entry
        self.size, self.depth = 1, 1
        self.is_map = isinstance(data, dict)
        self.key = _NO_KEY
        self.key_lines: dict = {}
        self.merges: list = []


_NO_KEY = object()


class _Builder:
    """Builds plain data from parser events with an explicit stack (no recursion).

    ``entries`` lists ``(is_key, path, (line, column))`` in document order; an anchored
    value's slice of it is replayed, re-rooted, wherever an alias copies the value.
    """

    def __init__(self, name: str, limits: Limits):
        self.name = name
        self.limits = limits
        self.entries: list = []
        self.anchors: dict = {}
        self.open_anchors: set = set()
        self.stack: list[_Open] = []
        self.root = None
        self.documents = 0
        self.alias_uses = 0
        self.alias_nodes = 0

    def feed(self, event) -> None:
        kind = type(event)
        if kind is yaml.ScalarEvent:
            self._scalar(event)
        elif kind is yaml.MappingStartEvent:
            self._open(event, {})
        elif kind is yaml.SequenceStartEvent:
            self._open(event, [])
        elif kind is yaml.MappingEndEvent or kind is yaml.SequenceEndEvent:
            self._close()
        elif kind is yaml.AliasEvent:
            self._alias(event)
        elif kind is yaml.DocumentStartEvent:
            self.documents += 1
            if self.documents > 1:
                raise _error("a scene file holds one YAML document; found a second one ('---')", event, self.name)
            self.anchors.clear()

    # -- where the next value goes

    def _slot(self) -> tuple | None:
        """The path of the value that ``event`` starts, or None when it is a mapping key."""
        if not self.stack:
            return ()
        top = self.stack[-1]
        if not top.is_map:
            return top.path + (len(top.data),)
        if top.key is _NO_KEY:
            return None
        return top.path + (top.key,)

    def _place(self, value, path: tuple, first_entry: int, size: int, depth: int) -> None:
        """Put a finished value into its parent (or make it the document)."""
        if not self.stack:
            self.root = value
            return
        top = self.stack[-1]
        top.size += size
        top.depth = max(top.depth, depth + 1)
        if not top.is_map:
            top.data.append(value)
        elif top.key is _MERGE_KEY:
            merged_entries = self.entries[first_entry:]
            del self.entries[first_entry:]
            top.merges.append((value, path, merged_entries))
            top.key = _NO_KEY
        else:
            top.data[top.key] = value
            top.key = _NO_KEY

    def _key(self, value, event) -> None:
        top = self.stack[-1]
        if isinstance(value, (int, float)):  # a plain key is kept as written; this is a tagged or aliased one
            value = str(value)
        if not isinstance(value, str):
            raise _error("mapping keys must be plain text", event, self.name)
        if value in top.key_lines:
            shown = value if len(value) <= 60 else value[:57] + "..."
            raise _error(f"duplicate key '{shown}' (first given on line {top.key_lines[value]})", event, self.name)
        top.key_lines[value] = event.start_mark.line + 1
        top.key = value
        self.entries.append((True, top.path + (value,), _mark(event)))

    def _is_merge_key(self, event) -> bool:
        return event.tag == _YAML + "merge" or (event.tag is None and event.implicit[0] and event.value == "<<")

    # -- events

    def _scalar(self, event) -> None:
        # the hot path of a large scene (most events are scalars), hence written out inline
        top = self.stack[-1] if self.stack else None
        if top is not None and top.is_map and top.key is _NO_KEY:
            if self._is_merge_key(event):
                top.key = _MERGE_KEY
                return
            key = event.value if event.tag is None else _scalar(event, self.name)
            self._remember(event.anchor, key, (), len(self.entries), 1, 0)
            self._key(key, event)
            return
        if top is None:
            path = ()
        else:
            path = top.path + ((top.key,) if top.is_map else (len(top.data),))
        if event.tag is None and event.implicit[0]:
            value = _plain(event, self.name)
        else:
            value = _scalar(event, self.name)
        first = len(self.entries)
        mark = event.start_mark
        self.entries.append((False, path, (mark.line + 1, mark.column + 1)))
        if event.anchor is not None:
            self._remember(event.anchor, value, path, first, 1, 0)
        if top is None or top.key is _MERGE_KEY:
            self._place(value, path, first, 1, 0)
        elif top.is_map:
            top.size += 1
            top.data[top.key] = value
            top.key = _NO_KEY
        else:
            top.size += 1
            top.data.append(value)

    def _open(self, event, data) -> None:
        path = self._slot()
        if path is None:
            raise _error("mapping keys must be plain text, not a list or mapping", event, self.name)
        if event.tag not in (None, "!", _YAML + "map", _YAML + "seq"):
            raise _error(f"unsupported YAML tag {_show_tag(event.tag)}", event, self.name)
        if len(self.stack) >= self.limits.yaml_depth:
            raise _error(f"nested more than {self.limits.yaml_depth} levels deep "
                         f"(raise with --limit yaml_depth=N)", event, self.name)
        if event.anchor is not None:  # a redefined anchor names this value from here on (also inside it)
            self.anchors.pop(event.anchor, None)
            self.open_anchors.add(event.anchor)
        first = len(self.entries)
        self.entries.append((False, path, _mark(event)))
        self.stack.append(_Open(data, path, event.anchor, first))

    def _close(self) -> None:
        done = self.stack.pop()
        if done.is_map and done.merges:
            self._merge(done)
        if done.anchor is not None:
            self.open_anchors.discard(done.anchor)
        self._remember(done.anchor, done.data, done.path, done.first_entry, done.size, done.depth)
        self._place(done.data, done.path, done.first_entry, done.size, done.depth)

    def _alias(self, event) -> None:
        anchor = self.anchors.get(event.anchor)
        if anchor is None:
            if event.anchor in self.open_anchors:
                raise _error(f"alias *{event.anchor} is used inside the value it names (a value cannot contain "
                             "itself)", event, self.name)
            raise _error(f"unknown alias *{event.anchor} (no anchor &{event.anchor} before it)", event, self.name)
        self._charge_alias(anchor, event)
        path = self._slot()
        if path is None:
            self._key(anchor.value, event)
            return
        first = len(self.entries)
        cut = len(anchor.path)
        self.entries.extend((is_key, path + at[cut:], mark) for is_key, at, mark in anchor.entries)
        self._place(_copy(anchor.value), path, first, anchor.size, anchor.depth)

    def _charge_alias(self, anchor: _Anchor, event) -> None:
        """Count this alias use against the limits before copying anything."""
        limits = self.limits
        self.alias_uses += 1
        self.alias_nodes += anchor.size
        if self.alias_uses > limits.yaml_aliases:
            raise _error(f"more than {limits.yaml_aliases:,} alias uses (raise with --limit yaml_aliases=N)",
                         event, self.name)
        if self.alias_nodes > limits.yaml_alias_nodes:
            raise _error(f"aliases expand to more than {limits.yaml_alias_nodes:,} values "
                         f"(raise with --limit yaml_alias_nodes=N)", event, self.name)
        if len(self.stack) + anchor.depth > limits.yaml_depth:
            raise _error(f"alias *{event.anchor} nests the document more than {limits.yaml_depth} levels deep "
                         f"(raise with --limit yaml_depth=N)", event, self.name)

    def _remember(self, anchor: str | None, value, path: tuple, first_entry: int, size: int, depth: int) -> None:
        if anchor is not None:
            self.anchors[anchor] = _Anchor(value, path, self.entries[first_entry:], size, depth)

    def _merge(self, mapping: _Open) -> None:
        """YAML merge keys (``<<: *defaults`` or ``<<: [*a, *b]``): keys of the merged mappings
        not set here, earlier mappings first; positions of merged keys point at the mapping
        they come from."""
        for value, path, entries in mapping.merges:
            sources = [(value, path)] if isinstance(value, dict) else None
            if isinstance(value, list) and all(isinstance(item, dict) for item in value):
                sources = [(item, path + (i,)) for i, item in enumerate(value)]
            if sources is None:
                line, column = entries[0][2] if entries else (None, None)
                raise UserError("'<<' merges only mappings (or a list of mappings)",
                                SourceLocation(self.name, line, column))
            for data, prefix in sources:
                adopted = {key for key in data if key not in mapping.data}
                for key in adopted:
                    mapping.data[key] = data[key]
                cut = len(prefix)
                self.entries.extend((is_key, mapping.path + at[cut:], mark) for is_key, at, mark in entries
                                    if len(at) > cut and at[:cut] == prefix and at[cut] in adopted)


_MERGE_KEY = object()  # _Open.key while the value of a '<<' key is being built


def _copy(value):
    """An unshared copy of alias data (aliased values must not change together under --set).
    Depth is bounded by ``Limits.yaml_depth``, checked before copying."""
    if isinstance(value, dict):
        return {key: _copy(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_copy(item) for item in value]
    return value
