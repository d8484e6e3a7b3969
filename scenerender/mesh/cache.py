"""Parsed OBJ meshes cached on disk, keyed by the file's content.

Parsing a 1M-triangle OBJ takes seconds; reading the finished arrays back takes a small
fraction of that. An entry is one ``.npz`` (plain NumPy arrays, no pickled objects) named
by a SHA-256 over the OBJ's bytes, ``LOADER_VERSION``, scenerender's version and the load
options that change the result (normals mode, normalize), so an edited file, another
release or other options simply miss.

What an entry cannot hold is re-done on every load, so a cached load behaves like a
fresh one:
- the MTL libraries the OBJ names are looked up through the scene's AssetPolicy again
  (confinement applies, the files enter ``files_read``) and re-parsed; when the materials
  come out different from those of the first parse (an edited MTL, a texture that
  appeared), the entry is not used;
- the warnings the first parse gave (skipped degenerate faces...) are stored and given
  again, through ``--strict`` too.

Nothing read from an entry is trusted: a file that is not a complete entry of this
format and key, or whose arrays have the wrong shapes, dtypes or indices, is ignored and
written again. Entries are written atomically (temporary file + rename); the folder is
kept under ``LIMIT_BYTES`` by removing the least recently used entries. The cache is
best effort: a folder that cannot be written only makes loads uncached.

Where: ``$SCENERENDER_CACHE_DIR/meshes`` when set, else
``${XDG_CACHE_HOME:-~/.cache}/scenerender/meshes``; ``SCENERENDER_CACHE=0`` turns it off.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import secrets
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from scenerender.errors import SourceLocation, UserError, Warnings, display_path
from scenerender.json_input import parse_json
from scenerender.mesh.data import MeshData, MeshGroup
from scenerender.scene.files import read_regular_file
from scenerender.version import __version__

# Bump whenever the OBJ reader or the normals code would give other arrays for the same
# file, or refuses a file it used to read: old entries then stop matching. 3: numbers
# beyond 32-bit floats are refused (an entry of version 2 may hold such a file's mesh).
LOADER_VERSION = 3
ENTRY_FORMAT = 1
# Smaller files parse faster than the hash and the entry read cost; not caching them also
# keeps the folder free of every small model a user ever opened.
MIN_CACHED_BYTES = 512 * 1024
LIMIT_BYTES = 2 * 1024**3
# A temporary file this old belongs to a run that was killed while writing it.
STALE_PARTIAL_SECONDS = 3600

_MTLLIB = re.compile(rb"^[ \t]*mtllib[ \t]+([^\r\n]*)", re.MULTILINE)
_PARTIAL = ".partial"

Parse = Callable[[Warnings], MeshData]


def cache_folder(environ=None) -> Path | None:
    """The folder mesh entries live in, or None when caching is turned off."""
    environ = os.environ if environ is None else environ
    if environ.get("SCENERENDER_CACHE", "1").strip() == "0":
        return None
    base = environ.get("SCENERENDER_CACHE_DIR")
    if not base:
        xdg = environ.get("XDG_CACHE_HOME")
        base = os.path.join(xdg if xdg else os.path.join(os.path.expanduser("~"), ".cache"), "scenerender")
    return Path(base) / "meshes"


def entry_key(data: bytes, *, normals: str, normalize: bool) -> str:
    """The hex SHA-256 naming the entry of an OBJ with bytes ``data`` loaded with these options."""
    digest = hashlib.sha256(data).hexdigest()
    options = f"format={ENTRY_FORMAT};loader={LOADER_VERSION};scenerender={__version__};" \
              f"normals={normals};normalize={bool(normalize)};file={digest}"
    return hashlib.sha256(options.encode("utf-8")).hexdigest()


def load_obj_cached(path: Path, parse: Parse, *, normals: str, normalize: bool, warnings: Warnings,
                    assets, budget) -> MeshData:
    """The mesh ``parse(warnings)`` would return for the OBJ at ``path``, from the cache when
    an entry for this content and these options is there; else parse and store it.

    ``assets`` (AssetPolicy) and ``budget`` (TriangleBudget) are the ones ``parse`` uses:
    a cached load looks the MTL libraries up through ``assets`` and charges ``budget``.
    """
    folder = cache_folder()
    if folder is None or _file_size(path) < MIN_CACHED_BYTES:
        return parse(warnings)
    data = read_regular_file(path, "OBJ file")
    key = entry_key(data, normals=normals, normalize=normalize)
    entry = folder / f"{key}.npz"
    stored = read_entry(entry, key)
    if stored is not None:
        mesh = _revive(stored, Path(path), warnings, assets, budget)
        if mesh is not None:
            with contextlib.suppress(OSError):  # marks it recently used, for eviction
                os.utime(entry)
            return mesh
    recorder = _RecordingWarnings(warnings)
    mesh = parse(recorder)
    libraries = _library_names(data)
    with contextlib.suppress(OSError):  # a read-only or full cache folder: stay uncached
        write_entry(entry, key, mesh, recorder.given, libraries)
        evict(folder)
    return mesh


def _file_size(path: Path) -> int:
    """The size of ``path``, or 0 when it cannot be read (the parse then says why)."""
    try:
        return os.stat(path).st_size
    except OSError:
        return 0


def _library_names(data: bytes) -> list[str]:
    """What follows each ``mtllib`` of the OBJ, in order. Should this differ from what the
    OBJ reader saw (an exotic file), the materials digest of the entry will not match and
    the entry is never used; correctness does not depend on it."""
    if b"mtllib" not in data:  # the regex scans every line; most big files have no library
        return []
    return [m.group(1).decode("utf-8", "surrogateescape").strip() for m in _MTLLIB.finditer(data)]


# ---------------------------------------------------------------------------------------
# warnings given again


class _RecordingWarnings:
    """Passes warnings on to ``warnings`` and keeps them, with absolute file names, in
    ``given``: (message, file or None, line or None, column or None)."""

    def __init__(self, warnings: Warnings):
        self.warnings = warnings
        self.given: list[list] = []

    @property
    def strict(self) -> bool:
        return self.warnings.strict

    def warn(self, message: str, location: SourceLocation | None = None) -> None:
        if location is None:
            self.given.append([message, None, None, None])
        else:
            self.given.append([message, os.path.abspath(location.file), location.line, location.column])
        self.warnings.warn(message, location)


def _replay(given: list[list], warnings: Warnings) -> None:
    for message, file, line, column in given:
        location = None if file is None else SourceLocation(display_path(file), line, column)
        warnings.warn(message, location)


# ---------------------------------------------------------------------------------------
# from an entry back to a mesh


@dataclass
class StoredMesh:
    """An entry's contents, checked: arrays as MeshData wants them, plus what the first
    parse said (``warnings``), the ``mtllib`` names and a digest of the materials."""

    positions: np.ndarray
    normals: np.ndarray
    uvs: np.ndarray | None
    indices: np.ndarray
    groups: list[MeshGroup]
    warnings: list[list]
    libraries: list[str]
    materials_digest: str
    winding: int | None = None  # MeshData.closed_winding(), when the entry records it


def _revive(stored: StoredMesh, path: Path, warnings: Warnings, assets, budget) -> MeshData | None:
    """The mesh of a checked entry, or None when it cannot stand for a fresh parse here
    (the materials changed, a library is refused, or the budget is short: the fresh parse
    then reports it exactly, with its line)."""
    from scenerender.mesh.obj import materials_of_libraries  # as in loader.load_mesh

    if len(stored.indices) > budget.remaining:
        return None
    try:
        materials = materials_of_libraries(path, stored.libraries, assets)
    except UserError:
        return None
    if materials_digest(materials) != stored.materials_digest:
        return None
    _replay(stored.warnings, warnings)
    budget.charge(len(stored.indices), SourceLocation(display_path(path)))
    mesh = MeshData(positions=stored.positions, normals=stored.normals, uvs=stored.uvs,
                    indices=stored.indices, groups=stored.groups, materials=materials,
                    source=display_path(path))
    if stored.winding is not None:
        mesh.record_winding(stored.winding)  # a whole-mesh analysis, ~0.6 s per 1M triangles
    return mesh


def materials_digest(materials: dict) -> str:
    """A digest of parsed MTL materials (frozen dataclasses: their repr is their value)."""
    text = repr(sorted(materials.items(), key=lambda item: item[0]))
    return hashlib.sha256(text.encode("utf-8", "surrogateescape")).hexdigest()


# ---------------------------------------------------------------------------------------
# the entry file


def write_entry(entry: Path, key: str, mesh: MeshData, given: list[list], libraries: list[str]) -> None:
    """Store ``mesh`` (and what its parse said) as ``entry``, whole or not at all."""
    meta = {
        "format": ENTRY_FORMAT, "key": key, "warnings": given, "libraries": libraries,
        "materials": materials_digest(mesh.materials),
        "group_materials": [group.material for group in mesh.groups],
        "winding": mesh.closed_winding(),
    }
    arrays = {
        "positions": mesh.positions, "normals": mesh.normals, "indices": mesh.indices,
        "group_first": np.array([g.first for g in mesh.groups], np.int64),
        "group_count": np.array([g.count for g in mesh.groups], np.int64),
        "meta": np.frombuffer(json.dumps(meta).encode("utf-8", "surrogateescape"), np.uint8),
    }
    if mesh.uvs is not None:
        arrays["uvs"] = mesh.uvs
    entry.parent.mkdir(parents=True, exist_ok=True)
    temp = entry.with_name(f".{entry.name}.{os.getpid()}-{secrets.token_hex(4)}{_PARTIAL}")
    try:
        with open(temp, "wb") as handle:
            np.savez(handle, **arrays)
        os.replace(temp, entry)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(temp)


def read_entry(entry: Path, key: str) -> StoredMesh | None:
    """The checked contents of ``entry``, or None when it is missing, damaged, of another
    format or key, or holds arrays a mesh cannot have."""
    try:
        with np.load(entry, allow_pickle=False) as npz:
            arrays = {name: npz[name] for name in npz.files}
        meta = parse_json(bytes(arrays.pop("meta")))
        return _checked(arrays, meta, key)
    except Exception:  # any way of being unreadable (zip, npy header, JSON...) means "no entry"
        return None


def _checked(arrays: dict, meta: dict, key: str) -> StoredMesh | None:
    if not isinstance(meta, dict) or meta.get("format") != ENTRY_FORMAT or meta.get("key") != key:
        return None
    positions, normals, indices = arrays.get("positions"), arrays.get("normals"), arrays.get("indices")
    uvs = arrays.get("uvs")
    if not (_is(positions, np.float32, 3) and _is(normals, np.float32, 3) and _is(indices, np.uint32, 3)):
        return None
    count = len(positions)
    if len(normals) != count or (uvs is not None and (not _is(uvs, np.float32, 2) or len(uvs) != count)):
        return None
    if len(indices) == 0 or int(indices.max()) >= count:
        return None
    if not (np.isfinite(positions).all() and np.isfinite(normals).all()):
        return None
    if uvs is not None and not np.isfinite(uvs).all():
        return None
    groups = _groups(arrays.get("group_first"), arrays.get("group_count"), meta.get("group_materials"), len(indices))
    given, libraries, digest = meta.get("warnings"), meta.get("libraries"), meta.get("materials")
    if groups is None or not _warning_rows(given) or not _strings(libraries) or not isinstance(digest, str):
        return None
    winding = meta.get("winding")
    return StoredMesh(positions, normals, uvs, indices, groups, given, libraries, digest,
                      winding if winding in (-1, 0, 1) and not isinstance(winding, bool) else None)


def _is(array, dtype, columns: int) -> bool:
    return isinstance(array, np.ndarray) and array.dtype == dtype and array.ndim == 2 and array.shape[1] == columns


def _groups(first, count, names, triangles: int) -> list[MeshGroup] | None:
    """The groups, when they cover 0..triangles in order without gaps; else None."""
    if not (isinstance(first, np.ndarray) and isinstance(count, np.ndarray) and isinstance(names, list)):
        return None
    if first.dtype != np.int64 or count.dtype != np.int64 or first.ndim != 1 or first.shape != count.shape \
            or len(names) != len(first) or not all(n is None or isinstance(n, str) for n in names):
        return None
    ends = np.cumsum(count)
    if len(first) == 0 or first[0] != 0 or (count < 0).any() or ends[-1] != triangles \
            or not np.array_equal(first[1:], ends[:-1]):
        return None
    return [MeshGroup(name, int(f), int(c)) for name, f, c in zip(names, first, count)]


def _strings(values) -> bool:
    return isinstance(values, list) and all(isinstance(v, str) for v in values)


def _warning_rows(rows) -> bool:
    return isinstance(rows, list) and all(
        isinstance(row, list) and len(row) == 4 and isinstance(row[0], str)
        and (row[1] is None or isinstance(row[1], str))
        and all(v is None or (isinstance(v, int) and not isinstance(v, bool)) for v in row[2:])
        for row in rows)


# ---------------------------------------------------------------------------------------
# size bound


def evict(folder: Path, limit: int | None = None) -> list[Path]:
    """Remove the least recently used entries until the folder holds at most ``limit``
    bytes (default LIMIT_BYTES), and temporary files killed runs left -> removed paths."""
    limit = LIMIT_BYTES if limit is None else limit
    now = time.time()
    entries, removed = [], []
    for item in os.scandir(folder):
        with contextlib.suppress(OSError):  # another process may remove it meanwhile
            info = item.stat(follow_symlinks=False)
            if item.name.endswith(_PARTIAL) and now - info.st_mtime > STALE_PARTIAL_SECONDS:
                os.unlink(item.path)
                removed.append(Path(item.path))
            elif item.name.endswith(".npz") and item.is_file(follow_symlinks=False):
                entries.append((info.st_mtime, info.st_size, item.path))
    total = sum(size for _, size, _ in entries)
    for _, size, name in sorted(entries):
        if total <= limit:
            break
        with contextlib.suppress(FileNotFoundError):
            os.unlink(name)
        removed.append(Path(name))
        total -= size
    return removed
