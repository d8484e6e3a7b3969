"""Wavefront MTL reader: the material statements the renderer uses.

Read keys (case-insensitive): Ka Kd Ks Ke Ns d Tr illum map_Ka map_Kd map_Ks map_Bump bump
norm map_d, and the PBR extension's Pr Pm map_Pr map_Pm map_Ke (roughness, metallic, their
single-channel maps, an emission map). Every other key (Ni, Tf, map_Ns, refl, Ps, ...) is
skipped silently, as the scene-file contract asks.
"""
from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

from scenerender.errors import SourceLocation, UserError, Warnings, display_path
from scenerender.mesh.capped import CappedWarnings
from scenerender.mesh.numbers import BEYOND_FLOAT32, beyond_float32, fits_float32
from scenerender.scene.assets import AssetPolicy, Lookup, policy_for, quoted
from scenerender.scene.files import read_regular_file

Color = tuple[float, float, float]


@dataclass(frozen=True)
class TextureRef:
    """A texture named in an MTL file.

    path:       where the image is (or, when ``missing``, where it was first looked for).
    scale:      (u, v) from ``-s``; texture coordinates are multiplied by it.
    offset:     (u, v) from ``-o``; added after scaling.
    bump_scale: ``-bm`` multiplier for normal / bump maps.
    location:   the MTL file and line that named it.
    missing:    True when no such file was found; the renderer draws a placeholder.
    """

    path: Path
    scale: tuple[float, float] = (1.0, 1.0)
    offset: tuple[float, float] = (0.0, 0.0)
    bump_scale: float = 1.0
    location: SourceLocation | None = None
    missing: bool = False


@dataclass(frozen=True)
class MtlMaterial:
    """One ``newmtl`` block. Every value is None when the file does not set it.

    Colours are linear RGB 3-tuples. ``opacity`` comes from ``d``, or ``1 - Tr`` when only
    ``Tr`` is given, clamped to [0, 1]. ``normal_map`` comes from map_Bump, bump or norm
    (the last of them in the block wins). ``roughness`` and ``metallic`` (``Pr``, ``Pm``)
    are clamped to [0, 1]; ``roughness_map`` and ``metallic_map`` (``map_Pr``, ``map_Pm``)
    are single-channel data, ``emissive_map`` (``map_Ke``) a colour map.
    """

    name: str
    ambient: Color | None = None
    diffuse: Color | None = None
    specular: Color | None = None
    emissive: Color | None = None
    shininess: float | None = None
    opacity: float | None = None
    illum: int | None = None
    roughness: float | None = None
    metallic: float | None = None
    ambient_map: TextureRef | None = None
    diffuse_map: TextureRef | None = None
    specular_map: TextureRef | None = None
    normal_map: TextureRef | None = None
    opacity_map: TextureRef | None = None
    roughness_map: TextureRef | None = None
    metallic_map: TextureRef | None = None
    emissive_map: TextureRef | None = None
    location: SourceLocation | None = None


_COLOR_KEYS = {"ka": "ambient", "kd": "diffuse", "ks": "specular", "ke": "emissive"}
_MAP_KEYS = {
    "map_ka": "ambient_map",
    "map_kd": "diffuse_map",
    "map_ks": "specular_map",
    "map_bump": "normal_map",
    "bump": "normal_map",
    "norm": "normal_map",
    "map_d": "opacity_map",
    "map_pr": "roughness_map",
    "map_pm": "metallic_map",
    "map_ke": "emissive_map",
}
_SCALAR_KEYS = {"ns", "d", "tr", "illum", "pr", "pm"}

# Texture options and how many arguments each takes (fewest, most). They have to be
# known to find where the file name starts, even the ones the renderer does not use.
_TEXTURE_OPTIONS = {
    "-blendu": (1, 1),
    "-blendv": (1, 1),
    "-bm": (1, 1),
    "-boost": (1, 1),
    "-cc": (1, 1),
    "-clamp": (1, 1),
    "-imfchan": (1, 1),
    "-mm": (2, 2),
    "-o": (1, 3),
    "-s": (1, 3),
    "-t": (1, 3),
    "-texres": (1, 1),
    "-type": (1, 1),
}

# CIE XYZ to linear sRGB (D65), for the rarely used "Kd xyz X Y Z" form.
_XYZ_TO_RGB = (
    (3.2404542, -1.5371385, -0.4985314),
    (-0.9692660, 1.8760108, 0.0415560),
    (0.0556434, -0.2040259, 1.0572252),
)


class _MtlContext:
    """The file being read, for error messages and for resolving texture paths."""

    def __init__(self, path: Path, warnings: Warnings, assets: AssetPolicy):
        self.path = path
        self.folder = path.parent
        self.shown = display_path(path)
        self.warnings = warnings
        self.assets = assets
        self.line = 0

    def location(self) -> SourceLocation:
        return SourceLocation(self.shown, self.line)

    def error(self, message: str) -> UserError:
        return UserError(message, self.location())

    def number(self, token: str, key: str) -> float:
        try:
            value = float(token)
        except ValueError:
            raise self.error(f"expected a number after '{key}', got {token!r}") from None
        if value != value or value in (float("inf"), float("-inf")):
            raise self.error(f"expected a finite number after '{key}', got {token!r}")
        if not fits_float32(value):  # colours, shininess and texture options reach the shaders as float32
            raise self.error(beyond_float32(value, key))
        return value


def parse_mtl(path: Path, warnings: Warnings, assets: AssetPolicy | None = None) -> dict[str, MtlMaterial]:
    """Read an MTL file into materials by name (a later ``newmtl`` of a name replaces an
    earlier one).

    Texture files are looked up through ``assets`` (default: the MTL's own folder is the
    only root) and recorded as read. Raises UserError (file and line) for malformed numbers
    and for a texture outside the allowed folders or not a regular file; warns about
    textures that cannot be found and marks them ``missing``; after the first few warnings
    of a file, one line counts the rest.
    """
    path = Path(path)
    text = read_regular_file(path, "MTL file").decode("utf-8", errors="surrogateescape")
    capped = CappedWarnings(warnings, display_path(path))
    ctx = _MtlContext(path, capped, assets if assets is not None else policy_for(path))
    materials = _parse_lines(text, ctx)
    capped.finish()
    return materials


def _parse_lines(text: str, ctx: _MtlContext) -> dict[str, MtlMaterial]:

    materials: dict[str, MtlMaterial] = {}
    current: dict | None = None
    for number, line in enumerate(text.splitlines(), 1):
        ctx.line = number
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        key, _, rest = stripped.partition(" ")
        if "\t" in key:  # the key may be followed by a tab instead of a space
            key, _, more = key.partition("\t")
            rest = more + " " + rest
        lowered = key.lower()
        if lowered == "newmtl":
            _finish(current, materials)
            current = _start_material(rest, ctx)
        elif lowered in _COLOR_KEYS or lowered in _MAP_KEYS or lowered in _SCALAR_KEYS:
            if current is None:
                ctx.warnings.warn(f"'{key}' before any 'newmtl' is ignored", ctx.location())
                continue
            _apply_statement(current, key, lowered, rest, ctx)
    _finish(current, materials)
    return materials


def _start_material(rest: str, ctx: _MtlContext) -> dict:
    name = rest.strip()
    if not name:
        raise ctx.error("'newmtl' needs a material name")
    return {"name": name, "location": ctx.location(), "_transmission": None}


def _finish(current: dict | None, materials: dict[str, MtlMaterial]) -> None:
    if current is None:
        return
    transmission = current.pop("_transmission")
    if current.get("opacity") is None and transmission is not None:
        current["opacity"] = _clamp01(1.0 - transmission)
    # A repeated name replaces the earlier definition, as in most viewers.
    materials[current["name"]] = MtlMaterial(**current)


def _apply_statement(current: dict, key: str, lowered: str, rest: str, ctx: _MtlContext) -> None:
    if lowered in _COLOR_KEYS:
        color = _parse_color(rest.split(), key, ctx)
        if color is not None:
            current[_COLOR_KEYS[lowered]] = color
    elif lowered in _MAP_KEYS:
        current[_MAP_KEYS[lowered]] = _parse_texture(rest, key, ctx)
    elif lowered == "ns":
        current["shininess"] = ctx.number(_first_argument(rest, key, ctx), key)
    elif lowered == "d":
        tokens = rest.split()
        if tokens and tokens[0].lower() == "-halo":  # "d -halo 0.5": the halo is not drawn
            tokens = tokens[1:]
        current["opacity"] = _clamp01(ctx.number(_first_argument(" ".join(tokens), key, ctx), key))
    elif lowered in ("pr", "pm"):
        value = _clamp01(ctx.number(_first_argument(rest, key, ctx), key))
        current["roughness" if lowered == "pr" else "metallic"] = value
    elif lowered == "tr":
        current["_transmission"] = ctx.number(_first_argument(rest, key, ctx), key)
    elif lowered == "illum":
        value = ctx.number(_first_argument(rest, key, ctx), key)
        if value != int(value):
            raise ctx.error(f"'illum' needs a whole number, got {value:g}")
        current["illum"] = int(value)


def _first_argument(rest: str, key: str, ctx: _MtlContext) -> str:
    tokens = rest.split()
    if not tokens:
        raise ctx.error(f"'{key}' needs a number")
    return tokens[0]


def _clamp01(value: float) -> float:
    return min(1.0, max(0.0, value))


def _parse_color(tokens: list[str], key: str, ctx: _MtlContext) -> Color | None:
    """``Kd r g b``, ``Kd r`` (grey), ``Kd xyz X Y Z``; ``Kd spectral file`` is not supported."""
    if tokens and tokens[0].lower() == "spectral":
        ctx.warnings.warn(f"spectral colour for '{key}' is not supported; ignored", ctx.location())
        return None
    from_xyz = bool(tokens) and tokens[0].lower() == "xyz"
    if from_xyz:
        tokens = tokens[1:]
    if len(tokens) in (0, 2):
        raise ctx.error(f"'{key}' needs 1 or 3 numbers, got {len(tokens)}")
    values = [ctx.number(token, key) for token in tokens[:3]]
    if len(values) == 1:
        values *= 3
    if from_xyz:
        values = [sum(m * v for m, v in zip(row, values)) for row in _XYZ_TO_RGB]
        if not all(fits_float32(v) for v in values):  # the matrix multiplies by up to 3.2
            raise ctx.error(f"'{key} xyz' gives a colour {BEYOND_FLOAT32}")
    return (values[0], values[1], values[2])


def _parse_texture(rest: str, key: str, ctx: _MtlContext) -> TextureRef:
    """A map statement: options, then a file name that is the whole rest of the line."""
    spans = [(m.group(), m.start()) for m in re.finditer(r"\S+", rest)]
    scale, offset, bump_scale = [1.0, 1.0], [0.0, 0.0], 1.0
    i = 0
    while i < len(spans) - 1 and spans[i][0].startswith("-"):
        option = spans[i][0].lower()
        arguments, i = _take_option_arguments(option, spans, i + 1, ctx)
        if option == "-s":
            scale[: len(arguments)] = [ctx.number(a, option) for a in arguments[:2]]
        elif option == "-o":
            offset[: len(arguments)] = [ctx.number(a, option) for a in arguments[:2]]
        elif option == "-bm":
            bump_scale = ctx.number(arguments[0], option)
        elif option in ("-mm", "-boost", "-texres"):
            for argument in arguments:  # unused, but a typo here is still worth reporting
                ctx.number(argument, option)
    if i >= len(spans):
        raise ctx.error(f"'{key}' needs a file name")
    name = rest[spans[i][1] :].strip()
    if len(name) >= 2 and name[0] == name[-1] == '"':
        name = name[1:-1]
    return _resolve_texture(name, scale, offset, bump_scale, ctx)


def _take_option_arguments(option: str, spans, i: int, ctx: _MtlContext) -> tuple[list[str], int]:
    """The arguments of ``option`` starting at spans[i], and the index after them.

    Always leaves at least one token for the file name.
    """
    last_usable = len(spans) - 1  # spans[last_usable] is the earliest the file name can be
    fewest, most = _TEXTURE_OPTIONS.get(option, (0, None))
    if option not in _TEXTURE_OPTIONS:
        ctx.warnings.warn(f"unknown texture option '{option}' ignored", ctx.location())
    arguments: list[str] = []
    while i < last_usable and len(arguments) < fewest:
        arguments.append(spans[i][0])
        i += 1
    if len(arguments) < fewest:
        raise ctx.error(f"texture option '{option}' needs {fewest} value(s) before the file name")
    # Optional trailing values (-s u [v [w]]) and the values of unknown options are taken
    # while they look like values.
    while i < last_usable and (most is None or len(arguments) < most):
        if not _looks_like_value(spans[i][0]):
            break
        arguments.append(spans[i][0])
        i += 1
    return arguments, i


def _looks_like_value(token: str) -> bool:
    if token.lower() in ("on", "off"):
        return True
    try:
        float(token)
    except ValueError:
        return False
    return True


def _resolve_texture(name: str, scale, offset, bump_scale: float, ctx: _MtlContext) -> TextureRef:
    lookups = [ctx.assets.lookup(str(candidate), ctx.folder) for candidate in _texture_candidates(name)]
    chosen = next((lookup for lookup in lookups if lookup.found), None)
    if chosen is None:
        chosen = _case_insensitive_match(lookups, ctx.assets)
    location = ctx.location()
    if chosen is None:
        refused = next((lookup for lookup in lookups if _refused(lookup)), None)
        if refused is not None:
            raise UserError(f"texture {refused.message}", location)
        ctx.warnings.warn(f"texture {_not_found(name, lookups)}; a placeholder is drawn instead", location)
    else:
        ctx.assets.record(chosen.path)
    return TextureRef(
        path=chosen.path if chosen is not None else lookups[0].path,
        scale=(scale[0], scale[1]),
        offset=(offset[0], offset[1]),
        bump_scale=bump_scale,
        location=location,
        missing=chosen is None,
    )


def _refused(lookup: Lookup) -> bool:
    """A texture that may not be read: outside the allowed folders, or not a regular file.
    Unlike a missing file, that is an error: a placeholder would hide a scene reaching for
    files it must not read. Whether a file outside is there is never looked at (the
    outcome, and the exit code, would tell): such a path is refused as written."""
    return lookup.problem in ("outside", "not_regular")


def _not_found(name: str, lookups: list[Lookup]) -> str:
    """Why no candidate was usable: a name the system rejects, or where it was looked for."""
    bad_name = next((lookup for lookup in lookups if lookup.problem == "bad_name"), None)
    if bad_name is not None:
        return bad_name.message
    folders = []
    for lookup in lookups:
        shown = display_path(lookup.path.parent) or "."
        if shown not in folders:
            folders.append(shown)
    return f"{quoted(name)} not found (looked in {', '.join(folders)})"


def _texture_candidates(written: str) -> list[str]:
    """Where a texture may be: as written (relative to the MTL file), then by its bare file
    name next to the MTL file (absolute paths from another machine are common). A
    backslash before a space escapes the space (``map_Kd my\\ wood.png``) and is tried
    first; other backslashes are Windows folder separators."""
    spellings = [written.replace("\\ ", " "), written] if "\\ " in written else [written]
    candidates: list[str] = []
    for spelling in spellings:
        relative = spelling.replace("\\", "/")  # Windows exporters; a folder separator everywhere
        on_another_drive = re.match(r"^[A-Za-z]:/", relative) is not None
        for candidate in ([] if on_another_drive else [relative]) + [Path(relative).name]:
            if candidate and candidate not in candidates:
                candidates.append(candidate)
    return candidates or [written.replace("\\", "/")]


def _case_insensitive_match(lookups: list[Lookup], assets: AssetPolicy) -> Lookup | None:
    """The first candidate that exists when letter case is ignored (models made on
    Windows or macOS often spell names differently from the files). Only folders inside
    the allowed roots are listed."""
    for lookup in lookups:
        if lookup.problem != "missing":
            continue
        folder = lookup.path.parent
        try:
            entries = os.listdir(folder)
        except OSError:
            continue
        wanted = lookup.path.name.lower()
        for entry in entries:
            if entry.lower() == wanted:
                match = assets.lookup(entry, folder)
                if match.found:
                    return match
    return None
