"""How many triangles a scene may still load, shared by every mesh it reads.

Loaders check the budget while they read, before building arrays for the triangles, so a
mesh far over the limit fails in seconds instead of exhausting memory first.
"""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.errors import SourceLocation, UserError
from scenerender.limits import exceeded_message


@dataclass
class TriangleBudget:
    """limit: triangles all meshes may have together (``Limits.triangles``); used: loaded so far."""

    limit: int
    used: int = 0

    @classmethod
    def unlimited(cls) -> "TriangleBudget":
        return cls(limit=2**62)

    @property
    def remaining(self) -> int:
        return self.limit - self.used

    def check(self, more: int, location: SourceLocation | None = None) -> None:
        """Raise when ``more`` triangles on top of those loaded would exceed the limit."""
        if self.used + more > self.limit:
            what = "triangles in the scene's meshes" if self.used else "triangles in this mesh"
            raise UserError(exceeded_message("triangles", self.used + more, self.limit, what), location)

    def charge(self, more: int, location: SourceLocation | None = None) -> None:
        """``check``, then count ``more`` as loaded."""
        self.check(more, location)
        self.used += more
