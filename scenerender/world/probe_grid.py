"""Where render.indirect's probes stand: a regular grid over the scene's bounds.

The bounds are cut into whole cells of about the spacing asked for; the probes, evenly
spaced, run from a quarter of a cell inside one face of the bounds to a quarter of a cell
inside the other. None lies on a face (the walls of a room, a ground plane, where half its
view would be the wall), and the outermost are near it: a surface there takes the light
of probes a quarter of a cell away, not half a cell (centred in the cells, the Cornell
box's ceiling read 8 % too bright against the path tracer; this way 1-4 %). No GL here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# Where render.indirect.probe_spacing is not set, the spacing gives the scene as many probes
# as a cube of its volume with this many along each side: the geometric mean of the bounds'
# sides over it. A cube (the Cornell box) gets 8x8x8; a wide, low scene gets its probes
# along the ground rather than one layer of them. Its longest side over 8, the first rule,
# put a 16 m ground's probes 2 m apart around boxes of 0.6-1.6 m and left the ground in
# their shadow 21 % dark against the path tracer; this way they are 0.92 m apart and it is
# within 2 % (benchmarks/quality/README.md, outdoors).
PROBES_ALONG_A_SIDE = 8
# The most probes a grid holds: a smaller spacing is widened to fit (the bake's cost grows
# with the count; the graph dump shows the spacing used).
MAX_PROBES = 4096
# How far inside the bounds the outermost probes stand, in cells.
MARGIN = 0.25


@dataclass(frozen=True)
class ProbeGrid:
    """origin: (3,) float64 world position of probe (0, 0, 0); spacing: (3,) float64
    between neighbours along x, y, z; counts: probes along x, y, z. Probe (i, j, k) has
    index i + nx (j + ny k)."""

    origin: np.ndarray
    spacing: np.ndarray
    counts: tuple

    @property
    def count(self) -> int:
        return int(np.prod(self.counts))

    def positions(self) -> np.ndarray:
        """(count, 3) float64 world positions, in index order."""
        k, j, i = np.meshgrid(*(np.arange(n) for n in reversed(self.counts)), indexing="ij")
        cells = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1).astype(np.float64)
        return self.origin + cells * self.spacing

    def describe(self) -> str:
        counts = "x".join(str(n) for n in self.counts)
        return f"{counts} probes, {', '.join(f'{s:.3g}' for s in self.spacing)} apart"


def default_spacing(size: np.ndarray) -> float:
    """The spacing where none is asked for: the geometric mean of ``size``'s ((3,) float64)
    sides that are not flat, over PROBES_ALONG_A_SIDE; 1.0 for a point."""
    sides = size[size > 0]
    if sides.size == 0:
        return 1.0
    return float(np.exp(np.log(sides).mean())) / PROBES_ALONG_A_SIDE


def probe_grid(bounds: np.ndarray, spacing: float | None) -> ProbeGrid:
    """The grid over ``bounds`` ((2, 3) float64 min, max) with about ``spacing`` between
    probes (None: default_spacing). Each axis is cut into whole cells of at most that
    size, one probe a cell, the outermost MARGIN of a cell inside the bounds; a flat axis
    holds one layer half a cell off it."""
    lo, hi = np.asarray(bounds, dtype=np.float64)
    size = hi - lo
    step = spacing if spacing is not None else default_spacing(size)
    while True:
        # a side within a millionth of whole cells is that many (bounds carry float32 rounding)
        counts = tuple(max(1, math.ceil(side / step - 1e-6)) for side in size)
        if math.prod(counts) <= MAX_PROBES:
            break
        step *= 1.1
    cells = np.array(counts, dtype=np.float64)
    cell = np.where(size > 0, size / cells, step)
    several = cells > 1
    spacing = np.where(several, (size - 2.0 * MARGIN * cell) / np.maximum(cells - 1.0, 1.0), cell)
    return ProbeGrid(lo + np.where(several, MARGIN, 0.5) * cell, spacing, counts)
