"""The scene-format reference, ``docs/scene-format.md``, generated from the format's models.

``scenerender schema --markdown`` (or ``python -m scenerender.scene.reference``) prints it.
What can drift is generated: each key's type, range or choices, default, whether it takes
a keyframe track, and which keys exist at all, are read from the JSON Schema that the
pydantic models of ``scene/model/`` produce (the same schema ``scenerender schema`` prints).
What a key means, and an example, are written in ``reference_keys.py``, keyed by key path;
``tests/test_format_reference.py`` fails when a key lacks an entry, when an entry names a
key that no longer exists, when an example does not validate, and when the committed
``docs/scene-format.md`` or ``scene.schema.json`` differs from what this module prints.

Key paths: ``render.fog.density``; ``[]`` for a list item (``objects[].position``);
``[tag]`` for one member of a union chosen by a key (``lights[spot].inner_angle``,
``objects[].mesh[sphere].radius``); ``<name>`` for a value in a mapping of names
(``materials.<name>.diffuse``). An entry written with ``[]`` in place of a ``[tag]``
covers every member (``lights[].color``).
"""
from __future__ import annotations

import dataclasses
import json
import re
from dataclasses import dataclass

from scenerender.limits import Limits
from scenerender.scene.json_schema import scene_json_schema
from scenerender.scene.reference_keys import KEYS
from scenerender.scene.reference_text import HEADER, SECTIONS, Section

REGENERATE = "scenerender schema --markdown -o docs/scene-format.md"


@dataclass(frozen=True)
class KeyRow:
    """One key of the format as the reference shows it (all fields are Markdown text)."""

    path: str        # full key path, e.g. "lights[spot].inner_angle"
    name: str        # the key as written in a scene, e.g. "inner_angle"
    type_text: str   # "number in [0, 89.9]", "one of `exp`, `exp2`, `linear`"
    default: str     # "`2048`", "required", "not set"
    animatable: str  # "yes", "yes (step)" or ""
    fixed: str | None = None  # the one value a union's choosing key has here (``spot``)


@dataclass(frozen=True)
class Table:
    """The keys of one mapping of the format, e.g. ``render.fog`` or ``lights[spot]``."""

    path: str
    title: str
    rows: tuple[KeyRow, ...]

    @property
    def section(self) -> str:
        """The top-level key this mapping lives under ("" for the top level itself)."""
        return re.split(r"[.\[]", self.path, maxsplit=1)[0]


# ---------------------------------------------------------------------------------------
# Reading the JSON Schema


def _is_track(schema: dict) -> bool:
    """The keyframe-track branch of an animatable value (see ``values._track_schema``)."""
    return schema.get("type") == "object" and "keys" in schema.get("properties", {})


def _alternatives(schema: dict) -> list[dict]:
    """The branches of nested anyOf/oneOf unions, flattened, in order (null included)."""
    branches = schema.get("anyOf") or schema.get("oneOf")
    if not branches:
        return [schema]
    return [leaf for branch in branches for leaf in _alternatives(branch)]


def _ref_name(schema: dict) -> str:
    return schema["$ref"].rsplit("/", 1)[-1]


def _tag_of(definition: dict) -> tuple[str, str] | None:
    """(key, value) of the constant that picks this member of a union (``type: spot``)."""
    for key, value in definition.get("properties", {}).items():
        if "const" in value and isinstance(value["const"], str):
            return key, value["const"]
    return None


def _number(value) -> str:
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return repr(value) if isinstance(value, float) else str(value)


def _flow(value) -> str:
    """A value written as YAML flow text: ``[640, 480]``, ``blinn_phong``, ``true``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "null"
    if isinstance(value, (int, float)):
        return _number(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_flow(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_flow(v)}" for k, v in value.items()) + "}"
    return str(value)


def _interval(schema: dict) -> str:
    """' in [0, 1]', ' in (0, 1000]', ' ≥ 0', ' > 0' or '' from JSON Schema bounds."""
    lo, lo_open = schema.get("minimum"), False
    if "exclusiveMinimum" in schema:
        lo, lo_open = schema["exclusiveMinimum"], True
    hi, hi_open = schema.get("maximum"), False
    if "exclusiveMaximum" in schema:
        hi, hi_open = schema["exclusiveMaximum"], True
    if lo is not None and hi is not None:
        return f" in {'(' if lo_open else '['}{_number(lo)}, {_number(hi)}{')' if hi_open else ']'}"
    if lo is not None:
        return f" {'>' if lo_open else '≥'} {_number(lo)}"
    if hi is not None:
        return f" {'<' if hi_open else '≤'} {_number(hi)}"
    return ""


def _is_colour(schema: dict) -> bool:
    item = schema.get("items", {})
    return (schema.get("type") == "array" and schema.get("minItems") == 3 and schema.get("maxItems") == 4
            and item.get("minimum") == 0 and item.get("maximum") == 1)


def _opaque(value):
    """Colours compared as written: a validated default carries the alpha 1 that the
    written default leaves out (only colours have four components)."""
    if isinstance(value, (list, tuple)) and len(value) == 4 and value[3] == 1.0:
        return list(value[:3])
    return list(value) if isinstance(value, tuple) else value


class SchemaWalker:
    """Turns the scene's JSON Schema into tables of keys, one per mapping of the format.

    Each model (a ``$defs`` entry) gets one table, at the first key path where it appears
    in the format's order; later uses point to that table. ``SAME_KEYS_AS`` folds models
    that repeat another's keys (a light's own shadow settings) into that other's table.
    """

    SAME_KEYS_AS = {"ShadowOverride": "ShadowSettings"}

    def __init__(self, schema: dict):
        self.defs = schema.get("$defs", {})
        self.root = schema
        self.home: dict[str, str] = {}  # model name -> key path of its table
        self.tables: list[Table] = []

    def walk(self) -> list[Table]:
        self._table(self.root, "", "top level")
        return self.tables

    def _table(self, model: dict, path: str, title: str) -> None:
        required = set(model.get("required", ()))
        rows, nested = [], []
        for name, field in self._fields_tag_first(model):
            key = f"{path}.{name}" if path else name
            for member_path, ref in self._models_in(field, key):
                if ref not in self.home and ref not in self.SAME_KEYS_AS:
                    self.home[ref] = member_path
                    nested.append((member_path, ref))
            rows.append(self._row(key, name, field, name in required))
        self.tables.append(Table(path, title, tuple(rows)))
        for member_path, ref in nested:
            self._table(self.defs[ref], member_path, self._title(member_path, ref))

    @staticmethod
    def _fields_tag_first(model: dict) -> list[tuple[str, dict]]:
        """The model's keys in declaration order, except that the key choosing a union
        member (``type``, ``primitive``) comes first, as scenes write it."""
        fields = list(model.get("properties", {}).items())
        tag = _tag_of(model)
        return sorted(fields, key=lambda item: item[0] != tag[0]) if tag else fields

    def _title(self, path: str, ref: str) -> str:
        tag = _tag_of(self.defs[ref])
        if tag and path.endswith(f"[{tag[1]}]"):
            return f"`{path[: -len(tag[1]) - 2]}` with `{tag[0]}: {tag[1]}`"
        return f"`{path}`"

    def _models_in(self, schema: dict, path: str) -> list[tuple[str, str]]:
        """(key path, model name) of every model a value may hold, e.g. the light types."""
        found = []
        if "$ref" in schema:
            name = _ref_name(schema)
            tag = _tag_of(self.defs[name])
            found.append((f"{path}[{tag[1]}]" if tag else path, name))
        for branch in schema.get("anyOf", []) + schema.get("oneOf", []):
            found += self._models_in(branch, path)
        if schema.get("type") == "array" and isinstance(schema.get("items"), dict):
            for item_path, name in self._models_in(schema["items"], path + "[]"):
                found.append((item_path.replace("[][", "["), name))
        if isinstance(schema.get("additionalProperties"), dict):
            found += self._models_in(schema["additionalProperties"], path + ".<name>")
        return found

    # -- one row -------------------------------------------------------------------------
    def _row(self, path: str, name: str, field: dict, required: bool) -> KeyRow:
        branches = _alternatives(field)
        tracks = [b for b in branches if _is_track(b)]
        plain = [b for b in branches if not _is_track(b) and b.get("type") != "null"]
        animatable = ""
        if tracks:
            value = tracks[0]["properties"]["keys"]["items"]["anyOf"][0]["prefixItems"][1]
            animatable = "yes (step)" if value.get("type") == "boolean" else "yes"
        colour = any(_is_colour(b) for b in plain)
        refs = [_ref_name(b) for b in plain if "$ref" in b]
        own_defaults = {}
        if len(refs) == 1:
            own_defaults = {k: v.get("default") for k, v in self.defs[refs[0]].get("properties", {}).items()}
        default = self._default_text(field, required, colour, own_defaults)
        fixed = plain[0]["const"] if len(plain) == 1 and isinstance(plain[0].get("const"), str) else None
        return KeyRow(path, name, self._types_text(plain), default, animatable, fixed)

    def _types_text(self, branches: list[dict]) -> str:
        refs = [_ref_name(b) for b in branches if "$ref" in b]
        words = [self._type_text(b) for b in branches if "$ref" not in b]
        if refs:
            words.append(self._mapping_text(refs))
        return ", or ".join(words)

    def _mapping_text(self, refs: list[str]) -> str:
        refs = [self.SAME_KEYS_AS.get(r, r) for r in refs]
        if len(refs) == 1:
            return f"mapping (keys of `{self.home[refs[0]]}`)"
        tag_key = _tag_of(self.defs[refs[0]])[0]
        return f"mapping chosen by `{tag_key}` (keys below)"

    def _type_text(self, schema: dict) -> str:
        if "const" in schema:
            return f"`{_flow(schema['const'])}`"
        if "enum" in schema and len(schema["enum"]) == 1:
            return f"`{_flow(schema['enum'][0])}`"
        if "enum" in schema:
            return "one of " + ", ".join(f"`{_flow(v)}`" for v in schema["enum"])
        kind = schema.get("type")
        if kind in ("number", "integer"):
            return ("whole number" if kind == "integer" else "number") + _interval(schema)
        if kind == "boolean":
            return "`true` or `false`"
        if kind == "string":
            return schema.get("description", "text").replace("path relative to the scene file", "file path")
        if kind == "array":
            return self._array_text(schema)
        if kind == "object" and isinstance(schema.get("additionalProperties"), dict):
            return "mapping of names to " + self._types_text(_alternatives(schema["additionalProperties"]))
        raise ValueError(f"the reference has no wording for this schema yet: {json.dumps(schema)[:200]}")

    def _array_text(self, schema: dict) -> str:
        if _is_colour(schema):
            return "colour: 3 or 4 numbers in [0, 1] (linear RGB or RGBA)"
        items = _alternatives(schema.get("items", {}))
        low, high = schema.get("minItems"), schema.get("maxItems")
        if any("$ref" in b for b in items):
            return "list of " + self._types_text(items).replace("mapping", "mappings", 1)
        item = items[0]
        what = ("whole numbers" if item.get("type") == "integer" else "numbers") + _interval(item)
        count = f"{low} " if low is not None and low == high else ""
        return f"list of {count}{what}"

    @staticmethod
    def _default_text(field: dict, required: bool, colour: bool, own_defaults: dict) -> str:
        """``own_defaults``: when the value is a mapping, the defaults of its keys; a default
        mapping that only repeats them is shown as such rather than spelt out."""
        if required:
            return "required"
        value = field.get("default")
        if value is None:
            return "not set"
        if value in ({}, []):
            return "none"
        if isinstance(value, dict) and all(_opaque(own_defaults.get(k)) == _opaque(v) for k, v in value.items()):
            return "its keys' defaults"
        if colour and isinstance(value, list) and len(value) == 4 and value[3] == 1.0:
            value = value[:3]  # written as RGB; validation adds the opaque alpha
        return f"`{_flow(value)}`"


def scene_tables() -> list[Table]:
    """Every mapping of the format with its keys, in the format's order."""
    return SchemaWalker(json.loads(scene_json_schema())).walk()


# ---------------------------------------------------------------------------------------
# Descriptions, keyed by key path


def general_path(path: str) -> str:
    """The key path with union tags replaced by ``[]``: ``lights[spot].color`` -> ``lights[].color``."""
    return re.sub(r"\[[A-Za-z_]+\]", "[]", path)


def entry_for(path: str, keys: dict) -> str | None:
    """The entry of ``keys`` that describes ``path``: its own, else the untagged one."""
    if path in keys:
        return path
    general = general_path(path)
    return general if general in keys else None


def undocumented_keys(tables=None) -> list[str]:
    """Key paths of the schema that no entry of ``reference_keys.KEYS`` describes."""
    tables = scene_tables() if tables is None else tables
    return [row.path for table in tables for row in table.rows if entry_for(row.path, KEYS) is None]


def stale_entries(tables=None) -> list[str]:
    """Entries of ``reference_keys.KEYS`` that describe no key of the schema."""
    tables = scene_tables() if tables is None else tables
    used = {entry_for(row.path, KEYS) for table in tables for row in table.rows}
    return [path for path in KEYS if path not in used]


def editor_schema() -> str:
    """What ``scenerender schema`` prints (and ``scene.schema.json`` holds): the models'
    JSON Schema with each key's meaning from ``reference_keys`` as its ``description``,
    which editors show on hover and in completion lists."""
    schema = json.loads(scene_json_schema())
    walker = SchemaWalker(json.loads(scene_json_schema()))
    tables = walker.walk()
    model_at = {path: schema["$defs"][name] for name, path in walker.home.items()}
    model_at[""] = schema
    for table in tables:
        copies = [model_at[table.path]] + [schema["$defs"][same] for same, name in walker.SAME_KEYS_AS.items()
                                           if model_at[table.path] is schema["$defs"].get(name)]
        for row in table.rows:
            entry = KEYS.get(entry_for(row.path, KEYS) or "")
            for model in copies:
                if entry and row.name in model.get("properties", {}):
                    model["properties"][row.name]["description"] = entry.meaning
    return json.dumps(schema, indent=2)


# ---------------------------------------------------------------------------------------
# Markdown


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _table_markdown(table: Table, keys: dict) -> str:
    lines = ["| key | type, range or choices | default | animatable | meaning | example |",
             "|---|---|---|---|---|---|"]
    for row in table.rows:
        entry = keys.get(entry_for(row.path, keys) or "")
        meaning, example = (entry.meaning, entry.example) if entry else ("", "")
        example = f"`{row.name}: {row.fixed or example}`" if entry else ""
        cells = (f"`{row.name}`", row.type_text, row.default, row.animatable, meaning, example)
        lines.append("| " + " | ".join(_cell(c) for c in cells) + " |")
    return "\n".join(lines)


def _animatable_list(tables: list[Table]) -> str:
    """The animatable keys, one entry for a key every member of a union has."""
    paths = [general_path(row.path) for table in tables for row in table.rows if row.animatable]
    return ", ".join(f"`{p}`" for p in dict.fromkeys(paths))


def _limits_table() -> str:
    """The size limits and their defaults, from ``scenerender.limits.Limits``."""
    meanings = dict(re.findall(r"^\s+(\w+):\s+(.+(?:\n\s{5,}[^\s].*)*)", Limits.__doc__ or "", re.M))
    lines = ["| limit | default | what it bounds |", "|---|---|---|"]
    for field in dataclasses.fields(Limits):
        meaning = " ".join(meanings.get(field.name, "").split()).replace("``", "`")
        lines.append(f"| `{field.name}` | {field.default:,} | {_cell(meaning)} |")
    return "\n".join(lines)


def _is_main_table(table: Table, section: Section) -> bool:
    """The section's own mapping (``render``, each of ``objects``, each of ``materials``):
    its table sits right under the section heading, without one of its own."""
    return table.path in (section.key, f"{section.key}[]", f"{section.key}.<name>")


def _anchor(heading: str) -> str:
    """The fragment GitHub gives a heading: lower case, punctuation dropped, spaces to '-'."""
    return re.sub(r"[^\w\- ]", "", heading.replace("`", "").lower()).replace(" ", "-")


def _table_anchors(tables: list[Table]) -> dict[str, str]:
    """Key path of each table -> the fragment of the heading it sits under."""
    anchors, seen = {}, {}

    def unique(heading: str) -> str:  # GitHub numbers repeated fragments: x, x-1, x-2
        slug = _anchor(heading)
        count = seen.get(slug, 0)
        seen[slug] = count + 1
        return f"{slug}-{count}" if count else slug

    for section in SECTIONS:
        section_anchor = unique(section.heading)
        for table in (t for t in tables if section.key is not None and t.section == section.key):
            main = _is_main_table(table, section)
            anchors[table.path] = section_anchor if main else unique(table.title)
    return anchors


def _linked(text: str, anchors: dict[str, str]) -> str:
    """Turns "keys of `render.fog`" into a link to that table."""
    def link(match):
        path = match.group(1)
        return f"keys of [`{path}`](#{anchors[path]})" if path in anchors else match.group(0)

    return re.sub(r"keys of `([^`]+)`", link, text)


def _section_markdown(section: Section, tables: list[Table], keys: dict) -> list[str]:
    parts = [f"## {section.heading}", section.intro.strip()]
    for table in (t for t in tables if section.key is not None and t.section == section.key):
        if not _is_main_table(table, section):
            parts.append(f"### {table.title}")
        parts.append(_table_markdown(table, keys))
    if section.outro:
        parts.append(section.outro.strip())
    return parts


def reference_markdown() -> str:
    """The whole of ``docs/scene-format.md``."""
    tables = scene_tables()
    anchors = _table_anchors(tables)
    tables = [dataclasses.replace(t, rows=tuple(dataclasses.replace(r, type_text=_linked(r.type_text, anchors))
                                                for r in t.rows)) for t in tables]
    markers = {"@animatable_keys@": _animatable_list(tables), "@limits_table@": _limits_table(),
               "@regenerate@": REGENERATE}
    parts = [HEADER.strip()]
    for section in SECTIONS:
        parts += _section_markdown(section, tables, KEYS)
    text = "\n\n".join(parts) + "\n"
    for marker, value in markers.items():
        text = text.replace(marker, value)
    return text


def main() -> None:
    print(reference_markdown(), end="")


if __name__ == "__main__":  # pragma: no cover
    main()
