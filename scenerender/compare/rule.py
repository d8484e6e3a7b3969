"""The verdict: which differences between two frames are noise and which are a change.

A frame passes when all three limits hold (the two views of a difference are explained in
scenerender.compare.metrics). The defaults come from the perturbation corpus (``python -m
scenerender.compare.perturbation``, tables in docs/diff-margins.md): re-renders, sub-pixel
camera jitter of 1/8 and 1/4 pixel, one-level dither and a one-level offset must pass;
moved, dropped, added, recoloured, re-lit and re-textured objects must fail.

The range limits sit about five times above the worst noise (a tile of 0.20 levels, a mean
of 0.0002) and catch the changes of colour, light and view; the shift limit sits 1.27 times
above the worst noise (a window of 3.9 levels: a quarter-pixel jitter of a textured floor)
and catches what the ranges excuse: a one-pixel pole added or removed, a small glow
dropped, a cylinder 10% smaller, a box turned 5 degrees, a cone 9% shorter. A cap on the
worst pixel was measured too and left out: nothing in the corpus fails by it alone, and its
noise (a thin lamp arm under jitter, 78 levels) lies close to the thin changes it would catch.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

TILE = 8  # side of the square blocks and windows of the scores, pixels


@dataclass(frozen=True)
class DiffRule:
    """A frame passes when all three limits hold. The tile limit catches a local change the
    neighbourhood ranges cannot explain (an object moved or dropped, a lost shadow); the mean
    limit a faint change spread wide (a colour, the field of view); the shift window limit a
    small or thin change the ranges excuse (a bias no quarter-pixel shift makes: a shape
    grown, an edge turned); the shift pixel limit one strong feature only one image has (a
    thin pole added or removed)."""

    max_tile: float = 1.0                # worst TILE x TILE block outside the neighbourhood ranges, levels
    max_unexplained_mean: float = 0.001  # frame mean outside the neighbourhood ranges, levels
    max_shift_tile: float = 5.0          # worst |signed mean| left after a shift, any TILE x TILE window, levels
    aa_tolerance: int = 1                # levels of rounding forgiven on every channel

    def failures(self, metrics) -> list[str]:
        """The limits ``metrics`` (a ``compare.metrics.FrameMetrics``) exceeds, as short phrases
        ([] when the frame passes). The rule imports no metrics code, so the command line
        reads its defaults at start-up without loading numpy."""
        out = []
        if metrics.worst_tile_aa > self.max_tile:
            out.append(f"worst {TILE}x{TILE} tile {metrics.worst_tile_aa:.2f} > {self.max_tile:g} levels unexplained")
        if metrics.unexplained_mean > self.max_unexplained_mean:
            out.append(f"unexplained mean {metrics.unexplained_mean:.4f} > {self.max_unexplained_mean:g} levels")
        if metrics.shift_tile > self.max_shift_tile:
            out.append(f"a {TILE}x{TILE} window {metrics.shift_tile:.2f} > {self.max_shift_tile:g} levels off "
                       "after the best shift")
        return out

    def describe(self) -> str:
        return (f"difference outside both 3x3 colour ranges ({self.aa_tolerance} level tolerance): worst {TILE}x{TILE} "
                f"tile <= {self.max_tile:g} levels, frame mean <= {self.max_unexplained_mean:g} levels; difference "
                f"left after the best shift of up to 1/4 px per {TILE}x{TILE} tile, both ways: signed mean of any "
                f"{TILE}x{TILE} window <= {self.max_shift_tile:g} levels")

    def to_json(self) -> dict:
        return asdict(self)


DEFAULT_RULE = DiffRule()
