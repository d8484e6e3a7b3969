"""The guard every JSON file is read through (scenerender/json_input.py): bounded nesting,
UTF-8, standard JSON; and no module reads JSON around it."""
from __future__ import annotations

import ast
import json
from pathlib import Path

import pytest

from scenerender.json_input import JSON_MAX_DEPTH, JsonProblem, nested_deeper, parse_json

PACKAGE = Path(__file__).resolve().parent.parent / "scenerender"


def _nested(depth: int) -> str:
    return "[" * depth + "]" * depth


@pytest.mark.parametrize("depth", [1, JSON_MAX_DEPTH - 1, JSON_MAX_DEPTH])
def test_nesting_up_to_the_bound_is_read(depth):
    assert parse_json(_nested(depth).encode()) is not None


@pytest.mark.parametrize("depth", [JSON_MAX_DEPTH + 1, 1000, 100_000])
def test_nesting_beyond_the_bound_is_a_problem_not_a_recursion_error(depth):
    with pytest.raises(JsonProblem, match=f"nested more than {JSON_MAX_DEPTH} deep"):
        parse_json(_nested(depth).encode())


def test_brackets_inside_strings_do_not_count():
    text = json.dumps({"why": "[" * 500 + '\\"{{{', "list": [[1, "]]]]"], {"a": ["[["]}]})  # 4 deep
    assert not nested_deeper(text, 4)
    assert nested_deeper(text, 3)
    assert parse_json(text.encode(), max_depth=4)["why"].startswith("[[[")


@pytest.mark.parametrize("text", ["[" * 100_000, "[" * 100_000 + "]", '{"a": ' * 70])
def test_unclosed_brackets_count_as_deep_as_they_reach(text):
    with pytest.raises(JsonProblem, match="nested more than"):
        parse_json(text.encode())


def test_objects_and_lists_nest_alike():
    assert not nested_deeper('{"a": [{"b": [1]}]}', 4)
    assert nested_deeper('{"a": [{"b": [1]}]}', 3)


@pytest.mark.parametrize("data, reason", [
    (b"\xff\xfe{}", "not UTF-8 text (byte 0)"),
    (b'{"a": NaN}', "NaN is no JSON number"),
    (b"[Infinity]", "Infinity is no JSON number"),
    (b'{"a": 1,', "not JSON (Expecting property name enclosed in double quotes: line 1 column 9)"),
    (b'"unclosed', "not JSON (Unterminated string"),
    (b"1" * 5000, "a number with thousands of digits"),
])
def test_what_is_not_json_within_the_bounds_says_why(data, reason):
    with pytest.raises(JsonProblem) as caught:
        parse_json(data)
    assert reason in str(caught.value)


def test_a_byte_order_mark_and_lone_surrogate_escapes_are_read():
    assert parse_json(b'\xef\xbb\xbf{"why": "\\ud800"}') == {"why": "\ud800"}


def _json_calls(path: Path) -> list[int]:
    """Lines of ``path`` that call json.load or json.loads."""
    lines = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in ("load", "loads")
                and isinstance(node.func.value, ast.Name) and node.func.value.id == "json"):
            lines.append(node.lineno)
    return lines


def test_no_module_reads_json_around_the_guard():
    """Only the guard decodes JSON, and the scene reference its own generated schema."""
    allowed = {PACKAGE / "json_input.py", PACKAGE / "scene" / "reference.py"}
    found = {str(path.relative_to(PACKAGE)): _json_calls(path) for path in PACKAGE.rglob("*.py") if path not in allowed}
    assert {name: lines for name, lines in found.items() if lines} == {}
