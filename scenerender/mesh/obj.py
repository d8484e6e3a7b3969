"""Wavefront OBJ reader.

The reader makes one pass over the lines to sort the statements it needs into lists of
string tokens, then converts each list to numbers in one NumPy call. Only the per-line
dispatch runs in Python; parsing face corners, resolving relative indices, de-duplicating
vertices and triangulating polygons are whole-array operations. That keeps a 200k-triangle
model within the renderer's start-up budget.

When the fast path meets something unusual (a malformed token, an empty ``1/2/`` field,
an index too large for 64 bits), the face corners are re-read one by one so the error can
name the exact line.

Real-world files hold things a triangle mesh cannot use: faces with fewer than three
corners, zero-area triangles, ``l`` (line) and ``p`` (point) elements. They are skipped,
and one warning per file counts them (``--strict`` makes that an error).
"""
from __future__ import annotations

import re
import warnings as _pywarnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, Warnings, display_path
from scenerender.mesh.budget import TriangleBudget
from scenerender.mesh.capped import CappedWarnings
from scenerender.mesh.data import MeshData, MeshGroup
from scenerender.mesh.mtl import parse_mtl
from scenerender.mesh.numbers import beyond_float32, fits_float32
from scenerender.scene.assets import AssetPolicy, policy_for
from scenerender.scene.files import read_regular_file

# Indices at or beyond this size cannot name an element of any file that fits in memory,
# and stay far enough from the int64 limits that index arithmetic cannot wrap.
_INDEX_LIMIT = 2**62

# What each kind of index refers to, for error messages: (singular, plural).
_ELEMENT_NAMES = {
    "v": ("vertex", "vertices"),
    "vt": ("texture coordinate", "texture coordinates"),
    "vn": ("normal", "normals"),
}


@dataclass
class _Statements:
    """The statements of one OBJ file that matter, still as text tokens.

    Line numbers are kept per record so that every later check can name its line.
    """

    v_tokens: list[str] = field(default_factory=list)
    v_lines: list[int] = field(default_factory=list)
    vt_tokens: list[str] = field(default_factory=list)
    vt_lines: list[int] = field(default_factory=list)
    vn_tokens: list[str] = field(default_factory=list)
    vn_lines: list[int] = field(default_factory=list)
    # Every face corner ("3/1/2"), faces one after another, with corners and line per face.
    corner_tokens: list[str] = field(default_factory=list)
    face_sizes: list[int] = field(default_factory=list)
    face_lines: list[int] = field(default_factory=list)
    # (index of the first face it applies to, material name, line)
    material_switches: list[tuple[int, str | None, int]] = field(default_factory=list)
    # (rest of the line, line)
    mtllib_statements: list[tuple[str, int]] = field(default_factory=list)
    # Elements skipped because a triangle mesh cannot draw them, and the first such line.
    short_faces: int = 0
    line_elements: int = 0
    point_elements: int = 0
    freeform_statements: int = 0
    first_skipped_line: int | None = None

    def skip(self, kind: str, line: int) -> None:
        setattr(self, kind, getattr(self, kind) + 1)
        if self.first_skipped_line is None:
            self.first_skipped_line = line


@dataclass
class _Corners:
    """Face corners as raw OBJ indices (1-based or negative).

    Each array is (C,) int64; ``has_vt``/``has_vn`` are (C,) bool and say whether the
    corner names that element at all (the index arrays hold 0 where it does not).
    """

    v: np.ndarray
    vt: np.ndarray
    vn: np.ndarray
    has_vt: np.ndarray
    has_vn: np.ndarray


def parse_obj(path: Path, warnings: Warnings, assets: AssetPolicy | None = None,
              budget: TriangleBudget | None = None) -> MeshData:
    """Read an OBJ file (and the MTL files it names) into an indexed triangle mesh.

    Returns a MeshData whose ``normals`` is the file's normals, (N, 3) float32 and not yet
    normalised, when every face corner names one, and ``None`` otherwise (the loader then
    computes them; see ``scenerender.mesh.loader.load_mesh``). ``uvs`` is (N, 2) float32, or
    None when no face corner names a texture coordinate. Vertices are shared between faces
    wherever the (v, vt, vn) triple is the same.

    ``assets`` confines and records the MTL libraries and textures the file names (default:
    the OBJ's own folder). ``budget`` is charged with the triangles, checked while the
    faces are read.

    Raises UserError with the file and line for malformed statements, for a library outside
    the allowed folders, and when the budget runs out; a missing MTL file and skipped
    degenerate elements are warnings.
    """
    path = Path(path)
    shown = display_path(path)
    assets = assets if assets is not None else policy_for(path)
    budget = budget if budget is not None else TriangleBudget.unlimited()
    text = read_regular_file(path, "OBJ file").decode("utf-8", errors="surrogateescape")
    capped = CappedWarnings(warnings, shown)  # each MTL file caps its own warnings
    mesh = _parse_text(text, path, shown, _Warners(capped, warnings), assets, budget)
    capped.finish()
    return mesh


@dataclass
class _Warners:
    """Where warnings go: ``obj`` (capped per OBJ file) for the OBJ's own, ``libraries``
    for the MTL reader, which caps per MTL file."""

    obj: CappedWarnings
    libraries: Warnings


# Texture coordinates are stored and interpolated in float32: near 1e4 a step is about
# 1e-3, a sixteenth of a texel of a 64-pixel texture. Beyond this magnitude a mesh's
# coordinates are moved towards 0 before rounding to float32.
FAR_TEXCOORD = 256.0


def recentred_texcoords(texcoords: np.ndarray) -> np.ndarray:
    """(N, 2) float64 texture coordinates, shifted per axis by a whole even number when they
    lie far from 0 (see FAR_TEXCOORD). Repeat and mirrored repeat (period 2) sample exactly
    the same texels after the shift, with any whole-number texture scale; the shift is what
    keeps them sharp after the float32 upload."""
    if len(texcoords) == 0 or np.abs(texcoords).max() <= FAR_TEXCOORD:
        return texcoords
    centre = (texcoords.min(axis=0) + texcoords.max(axis=0)) / 2.0
    shift = 2.0 * np.round(centre / 2.0)
    shift[np.abs(centre) <= FAR_TEXCOORD] = 0.0
    return texcoords - shift


def _parse_text(text: str, path: Path, shown: str, warners: _Warners, assets: AssetPolicy,
                budget: TriangleBudget) -> MeshData:
    warnings = warners.obj
    statements = _collect_statements(text, shown, budget)
    positions = _vectors(statements.v_tokens, statements.v_lines, 3, shown)
    texcoords = _vectors(statements.vt_tokens, statements.vt_lines, 2, shown)
    file_normals = _vectors(statements.vn_tokens, statements.vn_lines, 3, shown)

    corners = _parse_corners(statements, shown)
    v_index, vt_index, vn_index = _resolve_indices(corners, statements, shown, warnings)
    vertex_of_corner, unique_v, unique_vt, unique_vn = _weld_corners(
        v_index, vt_index, vn_index, len(positions), len(texcoords), len(file_normals)
    )

    sizes = np.asarray(statements.face_sizes, dtype=np.int64)
    indices = triangulate(vertex_of_corner, sizes, positions[v_index])
    groups = _material_groups(statements.material_switches, sizes)
    indices, groups, zero_area = _drop_zero_area(indices, groups, positions[unique_v])
    _warn_skipped(statements, zero_area, shown, warnings)
    budget.charge(len(indices), SourceLocation(shown))

    uvs = None
    if (vt_index >= 0).any():
        uvs = np.zeros((len(unique_vt), 2), dtype=np.float32)
        named = unique_vt >= 0
        uvs[named] = recentred_texcoords(texcoords[unique_vt[named]])
    normals = None
    if len(vn_index) and (vn_index >= 0).all():
        normals = file_normals[unique_vn].astype(np.float32)

    materials, all_libraries_found = _load_material_libraries(path, statements, warners, assets)
    if all_libraries_found and statements.mtllib_statements:
        _warn_undefined_materials(statements, materials, shown, warnings)

    return MeshData(
        positions=positions[unique_v].astype(np.float32),
        normals=normals,
        uvs=uvs,
        indices=indices,
        groups=groups,
        materials=materials,
        source=shown,
    )


# ---------------------------------------------------------------------------------------
# Pass 1: sort the lines into token lists.


def _numbered_lines(text: str):
    """(line number, line) pairs, joining lines continued with a trailing backslash.

    A joined line reports the number of its first physical line. Without continuations
    (nearly always) this is a plain enumerate, which keeps the hot loop free of
    generator overhead.
    """
    lines = text.splitlines()
    if "\\\n" not in text and "\\\r" not in text:
        return enumerate(lines, 1)
    joined: list[tuple[int, str]] = []
    pending: list[str] = []
    start = 0
    for number, line in enumerate(lines, 1):
        if not pending:
            start = number
        if line.endswith("\\"):
            pending.append(line[:-1])
            continue
        pending.append(line)
        joined.append((start, " ".join(pending)))
        pending = []
    if pending:
        joined.append((start, " ".join(pending)))
    return joined


# Free-form geometry (curves and surfaces): not drawn, and counted in one warning.
FREEFORM_KEYS = frozenset({"vp", "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole",
                           "scrv", "sp", "end", "con"})


def _collect_statements(text: str, shown: str, budget: TriangleBudget | None = None) -> _Statements:
    st = _Statements()
    budget = budget if budget is not None else TriangleBudget.unlimited()
    # Local aliases: this loop runs once per line of the file.
    v_tokens, add_v_line = st.v_tokens, st.v_lines.append
    corner_tokens = st.corner_tokens
    add_face_size, add_face_line = st.face_sizes.append, st.face_lines.append
    # A face of n corners makes n - 2 triangles, so there are fewer triangles than corners:
    # the exact count is needed only once the corners alone exceed the budget.
    corners_unchecked = budget.remaining
    for number, line in _numbered_lines(text):
        tokens = line.split()
        if not tokens:
            continue
        key = tokens[0]
        if key == "f":
            del tokens[0]
            if len(tokens) < 3:
                st.skip("short_faces", number)
                continue
            corner_tokens += tokens
            add_face_size(len(tokens))
            add_face_line(number)
            if len(corner_tokens) > corners_unchecked:
                budget.check(len(corner_tokens) - 2 * len(st.face_sizes), SourceLocation(shown, number))
        elif key == "v":
            if len(tokens) < 4:
                raise UserError(
                    f"'v' needs 3 numbers (x y z), got {len(tokens) - 1}",
                    SourceLocation(shown, number),
                )
            v_tokens += tokens[1:4]  # w and per-vertex colours are ignored
            add_v_line(number)
        elif key == "vt":
            if len(tokens) < 2:
                raise UserError(
                    "'vt' needs at least 1 number (u [v])", SourceLocation(shown, number)
                )
            # "vt u" alone means v = 0; a third (w) value is ignored.
            st.vt_tokens += tokens[1:3] if len(tokens) > 2 else (tokens[1], "0")
            st.vt_lines.append(number)
        elif key == "vn":
            if len(tokens) < 4:
                raise UserError(
                    f"'vn' needs 3 numbers (x y z), got {len(tokens) - 1}",
                    SourceLocation(shown, number),
                )
            st.vn_tokens += tokens[1:4]
            st.vn_lines.append(number)
        elif key == "usemtl":
            name = line.split(None, 1)[1].strip() if len(tokens) > 1 else None
            st.material_switches.append((len(st.face_sizes), name, number))
        elif key == "mtllib":
            if len(tokens) > 1:
                st.mtllib_statements.append((line.split(None, 1)[1].strip(), number))
        elif key == "l":
            st.skip("line_elements", number)
        elif key == "p":
            st.skip("point_elements", number)
        elif key in FREEFORM_KEYS:
            st.skip("freeform_statements", number)
        # Everything else (o, g, s, comments, unknown statements) does not affect a
        # triangle mesh and is skipped silently.
    return st


# ---------------------------------------------------------------------------------------
# Pass 2: numbers.


def _vectors(tokens: list[str], lines: list[int], width: int, shown: str) -> np.ndarray:
    """(len(lines), width) float64: the numbers of one kind of statement (v, vt or vn),
    each finite and within the range of a 32-bit float, which they are stored in."""
    if not tokens:
        return np.zeros((0, width), dtype=np.float64)
    try:
        values = np.array(tokens, dtype=np.float64)
    except ValueError:
        values = None
    if values is None or not fits_float32(values).all():
        _raise_for_bad_number(tokens, lines, width, shown)
    return values.reshape(-1, width)


def _raise_for_bad_number(tokens: list[str], lines: list[int], width: int, shown: str) -> None:
    """Find the first token the bulk conversion rejected and raise for its line."""
    for i, token in enumerate(tokens):
        location = SourceLocation(shown, lines[i // width])
        try:
            value = np.array([token], dtype=np.float64)[0]  # the same rules as the bulk call
        except ValueError:
            raise UserError(f"expected a number, got {token!r}", location) from None
        if not np.isfinite(value):
            raise UserError(f"expected a finite number, got {token!r}", location)
        if not fits_float32(value):
            raise UserError(beyond_float32(value), location)
    raise UserError("could not read the numbers in this file", SourceLocation(shown))


def _ints(text: str, expected: int) -> np.ndarray | None:
    """(expected,) int64: the whitespace-separated integers in ``text``, or None if any
    token is not an integer or the count differs."""
    try:
        # np.fromstring is the fastest integer reader NumPy has. On bad input it warns and
        # returns what it read so far ("3abc" gives 3), so its warnings must be errors.
        with _pywarnings.catch_warnings():
            _pywarnings.simplefilter("error")
            values = np.fromstring(text, dtype=np.int64, sep=" ")
    except (ValueError, Warning):
        try:  # strict, and still vectorised, should fromstring change or go away
            values = np.array(text.split(), dtype=np.int64)
        except (ValueError, OverflowError):
            return None
    if len(values) != expected:
        return None
    # fromstring saturates out-of-range numbers to the int64 limits without a warning;
    # the careful path reports them with their line.
    if len(values) and ((values >= _INDEX_LIMIT) | (values <= -_INDEX_LIMIT)).any():
        return None
    return values


def _parse_corners(st: _Statements, shown: str) -> _Corners:
    corners = _parse_corners_fast(st.corner_tokens)
    if corners is None:
        corners = _parse_corners_slowly(st, shown)
    return corners


def _parse_corners_fast(tokens: list[str]) -> _Corners | None:
    """Parse every corner at once; None when something needs the careful per-corner path.

    The shape of each corner (``v``, ``v/vt``, ``v//vn`` or ``v/vt/vn``) is read from the
    number of slashes and double slashes inside it, counted with NumPy over the bytes of
    all corners joined by single spaces.
    """
    count = len(tokens)
    if count == 0:
        empty = np.zeros(0, dtype=np.int64)
        return _Corners(empty, empty, empty, empty.astype(bool), empty.astype(bool))
    joined = " ".join(tokens)
    if "/" not in joined:
        v = _ints(joined, count)
        if v is None:
            return None
        zeros = np.zeros(count, dtype=np.int64)
        no = np.zeros(count, dtype=bool)
        return _Corners(v, zeros, zeros.copy(), no, no.copy())

    try:
        raw = np.frombuffer(joined.encode("ascii"), dtype=np.uint8)
    except UnicodeEncodeError:
        return None
    lengths = np.fromiter(map(len, tokens), dtype=np.int64, count=count)
    if lengths.max() > 255:
        return None  # the uint8 counts below could wrap; no real corner is this long
    starts = np.cumsum(lengths + 1) - (lengths + 1)
    ends = starts + lengths  # one past each corner's last character
    slash = (raw == ord("/")).astype(np.uint8)
    pair = np.zeros_like(slash)  # 1 where "//" starts
    np.bitwise_and(slash[:-1], slash[1:], out=pair[:-1])
    # Each reduceat segment runs from one corner's start to the next one's, which adds only
    # the separating space (never a slash). Summing in uint8 avoids an 8-byte-per-character
    # copy; the length check above keeps the sums from wrapping.
    slashes = np.add.reduceat(slash, starts).astype(np.int64)
    doubles = np.add.reduceat(pair, starts).astype(np.int64)

    well_formed = (
        (slashes <= 2)
        & ((doubles == 0) | ((doubles == 1) & (slashes == 2)))
        & (slash[starts] == 0)
        & (slash[ends - 1] == 0)
    )
    if not well_formed.all():
        return None
    fields = slashes + 1 - doubles
    numbers = _ints(joined.replace("//", " ").replace("/", " "), int(fields.sum()))
    if numbers is None:
        return None

    first = np.cumsum(fields) - fields
    last = len(numbers) - 1
    has_vt = (slashes >= 1) & (doubles == 0)
    has_vn = slashes == 2
    vt = np.where(has_vt, numbers[np.minimum(first + 1, last)], 0)
    vn = np.where(has_vn, numbers[np.minimum(first + 2 - doubles, last)], 0)
    return _Corners(numbers[first], vt, vn, has_vt, has_vn)


def _parse_corners_slowly(st: _Statements, shown: str) -> _Corners:
    """Parse corner by corner, raising UserError at the first malformed one."""
    count = len(st.corner_tokens)
    v = np.zeros(count, dtype=np.int64)
    vt = np.zeros(count, dtype=np.int64)
    vn = np.zeros(count, dtype=np.int64)
    has_vt = np.zeros(count, dtype=bool)
    has_vn = np.zeros(count, dtype=bool)
    corner = 0
    for size, line in zip(st.face_sizes, st.face_lines):
        for token in st.corner_tokens[corner : corner + size]:
            parts = token.split("/")
            if len(parts) > 3 or not parts[0]:
                raise UserError(
                    f"face corner {token!r} is not v, v/vt, v//vn or v/vt/vn",
                    SourceLocation(shown, line),
                )
            numbers = [_corner_int(part, token, shown, line) for part in parts]
            v[corner] = numbers[0]
            if len(numbers) > 1 and numbers[1] is not None:
                vt[corner], has_vt[corner] = numbers[1], True
            if len(numbers) > 2 and numbers[2] is not None:
                vn[corner], has_vn[corner] = numbers[2], True
            corner += 1
    return _Corners(v, vt, vn, has_vt, has_vn)


def _corner_int(part: str, token: str, shown: str, line: int) -> int | None:
    if part == "":
        return None  # an empty field, as in "3//1" or "3/1/", means "not given"
    try:
        value = int(part)
    except ValueError:
        raise UserError(
            f"expected a whole number in face corner {token!r}, got {part!r}",
            SourceLocation(shown, line),
        ) from None
    if not -_INDEX_LIMIT < value < _INDEX_LIMIT:
        shown_part = part if len(part) <= 30 else part[:12] + "..." + part[-6:]
        raise UserError(f"face index {shown_part} is out of range", SourceLocation(shown, line))
    return value


def _resolve_indices(corners: _Corners, st: _Statements, shown: str, warnings: Warnings):
    """Turn raw OBJ indices into 0-based ones; -1 where a corner names no vt / vn.

    A negative index counts back from the last element defined *before the face*, so each
    face needs the number of v/vt/vn statements above it. A position index no ``v`` defines
    is an error; a texture coordinate or normal index no ``vt``/``vn`` defines is dropped
    with one counted warning, as mainstream readers do (the corner then has none, and
    normals are computed), and is an error under --strict.
    """
    sizes = np.asarray(st.face_sizes, dtype=np.int64)
    face_lines = np.asarray(st.face_lines, dtype=np.int64)
    face_of_corner = np.repeat(np.arange(len(sizes)), sizes)
    resolved, dropped = [], []
    for key, raw, present in (
        ("v", corners.v, np.ones(len(corners.v), dtype=bool)),
        ("vt", corners.vt, corners.has_vt),
        ("vn", corners.vn, corners.has_vn),
    ):
        element_lines = np.asarray(getattr(st, f"{key}_lines"), dtype=np.int64)
        defined = np.searchsorted(element_lines, face_lines)[face_of_corner]
        absolute = np.where(raw < 0, defined + raw + 1, raw)
        bad = present & ((raw == 0) | (absolute < 1) | (absolute > defined))
        if bad.any():
            corner = int(np.argmax(bad))
            line = int(face_lines[face_of_corner[corner]])
            message = _index_message(_ELEMENT_NAMES[key], int(raw[corner]), int(defined[corner]))
            if key == "v":
                raise UserError(message, SourceLocation(shown, line))
            dropped.append((int(bad.sum()), key, line, message))
            present = present & ~bad
        resolved.append(np.where(present, absolute - 1, -1))
    if dropped:
        _warn_dropped_references(dropped, shown, warnings)
    return resolved


def _warn_dropped_references(dropped: list, shown: str, warnings: Warnings) -> None:
    counts = " and ".join(f"{count} {'texture coordinate' if key == 'vt' else 'normal'} reference"
                          f"{'s' if count != 1 else ''}" for count, key, _, _ in dropped)
    first_line, first_message = min((line, message) for _, _, line, message in dropped)
    warnings.warn(f"dropped {counts} that nothing defines (the first: {first_message}); those corners "
                  "get computed normals or no texture coordinate", SourceLocation(shown, first_line))


def _index_message(names: tuple[str, str], index: int, defined: int) -> str:
    singular, plural = names
    if defined == 0:
        defined_text = f"no {plural} are defined so far"
    elif defined == 1:
        defined_text = f"only 1 {singular} is defined so far"
    else:
        defined_text = f"only {defined} {plural} are defined so far"
    if index == 0:
        return f"face uses {singular} index 0, but OBJ indices start at 1"
    if index < 0:
        return f"face refers to {singular} {index} (counting back from the last) but {defined_text}"
    return f"face refers to {singular} {index} but {defined_text}"


# ---------------------------------------------------------------------------------------
# Pass 3: vertices and triangles.


def _weld_corners(v, vt, vn, v_count: int, vt_count: int, vn_count: int):
    """Give every distinct (v, vt, vn) triple one vertex.

    Returns (vertex index per corner (C,) int64, and per new vertex its v, vt and vn
    indices, each (N,) int64 with -1 for "none").
    """
    vt_range, vn_range = vt_count + 1, vn_count + 1  # +1 because -1 means "none"
    if v_count * vt_range * vn_range < 2**62:
        key = (v * vt_range + (vt + 1)) * vn_range + (vn + 1)
        unique_keys, vertex_of_corner = np.unique(key, return_inverse=True)
        unique_vn = unique_keys % vn_range - 1
        rest = unique_keys // vn_range
        unique_vt = rest % vt_range - 1
        unique_v = rest // vt_range
    else:  # too many elements to pack the triple into one int64
        triples = np.stack([v, vt, vn], axis=1)
        unique_rows, vertex_of_corner = np.unique(triples, axis=0, return_inverse=True)
        unique_v, unique_vt, unique_vn = unique_rows.T
    return vertex_of_corner.reshape(-1), unique_v, unique_vt, unique_vn


def triangulate(vertex_of_corner: np.ndarray, sizes: np.ndarray, corner_positions: np.ndarray) -> np.ndarray:
    """(M, 3) uint32 triangles, n - 2 for each face of n corners, in face order. Convex
    faces (all triangles and nearly every quad) become fans (c0, ci, ci+1); a concave one
    (an L-shaped face) is cut by ear clipping in its own plane, which a fan would draw
    wrong. ``corner_positions`` is (C, 3), the position of every corner."""
    indices = _fan_triangulate(vertex_of_corner, sizes)
    concave = np.flatnonzero(_concave_faces(sizes, corner_positions))
    if len(concave):
        face_start = np.cumsum(sizes) - sizes
        first_triangle = np.cumsum(sizes - 2) - (sizes - 2)
        for face in concave:
            start, count = int(face_start[face]), int(sizes[face])
            local = _ear_clip(corner_positions[start:start + count])
            if local is not None:  # else a self-crossing or degenerate face: it keeps its fan
                indices[first_triangle[face]:first_triangle[face] + count - 2] = vertex_of_corner[start + local]
    return indices


def _concave_faces(sizes: np.ndarray, corner_positions: np.ndarray) -> np.ndarray:
    """(F,) bool: faces of more than three corners that turn both ways around their
    Newell normal (a fan of such a face would cover what it does not)."""
    concave = np.zeros(len(sizes), dtype=bool)
    big = sizes > 3
    if not big.any():
        return concave
    starts = np.cumsum(sizes) - sizes
    face = np.repeat(np.arange(len(sizes)), sizes)
    position_in_face = np.arange(len(face)) - starts[face]
    following = starts[face] + (position_in_face + 1) % sizes[face]
    current, nxt = corner_positions, corner_positions[following]
    newell = np.zeros((len(sizes), 3))
    np.add.at(newell, face, np.cross(current, nxt))
    edge = nxt - current
    next_edge = edge[following]
    turn = np.einsum("ij,ij->i", np.cross(edge, next_edge), newell[face])
    scale = np.abs(turn).max() if len(turn) else 0.0
    negative = turn < -1e-12 * max(scale, 1e-300)
    np.logical_or.at(concave, face, negative)
    return concave & big


def _ear_clip(points: np.ndarray) -> np.ndarray | None:
    """(n - 2, 3) int64 corner indices of one polygon's triangles, (n, 3) points in any
    orientation: projected onto the plane of its Newell normal, then ear clipped
    (mapbox-earcut); winding kept as the face's own. None where ear clipping does not give
    n - 2 triangles (a self-crossing or degenerate face)."""
    import mapbox_earcut

    normal = np.cross(points, np.roll(points, -1, axis=0)).sum(axis=0)
    axis = int(np.argmax(np.abs(normal)))
    keep = [i for i in range(3) if i != axis]
    flat = np.ascontiguousarray(points[:, keep], dtype=np.float64)
    if normal[axis] < 0:  # seen from the other side: mirror, so the winding stays the face's
        flat[:, 0] = -flat[:, 0]
    triangles = mapbox_earcut.triangulate_float64(flat, np.array([len(points)], dtype=np.uint32))
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if len(triangles) != len(points) - 2:
        return None
    return _same_winding(triangles, flat)


def _same_winding(triangles: np.ndarray, flat: np.ndarray) -> np.ndarray:
    """Triangles turned to wind counter-clockwise in the projected plane, as the face does."""
    a, b, c = flat[triangles[:, 0]], flat[triangles[:, 1]], flat[triangles[:, 2]]
    signed = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    flipped = signed < 0
    triangles[flipped] = triangles[flipped][:, [0, 2, 1]]
    return triangles


def _fan_triangulate(vertex_of_corner: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """(M, 3) uint32 triangles: a polygon (c0, c1, ..., cn) becomes (c0, ci, ci+1)."""
    if len(sizes) == 0:
        return np.zeros((0, 3), dtype=np.uint32)
    if (sizes == 3).all():
        return vertex_of_corner.reshape(-1, 3).astype(np.uint32)
    triangles_per_face = sizes - 2
    face_start = np.cumsum(sizes) - sizes
    first_triangle = np.cumsum(triangles_per_face) - triangles_per_face
    face = np.repeat(np.arange(len(sizes)), triangles_per_face)
    step = np.arange(int(triangles_per_face.sum())) - first_triangle[face]
    anchor = face_start[face]
    corners = np.stack([anchor, anchor + step + 1, anchor + step + 2], axis=1)
    return vertex_of_corner[corners].astype(np.uint32)


def _material_groups(switches, sizes: np.ndarray) -> list[MeshGroup]:
    """Triangle ranges per ``usemtl``: empty runs dropped, neighbours with one material merged."""
    triangles_before_face = np.concatenate(([0], np.cumsum(sizes - 2)))
    total = int(triangles_before_face[-1])
    marks: list[tuple[int, str | None]] = [(0, None)]
    for first_face, material, _line in switches:
        marks.append((int(triangles_before_face[first_face]), material))
    groups: list[MeshGroup] = []
    for (first, material), (end, _) in zip(marks, marks[1:] + [(total, None)]):
        if end == first:
            continue
        if groups and groups[-1].material == material:
            previous = groups.pop()
            first = previous.first
        groups.append(MeshGroup(material, first, end - first))
    return groups or [MeshGroup(None, 0, 0)]


def _drop_zero_area(indices: np.ndarray, groups: list[MeshGroup], positions: np.ndarray):
    """Remove triangles whose corners coincide or lie on one line (exactly, in float64):
    they draw nothing and give no normal. Returns (indices (M', 3) uint32, groups, count
    removed); ``positions`` is (N, 3) float64 per vertex."""
    if len(indices) == 0:
        return indices, groups, 0
    corners = positions[indices.astype(np.int64)]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    keep = (cross != 0).any(axis=1)
    removed = int(len(keep) - keep.sum())
    if removed == 0:
        return indices, groups, 0
    kept_before = np.concatenate(([0], np.cumsum(keep)))
    new_groups = []
    for group in groups:
        first, end = int(kept_before[group.first]), int(kept_before[group.first + group.count])
        if end > first:
            new_groups.append(MeshGroup(group.material, first, end - first))
    return indices[keep], new_groups or [MeshGroup(None, 0, 0)], removed


def _warn_skipped(st: _Statements, zero_area: int, shown: str, warnings: Warnings) -> None:
    """One warning for everything a triangle mesh cannot draw, counted by kind."""
    parts = []
    for count, singular, plural in (
        (st.short_faces, "face with fewer than 3 vertices", "faces with fewer than 3 vertices"),
        (zero_area, "zero-area triangle", "zero-area triangles"),
        (st.line_elements, "line element (l)", "line elements (l)"),
        (st.point_elements, "point element (p)", "point elements (p)"),
        (st.freeform_statements, "free-form geometry statement", "free-form geometry statements"),
    ):
        if count:
            parts.append(f"{count} {singular if count == 1 else plural}")
    if not parts:
        return
    listed = parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]
    warnings.warn(f"skipped {listed}", SourceLocation(shown, st.first_skipped_line))


# ---------------------------------------------------------------------------------------
# Materials.


def materials_of_libraries(obj_path: Path, libraries: list[str], assets: AssetPolicy) -> dict:
    """The materials of the ``mtllib`` names of the OBJ at ``obj_path``, read as the OBJ
    reader reads them (through ``assets``), with their warnings dropped: for a reader that
    keeps the warnings of the first read (the mesh cache)."""
    if not libraries:
        return {}
    statements = _Statements(mtllib_statements=[(rest, 0) for rest in libraries])
    silent = Warnings()
    materials, _all_found = _load_material_libraries(obj_path, statements, _Warners(silent, silent), assets)
    return materials


def _load_material_libraries(
    obj_path: Path, st: _Statements, warners: _Warners, assets: AssetPolicy
) -> tuple[dict, bool]:
    """Materials of every ``mtllib`` (later definitions of a name win), and whether every
    library was found. A library outside the allowed folders, or not a regular file, is an
    error at the ``mtllib`` line; a missing one (or a name no file can have) is a warning."""
    shown = display_path(obj_path)
    folder = obj_path.parent
    materials: dict = {}
    all_found = True
    loaded: set[Path] = set()
    for rest, line in st.mtllib_statements:
        location = SourceLocation(shown, line)
        for lookup in _library_lookups(folder, rest, assets):
            if lookup.problem in ("missing", "bad_name"):
                reason = lookup.message if lookup.problem == "bad_name" else \
                    f"material library '{display_path(lookup.path)}' not found"
                warners.obj.warn(f"{reason}; its materials are drawn with the object's material", location)
                all_found = False
                continue
            if not lookup.found:
                raise UserError(f"mtllib: {lookup.message}", location)
            if lookup.path in loaded:
                continue
            loaded.add(lookup.path)
            assets.record(lookup.path)
            materials.update(parse_mtl(lookup.path, warners.libraries, assets=assets))
    return materials, all_found


def _library_lookups(folder: Path, rest: str, assets: AssetPolicy) -> list:
    """Where the files named by one ``mtllib`` statement are (``AssetPolicy.lookup`` results).

    The format separates several names with spaces; a backslash before a space keeps it in
    the name (``mtllib my\\ file.mtl``), and exporters also write one name containing plain
    spaces: the whole rest of the line wins when such a file exists.
    """
    names = unescaped_names(rest)
    if " " in rest and len(names) > 1:
        whole = assets.lookup(rest, folder)
        if whole.found:
            return [whole]
    return [assets.lookup(name, folder) for name in names]


def unescaped_names(rest: str) -> list[str]:
    """Names separated by spaces, a backslash-escaped space kept in its name."""
    return [re.sub(r"\\ ", " ", name) for name in re.split(r"(?<!\\)\s+", rest.strip()) if name]


def _warn_undefined_materials(
    st: _Statements, materials: dict, shown: str, warnings: Warnings
) -> None:
    """Warn once per ``usemtl`` name that no library defines.

    Called only when the file has libraries and all were found: files without any
    ``mtllib`` often carry a meaningless ``usemtl default``, and a missing library has
    already been reported.
    """
    reported: set[str] = set()
    for _face, name, line in st.material_switches:
        if name is None or name in materials or name in reported:
            continue
        reported.add(name)
        warnings.warn(
            f"material '{name}' is not defined in the material libraries; "
            "those faces use the object's material",
            SourceLocation(shown, line),
        )
