"""Reading input files safely: the scene file and every asset go through here.

A path is opened without blocking and checked with fstat before anything is read, so a
FIFO, a device or a folder named as an input is refused instead of hanging the run or
flooding memory; at most ``max_bytes + 1`` bytes are ever read. Every OSError (missing,
permission, name too long...) becomes a one-line UserError naming the file.

A JSON file is read by ``read_json_file``: bounded in size here, in depth by
json_input.parse_json; the reader then validates the value into its typed model.
"""
from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.json_input import JSON_MAX_DEPTH, JsonProblem, parse_json


def open_regular_file(path: Path, what: str = "file"):
    """A binary file object for ``path``, which must be a regular file (use it in ``with``)."""
    where = SourceLocation(display_path(path))
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except (OSError, ValueError) as exc:
        raise UserError(cannot_read(what, exc), where) from None
    try:
        mode = os.fstat(fd).st_mode
    except OSError as exc:
        os.close(fd)
        raise UserError(cannot_read(what, exc), where) from None
    if not stat.S_ISREG(mode):
        os.close(fd)
        raise UserError(f"the {what} is not a regular file ({file_kind(mode)})", where)
    return os.fdopen(fd, "rb")


def read_regular_file(path: Path, what: str = "file", max_bytes: int | None = None,
                      limit_name: str | None = None) -> bytes:
    """The bytes of the regular file ``path``; with ``max_bytes`` a larger file is a UserError
    that names the ``--limit`` raising it, and no more than ``max_bytes + 1`` bytes are read."""
    where = SourceLocation(display_path(path))
    with open_regular_file(path, what) as stream:
        try:
            if max_bytes is None:
                return stream.read()
            _check_size(os.fstat(stream.fileno()).st_size, max_bytes, what, limit_name, where)
            data = stream.read(max_bytes + 1)
        except OSError as exc:  # EIO, EISDIR races...
            raise UserError(cannot_read(what, exc), where) from None
    _check_size(len(data), max_bytes, what, limit_name, where)  # the file grew while it was read
    return data


def _check_size(size: int, max_bytes: int, what: str, limit_name: str | None, where: SourceLocation) -> None:
    if size > max_bytes:
        how = f" (raise with --limit {limit_name}=N)" if limit_name else ""
        raise UserError(f"the {what} is {size:,} bytes, over the limit of {max_bytes:,}{how}", where)


def cannot_read(what: str, exc: BaseException) -> str:
    """'MESH FILE not found', 'cannot read the scene file: its name is too long'..."""
    if isinstance(exc, FileNotFoundError):
        return f"{what} not found"
    return f"cannot read the {what}: {os_reason(exc)}"


def os_reason(exc: BaseException) -> str:
    """A short reason for an OS-level failure, e.g. 'file name too long'."""
    if isinstance(exc, OSError):
        if exc.errno == errno.ENAMETOOLONG:
            return "file name too long"
        if exc.errno == errno.ELOOP:
            return "too many levels of symbolic links"
        if exc.strerror:
            return exc.strerror[0].lower() + exc.strerror[1:]
    if isinstance(exc, ValueError) and "null" in str(exc).lower():
        return "the name contains a NUL character"
    if isinstance(exc, RuntimeError):  # Path.resolve on a symlink loop (Python < 3.13)
        return "too many levels of symbolic links"
    return str(exc) or type(exc).__name__


def file_kind(mode: int) -> str:
    """What a non-regular file is, for messages: 'a folder', 'a named pipe'..."""
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a named pipe (FIFO)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a plain file"


def read_json_file(path: Path, what: str, max_bytes: int, max_depth: int = JSON_MAX_DEPTH):
    """The JSON value of the regular file ``path`` of at most ``max_bytes``: a UserError
    naming the file where it cannot be read, is larger, or is not JSON within the bounds."""
    data = read_regular_file(path, what, max_bytes)
    try:
        return parse_json(data, max_depth)
    except JsonProblem as exc:
        raise UserError(f"the {what} is {exc}", SourceLocation(display_path(path))) from None
