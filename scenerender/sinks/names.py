"""Frame file-name templates (``output.name``): the only field is ``{frame}``, with an
optional integer format spec such as ``{frame:05d}``. Checked by parsing, never by
formatting an arbitrary template, so ``{frame.__class__}`` or ``{0}`` cannot reach
attributes, and a name can never contain a path separator or be ``.``/``..``: a frame
file cannot leave its output folder.

The scene model checks ``output.name`` with it and the image sinks check the pattern
they are given; it imports nothing of either.
"""
from __future__ import annotations

import re
import string

# [[fill]align][sign][z][#][0][width][grouping][.precision][type] with an integer type
_SPEC = re.compile(r"^(?:(?P<fill>.)?[<>=^])?[+\- ]?z?#?0?(?P<width>\d*)[,_]?(?P<type>[bdoxX])?$", re.DOTALL)
MAX_WIDTH = 32
# Room left for the image suffix and the temporary-name decoration within the 255-byte
# limit of common file systems.
MAX_NAME_BYTES = 200
_FORBIDDEN = ("/", "\\", "\0")
# What the output format appends: a name ending in one would get it twice (0001.png.png).
_FORMAT_SUFFIXES = (".png", ".jpg", ".jpeg", ".tga", ".exr", ".mp4", ".gif")


def name_template_problem(template: str, frame_count: int = 1) -> str | None:
    """Why ``template`` is not a valid frame name template, or None when it is.
    ``frame_count`` > 1 requires a ``{frame}`` field (else every frame has one name)."""
    try:
        parts = list(string.Formatter().parse(template))
    except ValueError as exc:  # unbalanced braces
        return f"{exc} (write {{{{ and }}}} for literal braces)"
    has_frame = False
    for _literal, field, spec, conversion in parts:
        if field is None:
            continue
        if field != "frame":
            return f"only {{frame}} may appear in the name, got {{{field}{'!' + conversion if conversion else ''}}}"
        if conversion:
            return f"conversions such as !{conversion} are not allowed"
        if spec and _spec_problem(spec):
            return _spec_problem(spec)
        has_frame = True
    if frame_count > 1 and not has_frame:
        return "name pattern must contain {frame} when there is more than one frame"
    suffix = next((end for end in _FORMAT_SUFFIXES if template.lower().endswith(end)), None)
    if suffix is not None:
        return f"the name is the file name without its suffix: leave out '{template[-len(suffix):]}' (the format adds it)"
    return _rendered_problem(template, frame_count)


def _spec_problem(spec: str) -> str | None:
    match = _SPEC.match(spec)
    if match is None:
        return f"'{spec}' is not an integer format spec (e.g. 04d, >6, x)"
    if match["width"] and int(match["width"]) > MAX_WIDTH:
        return f"width {match['width']} is more than {MAX_WIDTH}"
    return None


def _rendered_problem(template: str, frame_count: int) -> str | None:
    """Check the names of the first and last frame: fill characters pad the first, the
    last is the longest."""
    for frame in {0, max(frame_count - 1, 0)}:
        try:
            name = template.format(frame=frame)
        except ValueError as exc:  # a spec the pattern admits but int refuses, e.g. ',x'
            return f"bad format spec ({exc})"
        if any(mark in name for mark in _FORBIDDEN):
            return f"a frame name cannot contain '/' or '\\' (frame {frame} would be '{name}')"
        if name in ("", ".", ".."):
            return f"a frame name cannot be '{name}'"
        size = len(name.encode("utf-8", "surrogatepass"))
        if size > MAX_NAME_BYTES:
            return f"frame names would be {size} bytes long; at most {MAX_NAME_BYTES}"
    return None
