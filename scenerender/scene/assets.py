"""Where a scene may read files from: the one place where an asset path becomes a file.

Every file a scene reads besides the scene file itself (meshes, MTL libraries, textures an
MTL or the scene names, skybox faces) goes through ``AssetPolicy.resolve``. A path must
resolve, symlinks followed, inside the scene file's folder or a root the user allowed
explicitly (``--asset-root DIR`` or the ``SCENERENDER_ASSET_ROOTS`` environment variable),
and must be a regular file. The policy also records every file it handed out, so a run can
fingerprint exactly what it read.

Reading goes through ``scene.files.read_regular_file``, which refuses anything but a regular
file at the moment of opening (a FIFO swapped in after validation would otherwise block).
"""
from __future__ import annotations

import os
import stat
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Mapping

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.scene.files import file_kind, os_reason
from scenerender.scene.suggest import did_you_mean

ENV_ROOTS = "SCENERENDER_ASSET_ROOTS"
HOW_TO_ALLOW = f"allow its folder with --asset-root DIR or {ENV_ROOTS}"


@dataclass(frozen=True)
class Lookup:
    """The outcome of looking for one asset path.

    path:    the resolved file when ``problem`` is None; else the best-known location.
    problem: None, or one of "missing", "outside", "not_regular", "bad_name".
    message: the one-line explanation of ``problem`` (empty when found).
    """

    path: Path
    problem: str | None = None
    message: str = ""

    @property
    def found(self) -> bool:
        return self.problem is None


class AssetPolicy:
    """Where a scene may read files from, and the record of every file it read.

    roots:      resolved folders, the scene's folder first, then ``extra_roots``, then the
                folders in ``SCENERENDER_ASSET_ROOTS`` (os.pathsep-separated).
    files_read: every file ``resolve`` (or ``record``) returned, in order, no duplicates.
    """

    def __init__(self, scene_dir: Path, extra_roots: Iterable[Path] = (), environ: Mapping[str, str] | None = None):
        environ = os.environ if environ is None else environ
        roots = [Path(scene_dir).resolve()]
        for root in extra_roots:
            roots.append(_checked_root(Path(root), SourceLocation("--asset-root")))
        for text in environ.get(ENV_ROOTS, "").split(os.pathsep):
            if text.strip():
                roots.append(_checked_root(Path(text), SourceLocation(ENV_ROOTS)))
        self.roots: tuple[Path, ...] = tuple(dict.fromkeys(roots))
        self.files_read: list[Path] = []
        self._recorded: set[Path] = set()
        # (written, folder) -> Lookup: a scene of 50,000 objects names one mesh 50,000
        # times, and resolving symlinks costs a system call per path component.
        self._lookups: dict[tuple[str, str], Lookup] = {}

    # -- the boundary --------------------------------------------------------------------
    def resolve(self, written: str, relative_to: Path, location: SourceLocation | None = None,
                key: str | None = None) -> Path:
        """The file ``written`` names (relative to the folder ``relative_to`` unless absolute),
        resolved and recorded. Raises UserError at ``location``/``key`` when it is missing
        (with a did-you-mean), outside every root, not a regular file, or not a valid name."""
        lookup = self.lookup(written, relative_to)
        if not lookup.found:
            raise UserError(lookup.message, location, key)
        self.record(lookup.path)
        return lookup.path

    def lookup(self, written: str, relative_to: Path) -> Lookup:
        """Like ``resolve`` without raising or recording: for callers with fallbacks (an MTL
        texture tried as written, then by bare name, then ignoring letter case)."""
        key = (written, str(relative_to))
        found = self._lookups.get(key)
        if found is None:
            found = self._lookups[key] = self._lookup(written, relative_to)
        return found

    def _lookup(self, written: str, relative_to: Path) -> Lookup:
        candidate = _joined(written, relative_to)
        try:
            real = Path(os.path.realpath(candidate))
        except (OSError, ValueError) as exc:  # ENAMETOOLONG, embedded NUL...
            return Lookup(candidate, "bad_name", f"{quoted(written)}: {os_reason(exc)}")
        if not self.allows(real):
            return Lookup(real, "outside", self._outside_message(written, real))
        try:
            info = os.stat(real)
        except FileNotFoundError:
            return Lookup(real, "missing", f"file not found: {written}{_suggestion(real)}")
        except (OSError, ValueError) as exc:
            return Lookup(real, "bad_name", f"{quoted(written)}: {os_reason(exc)}")
        if not stat.S_ISREG(info.st_mode):
            return Lookup(real, "not_regular", f"{quoted(written)} is {file_kind(info.st_mode)}, not a regular file")
        return Lookup(real)

    def resolve_folder(self, written: str, relative_to: Path, location: SourceLocation | None = None,
                       key: str | None = None) -> Path:
        """A folder (a skybox folder) inside the roots; its files still go through ``resolve``."""
        candidate = _joined(written, relative_to)
        try:
            real = Path(os.path.realpath(candidate))
            if not self.allows(real):
                raise UserError(self._outside_message(written, real), location, key)
            is_dir = real.is_dir()
        except (OSError, ValueError) as exc:
            raise UserError(f"{quoted(written)}: {os_reason(exc)}", location, key) from None
        if not is_dir:
            raise UserError(f"folder not found: {written}{_suggestion(real)}", location, key)
        return real

    def allows(self, real: Path) -> bool:
        """Whether the resolved path ``real`` lies inside one of the roots."""
        return any(real == root or real.is_relative_to(root) for root in self.roots)

    def record(self, path: Path) -> None:
        """Add a resolved file to ``files_read`` (once)."""
        if path not in self._recorded:
            self._recorded.add(path)
            self.files_read.append(path)

    def _outside_message(self, written: str, real: Path) -> str:
        shown = display_path(real)
        where = f" (it resolves to {quoted(shown)})" if shown != written and str(real) != written else ""
        allowed = ", ".join([f"the scene's folder {quoted(display_path(self.roots[0]))}"]
                            + [quoted(display_path(root)) for root in self.roots[1:]])
        return (f"{quoted(written)} is outside the folders this scene may read{where}; "
                f"allowed: {allowed}; {HOW_TO_ALLOW}")


def policy_for(path: Path) -> AssetPolicy:
    """A policy rooted at a file's own folder (and the environment's roots): for loaders
    called on their own, outside a scene (tests, tools)."""
    return AssetPolicy(Path(path).parent)


# ---------------------------------------------------------------------------------------
# Helpers


def _checked_root(root: Path, where: SourceLocation) -> Path:
    try:
        real = root.expanduser().resolve()
        ok = real.is_dir()
    except (OSError, ValueError, RuntimeError) as exc:
        raise UserError(f"{quoted(str(root))}: {os_reason(exc)}", where) from None
    if not ok:
        raise UserError(f"asset root '{root}' is not a folder", where)
    return real


def _joined(written: str, relative_to: Path) -> Path:
    # Exporters on Windows write backslashes; on every platform they separate folders.
    path = Path(written.replace("\\", "/")) if "\\" in written and os.sep == "/" else Path(written)
    return path if path.is_absolute() else Path(relative_to) / path


def _suggestion(real: Path) -> str:
    """' (did you mean ...?)' from the names in the file's folder, or ''."""
    try:
        names = os.listdir(real.parent)
    except (OSError, ValueError):
        return ""
    return did_you_mean(real.name, names)


def quoted(written: str, limit: int = 120) -> str:
    """The path as written, shortened when absurdly long (it goes into a one-line message)."""
    if len(written) > limit:
        written = written[: limit // 2] + "..." + written[-limit // 4:]
    return f"'{written}'"
