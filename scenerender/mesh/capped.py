"""At most a few warnings per file, however often a problem repeats in it.

A model exported with 500 materials that all name textures left on the artist's machine
would otherwise print 500 lines; the user needs the first few and a count.
"""
from __future__ import annotations

from scenerender.errors import SourceLocation, Warnings

SHOWN_PER_FILE = 3


class CappedWarnings:
    """Passes the first ``shown`` warnings on to ``warnings``; counts the rest, which
    ``finish`` reports as one line. With a strict ``warnings`` the first one raises, as
    before."""

    def __init__(self, warnings: Warnings, source: str, shown: int = SHOWN_PER_FILE):
        self.warnings = warnings
        self.source = source
        self.shown = shown
        self.given = 0

    @property
    def strict(self) -> bool:
        return self.warnings.strict

    def warn(self, message: str, location: SourceLocation | None = None) -> None:
        self.given += 1
        if self.given <= self.shown:
            self.warnings.warn(message, location)

    def finish(self) -> None:
        """One line for the warnings not shown, if any."""
        hidden = self.given - self.shown
        if hidden > 0:
            self.warnings.warn(f"and {hidden} more warning{'s' if hidden != 1 else ''} like these",
                               SourceLocation(self.source))
        self.given = 0
