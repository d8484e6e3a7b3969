"""The verdict: which differences between two frames are noise and which are a change.

A frame passes when all three colour limits hold (the two views of a difference are explained
in scenerender.compare.metrics) and, where both sides carry object ids, the three object
limits too (scenerender.compare.objects). The defaults come from the perturbation corpus (``python -m
scenerender.tools.perturbation``, tables in docs/diff-margins.md): re-renders, sub-pixel
camera jitter of 1/8 and 1/4 pixel, one-level dither and a one-level offset must pass;
moved, dropped, added, recoloured, re-lit and re-textured objects must fail.

The range limits sit 6.4 and 2.2 times above the worst noise (a tile of 0.16 levels, a mean
of 0.0003) and catch the changes of colour, light and view; the shift limit sits 2.2 times
above the worst noise (a 12x12 window of 0.32 levels: the detail scene jittered a quarter
pixel) and 2.1 times under the weakest change only it catches (a cylinder 5% smaller, 1.49
levels), and catches what the ranges excuse: a one-pixel pole added or removed, a small glow
dropped, a cylinder 10% or 5% smaller, a box turned 5 degrees, a cone 9% shorter. Every
change the colours catch fails a colour limit by twice that limit or more. A cap on the
worst pixel was measured too and left out: nothing in the corpus fails by it alone, and its
noise (a thin lamp arm under jitter, 78 levels) lies close to the thin changes it would catch.

The still region limit judges a frame the whole of which moved under 1/128 px (re-renders,
thread counts, workers: nothing past the rounding): the largest one-sign sum of levels past
the rounding over a 32x32 window may be 100 levels x px. Camera moves of 1/256 px, which
read as still, score 53-79; a halved shininess 924-975, a 3-px bead moved 1 px 134.

Where both sides were rendered with object ids (``render --check`` keeps them), three more limits
judge each object (scenerender.compare.objects): one covering pixels on one side only, one
moved against the rest of the frame, one whose interior changed colour. They catch what no
image statistic separates from a sub-pixel camera move: a 3-px bead moved 1 px, a sphere
moved 5 cm, a shininess halved, a thin pole dropped at 160x120. No noise case makes an
object appear or vanish (the thin pole covers 6 px, three times the limit); the shift limit
sits 2.2 times above the worst noise (0.20 px, a 4-px glow under a quarter-pixel jitter) and
2.2 times under the closest change (the bead, 0.98 px; the unnamed sphere, named by its
position, is gone and new when moved); the interior limit 4.8 times above
its worst noise (0.21 levels) and 2.6 times under the closest change (2.59 levels).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields

from scenerender.option_rules import LEVELS, OBJECT_PIXELS, PIXELS, TOLERANCE_LEVELS, NumberRule

TILE = 8  # side of the square blocks of the range scores and of the shift search, pixels
SHIFT_WINDOW = 12  # side of the windows the residual after the shift is averaged over, pixels


def limit(default, rule: NumberRule, metavar: str, help: str):
    """A DiffRule field: its default, its rule (option_rules), and what ``scenerender diff``
    shows for the option made from it (``--max-tile`` for ``max_tile``)."""
    return field(default=default, metadata={"rule": rule, "metavar": metavar, "help": help})


@dataclass(frozen=True)
class DiffRule:
    """A frame passes when all three colour limits hold, and the object limits where both
    sides have object ids. The tile limit catches a local change the neighbourhood ranges
    cannot explain (an object moved or dropped, a lost shadow); the mean limit a faint change
    spread wide (a colour, the field of view); the shift window limit a small or thin change
    the ranges excuse (a bias no quarter-pixel shift makes: a shape grown, an edge turned),
    and one strong feature only one image has (a thin pole added or removed); the still
    region limit, in a frame nothing moved in, a faint change of one sign the allowances for
    moved edges would forgive (a recolour of a faceted model, a highlight widened). The object
    limits catch an object on one side only, one moved against the frame's common
    displacement, and an interior changed one way (a shininess, a colour)."""

    max_tile: float = limit(1.0, LEVELS, "LEVELS",
                            "Largest allowed mean difference (levels) of any 8x8 block outside the other image's 3x3 "
                            "colour ranges: catches a moved or dropped object, a lost shadow.")
    max_unexplained_mean: float = limit(0.0007, LEVELS, "LEVELS",
                                        "Largest allowed difference per pixel outside the 3x3 colour ranges, over "
                                        "the frame (levels): catches faint changes spread wide, such as a colour or "
                                        "the field of view.")
    max_shift_tile: float = limit(0.7, LEVELS, "LEVELS",
                                  "Largest allowed signed mean (levels) of any 12x12 window of what is left after "
                                  "each 8x8 tile's best shift of up to 1/4 pixel: catches small and thin changes "
                                  "the ranges excuse.")
    max_still_region: float = limit(100.0, LEVELS, "LEVELS_X_PX",
                                    "In a frame that did not move (the whole picture moved under 1/128 px): largest "
                                    "allowed sum of levels past the rounding over one connected region changed one "
                                    "way (a recolour, a shininess).")
    aa_tolerance: int = limit(1, TOLERANCE_LEVELS, "LEVELS",
                              "Levels of rounding forgiven on every channel, before both tests.")
    # with object ids on both sides (compare.objects)
    min_object_pixels: int = limit(2, OBJECT_PIXELS, "PX",
                                   "With object ids on both sides: an object covering this many pixels or more on "
                                   "one side and none on the other fails (a dropped pole, a new glow).")
    max_object_shift: float = limit(0.45, PIXELS, "PX",
                                    "With object ids on both sides: largest allowed move of an object against the "
                                    "frame's common displacement (a camera jitter moves every object alike), pixels.")
    max_interior_change: float = limit(1.0, LEVELS, "LEVELS",
                                       "With object ids on both sides: largest allowed signed mean change of an "
                                       "object's interior, after its own move, discounted by the change of the other "
                                       "sign (a shininess, a colour).")

    def __post_init__(self):
        """The Python door to the limits' rules (``scenerender diff`` makes its options from
        the same fields): ValueError naming the field."""
        for item in fields(self):
            problem = item.metadata["rule"].problem(getattr(self, item.name))
            if problem is not None:
                raise ValueError(f"DiffRule.{item.name}: {problem}")

    def failures(self, metrics, objects=None) -> list[str]:
        """The limits ``metrics`` (a ``compare.metrics.FrameMetrics``) and ``objects`` (a
        ``compare.objects.ObjectMetrics``, where both sides have object ids) exceed, as short
        phrases ([] when the frame passes). The rule imports no metrics code, so the command
        line reads its defaults at start-up without loading numpy."""
        out = self.object_failures(objects) if objects is not None else []
        if metrics.worst_tile_aa > self.max_tile:
            out.append(f"worst {TILE}x{TILE} tile {metrics.worst_tile_aa:.2f} > {self.max_tile:g} levels unexplained")
        if metrics.unexplained_mean > self.max_unexplained_mean:
            out.append(f"unexplained mean {metrics.unexplained_mean:.4f} > {self.max_unexplained_mean:g} levels")
        if metrics.still_region > self.max_still_region:
            out.append(f"nothing moved, yet a region changed one way: {metrics.still_region:.0f} > "
                       f"{self.max_still_region:g} levels x px")
        if metrics.shift_tile > self.max_shift_tile:
            out.append(f"a {SHIFT_WINDOW}x{SHIFT_WINDOW} window {metrics.shift_tile:.2f} > {self.max_shift_tile:g} levels off "
                       "after the best shift")
        return out

    def object_failures(self, objects) -> list[str]:
        """The object limits ``objects`` (a ``compare.objects.ObjectMetrics``) exceeds, a
        phrase per object (the first few of each kind, the worst first)."""
        one_side, moved, inside = self.offenders(objects)
        return (_first([f"{s.status}: {s.name} on {s.coverage} px of the "
                        f"{'output' if s.status == 'new' else 'reference'} only" for s in one_side], "object(s)")
                + _first([f"{s.name} moved {s.shift:.2f} px against the frame (> {self.max_object_shift:g})"
                          for s in moved], "moved")
                + _first([f"{s.name} interior {abs(s.interior):.2f} levels {'brighter' if s.interior > 0 else 'darker'}"
                          f" (> {self.max_interior_change:g})" for s in inside], "interior(s) changed"))

    def offenders(self, objects) -> tuple[list, list, list]:
        """The objects (``ObjectScore``) past each object limit, the worst first: on one side
        only, moved, changed inside."""
        one_side = sorted((s for s in objects.objects if s.status != "both" and s.coverage >= self.min_object_pixels),
                          key=lambda s: -s.coverage)
        moved = sorted((s for s in objects.objects if s.shift is not None and s.shift > self.max_object_shift),
                       key=lambda s: -s.shift)
        inside = sorted((s for s in objects.objects
                         if s.interior is not None and abs(s.interior) > self.max_interior_change),
                        key=lambda s: -abs(s.interior))
        return one_side, moved, inside

    def describe(self) -> str:
        return (f"difference outside both 3x3 colour ranges ({self.aa_tolerance} level tolerance): worst {TILE}x{TILE} "
                f"tile <= {self.max_tile:g} levels, frame mean <= {self.max_unexplained_mean:g} levels; difference "
                f"left after the best shift of up to 1/4 px per {TILE}x{TILE} tile, both ways: signed mean of any "
                f"{SHIFT_WINDOW}x{SHIFT_WINDOW} window <= {self.max_shift_tile:g} levels; in a frame that did not move "
                f"(under 1/128 px), no region changed one way by more than {self.max_still_region:g} levels x px "
                f"summed; where both sides have object ids, no "
                f"object on {self.min_object_pixels} px or more of one side only, none moved more than "
                f"{self.max_object_shift:g} px against the frame, no interior changed more than "
                f"{self.max_interior_change:g} levels")

    def to_json(self) -> dict:
        return asdict(self)


def _first(phrases: list[str], what: str, shown: int = 3) -> list[str]:
    return phrases[:shown] + ([f"{len(phrases) - shown} more {what}"] if len(phrases) > shown else [])


DEFAULT_RULE = DiffRule()
