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
    """Bad input: a scene file, an asset or a command-line option. Exit code 2."""

    exit_code = 2

    def __init__(self, message: str, location: SourceLocation | None = None, key: str | None = None):
        super().__init__(message)
        self.message = message
        self.location = location
        self.key = key

    def __str__(self) -> str:
        parts = []
        if self.location is not None:
            parts.append(str(self.location))
        if self.key:
            parts.append(self.key)
        parts.append(self.message)
        return one_line(": ".join(parts))


class SceneErrors(UserError):
    """Several problems found at once in one scene file; each prints on its own line."""

    def __init__(self, errors: list[UserError]):
        first = errors[0]
        super().__init__(first.message, first.location, first.key)
        self.errors = errors

    def lines(self) -> list[str]:
        return [str(e) for e in self.errors]


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


def one_line(text: str) -> str:
    """Messages are one line: control characters in user values are shown escaped."""
    if "\n" in text or "\r" in text or "\t" in text:
        return text.replace("\r", "\\r").replace("\n", "\\n").replace("\t", "\\t")
    return text


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
