"""The sink interface and the write-whole-or-nothing helpers.

Every output file is first written to a temporary name beside it and renamed into place
only when whole. Temporary names follow one pattern,
``.<final name>.<pid>-<token>.partial<suffix>``, so that a later run can recognise (and
remove) the ones a killed run left behind without ever touching anyone else's files.
Operating-system failures while writing (disk full, read-only, no permission) become
``UserError`` naming the path: the user can act on them, they are not bugs.
"""
from __future__ import annotations

import contextlib
import errno
import os
import re
import secrets
from pathlib import Path

from scenerender.errors import SourceLocation, UserError, display_path


class FrameSink:
    """Receives frames in order. ``write`` takes a ``render.renderer.FrameResult``-like
    object with ``index``, ``pixels`` ((H, W, 3) uint8) and ``linear`` ((H, W, 3) float32
    or None). ``close`` finishes the output; ``abort`` discards anything unfinished.

    ``target`` is what it writes: the folder of an image sequence (``is_sequence``), else
    the one file (a video, or a single image)."""

    needs_linear = False
    is_sequence = False
    keeps_cameras = True  # a cameras.json beside the output (sinks/cameras.py)
    target: Path

    def write(self, frame) -> None:  # pragma: no cover - interface
        raise NotImplementedError

    def is_complete(self, index: int) -> bool:  # pragma: no cover - interface
        """True when frame ``index`` already exists whole in the output."""
        raise NotImplementedError

    def close(self) -> None:
        """Finish: after this every output file is complete."""

    def abort(self) -> None:
        """Stop after an error: leave no partial file behind."""

    def describe(self) -> str:
        return ""


# ---------------------------------------------------------------------------------------
# operating-system write failures -> user errors

# errno -> what the user can do about it; {option} is the option that named the destination
_WRITE_FAILURES = {
    errno.ENOSPC: "free some space or write elsewhere with {option}",
    errno.EDQUOT: "free some space or write elsewhere with {option}",
    errno.EROFS: "the file system is read-only; write elsewhere with {option}",
    errno.EACCES: "no permission to write there; write elsewhere with {option}",
    errno.EPERM: "no permission to write there; write elsewhere with {option}",
    errno.ENAMETOOLONG: "use a shorter output name",
    errno.ENOTDIR: "a file stands where a folder is needed; write elsewhere with {option}",
    errno.EISDIR: "a folder stands where a file is needed; write elsewhere with {option}",
    # a folder that takes no new entries (/proc, /sys) or one removed while writing
    errno.ENOENT: "the folder it would go in does not take new files; write elsewhere with {option}",
}
# The failures any OSError reaching the command line is taken for. ENOENT is not among
# them: outside the writing helpers it is far more often a bug than a user's mistake.
WRITE_ERRNOS = frozenset(_WRITE_FAILURES) - {errno.ENOENT}
OUTPUT_OPTION = "-o"  # the option naming most destinations; `diff` has --report, references --check


def write_failure(path, code: int, option: str = OUTPUT_OPTION) -> UserError:
    """The one-line error for failing to write ``path`` (given with ``option``) with
    ``errno`` ``code``, e.g. ``out/frame_0003.png: cannot write: no space left on device
    (free some space or write elsewhere with -o)``."""
    cause = os.strerror(code).lower()
    hint = _WRITE_FAILURES[code].format(option=option)
    return UserError(f"cannot write: {cause} ({hint})", SourceLocation(display_path(path)))


@contextlib.contextmanager
def output_errors(path, option: str = OUTPUT_OPTION):
    """Turn an OSError the user can act on (disk full, no permission, a file in the way...)
    into a UserError naming ``path``, or the folder the OSError names (a folder that cannot
    be created), and ``option``, where the user can give another destination; never a
    temporary name, which means nothing to the user. Every output of every command is
    created and written inside this."""
    try:
        yield
    except OSError as exc:
        if exc.errno not in _WRITE_FAILURES:
            raise
        named = exc.filename
        if not named or PARTIAL in os.path.basename(os.fspath(named)):
            named = path
        raise write_failure(named, exc.errno, option) from None


def make_folders(folder: Path) -> None:
    """``mkdir -p folder``. A file standing where the last folder should be is reported
    like one further up (ENOTDIR), not as the EEXIST mkdir gives, which reads as a bug."""
    try:
        Path(folder).mkdir(parents=True, exist_ok=True)
    except FileExistsError as exc:
        raise NotADirectoryError(errno.ENOTDIR, os.strerror(errno.ENOTDIR), exc.filename) from None


# ---------------------------------------------------------------------------------------
# temporary names

PARTIAL = ".partial"
# The final name is shortened inside the temporary name so a long (but valid) final name
# cannot make the temporary one exceed the file system's 255-byte limit.
_NAME_PART_MAX = 96  # bytes
_OURS = re.compile(r"^\..+\.(?P<pid>\d+)-[0-9a-f]{8}\.partial(\.[A-Za-z0-9]+)?$")
# Names made by earlier versions (mkstemp tokens; the video's fixed name). No process id,
# so they can only be left-overs of a killed run of such a version.
_LEGACY = (re.compile(r"^\..+\.(png|jpg|tga|exr)\.[a-z0-9_]{8}\.partial\.\1$"),
           re.compile(r"^\..+\.(mp4|gif)\.partial\.\1$"))


def temp_name(final: Path) -> str:
    """A fresh temporary name for ``final``, carrying this process's id."""
    stem = os.fsencode(final.name)[:_NAME_PART_MAX].decode("utf-8", "ignore") or "x"
    return f".{stem}.{os.getpid()}-{secrets.token_hex(4)}{PARTIAL}{final.suffix}"


def create_temp(final: Path) -> Path:
    """Create an empty temporary file beside ``final`` (exclusively, so never someone
    else's) and return its path. Created with mode 0666 so the umask decides the final
    permissions, as for any other tool (mkstemp would force 0600)."""
    for _ in range(100):
        temp = final.parent / temp_name(final)
        try:
            os.close(os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666))
        except FileExistsError:  # a token collision: draw again
            continue
        return temp
    raise FileExistsError(errno.EEXIST, "no free temporary name", str(final))  # pragma: no cover


def _process_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True


def is_stale_partial(name: str) -> bool:
    """True for a temporary name of ours whose writing process no longer runs."""
    match = _OURS.match(name)
    if match is not None:
        return not _process_alive(int(match["pid"]))
    return any(pattern.match(name) for pattern in _LEGACY)


def remove_stale_partials(folder: Path) -> list[Path]:
    """Delete the temporary files killed runs left in ``folder`` (only names of our own
    pattern whose process is gone; live runs' files are kept) -> the paths removed."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    removed = []
    with output_errors(folder):
        for entry in os.scandir(folder):
            if entry.name.startswith(".") and PARTIAL in entry.name and is_stale_partial(entry.name) \
                    and entry.is_file(follow_symlinks=False):
                with contextlib.suppress(FileNotFoundError):  # another run removed it first
                    os.unlink(entry.path)
                removed.append(Path(entry.path))
    return removed


# ---------------------------------------------------------------------------------------
# writing whole files


@contextlib.contextmanager
def atomic_path(final: Path, option: str = OUTPUT_OPTION):
    """Yield an (empty, existing) temporary path beside ``final``; rename it to ``final``
    only when the body succeeds, remove it otherwise. Write failures the user can act on
    (disk full, read-only, no permission) raise UserError naming ``final`` and ``option``
    (see ``output_errors``)."""
    final = Path(final)
    temp = None
    try:
        with output_errors(final, option):
            make_folders(final.parent)
            temp = create_temp(final)
            yield temp
            os.replace(temp, final)
    finally:
        if temp is not None and os.path.lexists(temp):
            with contextlib.suppress(OSError):  # cleanup must not hide the first error
                os.unlink(temp)


def write_file(path: Path, data) -> None:
    """Write ``data`` (bytes-like) to ``path`` with plain file I/O, so that a full disk or a failed
    flush raises OSError with its errno (some encoders writing by themselves do not)."""
    with open(path, "wb") as handle:
        handle.write(data)
