"""The verdict: which differences between two frames are noise and which are a change.

The default limits come from the perturbation suite (``python -m
scenerender.compare.perturbation``, tables in docs/diff-margins.md): re-renders, sub-pixel
camera jitter, one-level dither and a one-level offset must pass; a moved or dropped object,
a 10% colour change, a shadow switched off, fov changed by one degree and a swapped texture
must fail. Measured at 160x120 over four scenes, the largest noise scores were a worst tile
of 0.094 levels and an unexplained mean of 0.0003 levels. Every local change (moved,
dropped, shadow, texture) scored a tile of 2.6 levels or more, so the tile limit sits at
1.0, ten times the noise; the faint wide changes (colour, fov) are caught by the mean,
whose smallest change score was 0.0023, so its limit sits at 0.001, about three times the
noise and half the closest change.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the rule itself needs no numpy: the command line reads its defaults at start-up
    from scenerender.compare.metrics import FrameMetrics

TILE = 8  # side of the square blocks of the worst-tile scores, pixels


@dataclass(frozen=True)
class DiffRule:
    """A frame passes when both limits hold. "Unexplained" differences are those no
    sub-pixel shift explains, less ``aa_tolerance`` levels (see scenerender.compare.metrics).
    The tile limit catches a local change (an object moved or dropped, a lost shadow) at any
    image size; the mean limit a faint change spread wide (a colour, the field of view)."""

    max_tile: float = 1.0                # worst TILE x TILE block of unexplained difference, levels
    max_unexplained_mean: float = 0.001  # unexplained difference per pixel over the frame, levels
    aa_tolerance: int = 1                # levels of rounding forgiven beyond the neighbourhood ranges

    def failures(self, metrics: "FrameMetrics") -> list[str]:
        """The limits ``metrics`` exceeds, as short phrases ([] when the frame passes)."""
        out = []
        if metrics.worst_tile_aa > self.max_tile:
            out.append(f"worst {TILE}x{TILE} tile {metrics.worst_tile_aa:.2f} > {self.max_tile:g} levels unexplained")
        if metrics.unexplained_mean > self.max_unexplained_mean:
            out.append(f"unexplained mean {metrics.unexplained_mean:.4f} > {self.max_unexplained_mean:g} levels")
        return out

    def describe(self) -> str:
        return (f"unexplained difference (edge shifts excused, {self.aa_tolerance} level tolerance): "
                f"worst {TILE}x{TILE} tile <= {self.max_tile:g} levels, frame mean <= "
                f"{self.max_unexplained_mean:g} levels")

    def to_json(self) -> dict:
        return asdict(self)


DEFAULT_RULE = DiffRule()
