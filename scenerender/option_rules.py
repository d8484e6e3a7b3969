"""The rule of every option that more than one door takes, declared once.

A value can reach the renderer through the command line (``--samples 4``), the scene file
(``render: {samples: 4}``, also ``--set render.samples=4``) and the Python API
(``Renderer(scene, samples=4)``). Each door checks it with the one ``NumberRule`` here and
says what is wrong in the same words: the command line through ``cli.RuleType`` (exit 2),
the scene model through its validator (file, line and key), the API as a ``ValueError``.
The diff options are the fields of ``compare.rule.DiffRule``, each with its rule here.

Imports nothing but the standard library: the command line reads it at start-up.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass


@dataclass(frozen=True)
class NumberRule:
    """A finite number, whole where ``integer``, within ``lo``..``hi`` (either may be open
    ended), or one of ``choices`` when those are given. ``what`` names the value in
    messages; ``note`` follows the list of choices (``(1 = off)``)."""

    what: str
    lo: float | None = None
    hi: float | None = None
    integer: bool = False
    choices: tuple = ()
    note: str = ""

    def problem(self, value) -> str | None:
        """What is wrong with ``value`` in one phrase, or None when it keeps the rule."""
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            return f"{self.what} must be {self._kind()}, got {value!r}"
        if not math.isfinite(value):
            return f"{self.what} must be a finite number, got {value}"
        if self.integer and not float(value).is_integer():
            return f"{self.what} must be a whole number, got {value:g}"
        if self.choices and value not in self.choices:
            note = f" {self.note}" if self.note else ""
            return f"{self.what} must be one of {', '.join(map(str, self.choices))}{note}, got {value:g}"
        if (self.lo is not None and value < self.lo) or (self.hi is not None and value > self.hi):
            return f"{self.what} must be {self.bounds()}, got {value:g}"
        return None

    def check(self, value):
        """``value`` (an int where ``integer``), or ValueError saying what is wrong."""
        problem = self.problem(value)
        if problem is not None:
            raise ValueError(problem)
        return int(value) if self.integer else float(value)

    def bounds(self) -> str:
        if self.choices:
            return "one of " + ", ".join(map(str, self.choices))
        if self.hi is None:
            return f"{self.lo:g} or more"
        if self.lo is None:
            return f"{self.hi:g} or less"
        return f"{self.lo:g}..{self.hi:g}"

    def _kind(self) -> str:
        return "a whole number" if self.integer else "a number"


# GL multisampled images come in powers of two only (moderngl refuses any other count), so
# a count no device offers is refused at every door rather than by the driver mid-render;
# a device offering fewer than asked lowers the count with a warning (rendering/renderer.py).
MSAA_SAMPLES = NumberRule("MSAA samples", integer=True, choices=(1, 2, 4, 8, 16, 32, 64), note="(1 = off)")

# the diff rule's limits (compare/rule.py): a NaN limit compares false with every score and
# an infinite one passes every change, so both are refused
LEVELS = NumberRule("a limit in 8-bit levels", lo=0)
PIXELS = NumberRule("a limit in pixels", lo=0)
TOLERANCE_LEVELS = NumberRule("a tolerance in 8-bit levels", lo=0, hi=255, integer=True)
OBJECT_PIXELS = NumberRule("an object's pixel count", lo=1, integer=True)

# the CPU reference (raytrace/render.py; `scenerender reference` and `bench`)
SPP = NumberRule("samples a pixel along each axis (spp)", lo=1, hi=32, integer=True)
AMBIENT_SAMPLES = NumberRule("ambient samples", lo=0, hi=65536, integer=True)
ENVIRONMENT_SAMPLES = NumberRule("environment samples", lo=1, hi=65536, integer=True)
DEFAULT_ENVIRONMENT_SAMPLES = 4  # directions a sample point draws from an environment light
SHUTTER_SAMPLES = NumberRule("shutter samples", lo=1, hi=4096, integer=True)
DEFAULT_SHUTTER_SAMPLES = 32  # instants over an open shutter (camera.shutter)
BOUNCES = NumberRule("bounces", lo=0, hi=1024, integer=True)  # 0: direct light only
