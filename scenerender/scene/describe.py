"""How a message shows a value the user wrote: short, and as YAML would say it."""
from __future__ import annotations

from typing import Any

# The largest integer that converts to a float; a larger one has no float value at all.
LARGEST_FLOAT_INT = int(1.7976931348623157e308)


def describe(value: Any) -> str:
    """A short rendering of a bad value for messages."""
    if isinstance(value, str):
        return repr(value) if len(value) < 40 else repr(value[:37] + "...")
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return _describe_list(value)
    if value is None:
        return "nothing (null)"
    if isinstance(value, bool):
        return "true" if value else "false"  # as the YAML says it, not Python's True
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**15:
        return f"{float(value):.6g}" if abs(value) <= LARGEST_FLOAT_INT else "a number over 1.8e308"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _describe_list(items: list) -> str:
    """A short list of plain values as written ("[100000, 100000]"), else its length."""
    if len(items) <= 4 and all(isinstance(v, (int, float, str, bool)) or v is None for v in items):
        text = "[" + ", ".join(describe(v) for v in items) + "]"
        if len(text) <= 60:
            return text
    return f"a list of {len(items)}"
