"""Errors a user can act on, each printed as one line by the CLI.

``UserError`` and its subclasses mean "your input is wrong" (exit code 2);
``EnvironmentProblem`` means "this machine lacks something" (exit code 3).
Anything else reaching the CLI is a bug in scenerender (exit code 1).
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SourceLocation:
    """Where a value came from: a file and 1-based line/column, or a CLI option."""

    file: str
    line: int | None = None
    column: int | None = None

    def __str__(self) -> str:
        if self.line is None:
            return self.file
        if self.column is None:
            return f"{self.file}:{self.line}"
        return f"{self.file}:{self.line}:{self.column}"


class UserError(Exception):
    """Bad input: a scene file, an asset or a command-line option. Exit code 2.

    ``kind`` groups errors that are the same mistake repeated (e.g. the same bad key in
    every object) so that a list of them can say "and 297 more like it"; by default the
    message itself is the kind.
    """

    exit_code = 2

    def __init__(self, message: str, location: SourceLocation | None = None, key: str | None = None,
                 kind=None):
        super().__init__(message)
        self.message = message
        self.location = location
        self.key = key
        self.kind = kind if kind is not None else message

    def __str__(self) -> str:
        parts = []
        if self.location is not None:
            parts.append(str(self.location))
        if self.key:
            parts.append(self.key)
        parts.append(self.message)
        return one_line(": ".join(parts))


class SceneErrors(UserError):
    """Several problems found at once in one scene file; each prints on its own line.

    However many there are, ``lines()`` stays short: one line per kind of problem (its first
    occurrence), "(and N more like it)" for repeats, at most ``MAX_LINES`` lines.
    """

    MAX_LINES = 10

    def __init__(self, errors: list[UserError]):
        first = errors[0]
        super().__init__(first.message, first.location, first.key, first.kind)
        self.errors = errors

    def lines(self) -> list[str]:
        groups: dict = {}
        for error in self.errors:
            groups.setdefault(error.kind, []).append(error)
        shown = list(groups.values())
        if len(shown) > self.MAX_LINES:
            shown = shown[:self.MAX_LINES - 1]
        lines = []
        for group in shown:
            more = f" (and {len(group) - 1} more like it)" if len(group) > 1 else ""
            lines.append(str(group[0]) + more)
        hidden = len(self.errors) - sum(len(group) for group in shown)
        if hidden:
            lines.append(f"... and {hidden} more problem{'s' if hidden != 1 else ''}")
        return lines


class EnvironmentProblem(Exception):
    """The machine lacks something scenerender needs (an EGL driver, ffmpeg). Exit code 3."""

    exit_code = 3


class Warnings:
    """Collects warnings; with ``strict`` the first one becomes a ``UserError`` instead."""

    def __init__(self, strict: bool = False, echo=None):
        self.strict = strict
        self.items: list[str] = []
        self._echo = echo

    def warn(self, message: str, location: SourceLocation | None = None) -> None:
        text = f"{location}: {message}" if location is not None else message
        if self.strict:
            raise UserError(message + " (--strict turns warnings into errors)", location)
        self.items.append(text)
        if self._echo is not None:
            self._echo(f"warning: {text}")


LONGEST_WORD = 400  # characters without a space a message shows whole (a path, a value)


def one_line(text: str) -> str:
    """Messages are one line: control characters in user values are shown escaped, and a
    run of more than LONGEST_WORD characters without a space (a pasted value) is cut in the
    middle, so one bad value cannot fill the terminal."""
    text = printable(text)
    if "\n" in text or "\r" in text or "\t" in text:
        text = text.replace("\r", "\\r").replace("\n", "\\n").replace("\t", "\\t")
    if len(text) > LONGEST_WORD:
        text = " ".join(_shortened(word) for word in text.split(" "))
    return text


def printable(text: str) -> str:
    """``text`` with what no terminal can be sent escaped: a lone surrogate (valid in a JSON
    string as ``\\ud800``, or a file name's undecodable byte) becomes ``\\ud800``."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return text.encode("utf-8", "backslashreplace").decode("utf-8")
    return text


def _shortened(word: str) -> str:
    if len(word) <= LONGEST_WORD:
        return word
    return f"{word[:200]}...({len(word) - 260:,} characters left out)...{word[-60:]}"


def display_path(path) -> str:
    """A path as a user wants to read it in a message: relative to the working
    directory when that is shorter, else as given."""
    import os

    text = os.fspath(path)
    try:
        rel = os.path.relpath(text)
    except ValueError:  # another drive on Windows
        return text
    return rel if len(rel) < len(text) or not os.path.isabs(text) else text
