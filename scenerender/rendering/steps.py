"""Long GPU work in steps a signal can stop between.

Python runs a signal's handler (run/interrupts.py) only between bytecodes of the main
thread, never inside a C call: one draw whose fragments take minutes on a software
renderer (the environment's prefilter at 2048 px and 4096 samples: 10 to 20 minutes on
Mesa llvmpipe, 2 cores) would hold SIGTERM back for all of them, since the draw returns at
once and the wait falls on one later call. So such work is cut into rectangles of its
target, each drawn under a scissor and waited for (``PassContext.checkpoint``) before the
next: the handler runs at the end of the step the signal fell in.

A scissor only drops fragments outside it; each fragment runs the same shader on the same
inputs, so the image comes out the same bytes as one full draw
(tests/test_interruptible_work.py compares them).
"""
from __future__ import annotations

from dataclasses import dataclass

# Texture lookups (the unit of ``Step.work``) sent between two waits at most: the
# prefilter's run 34 to 124 million a second on Mesa llvmpipe on 2 cores of an AMD EPYC
# (the slowest, rough levels at the equator), so a step takes under 0.2 s on such a machine
# left to itself (benchmarks/interruptible_work.py; docs/performance.md, Interruptible GPU work).
STEP_LOOKUPS = 5_000_000
# Texels of depth maps drawn between waits (ShadowMapPass): one of the environment's
# visibility maps at its largest, 4096 px, took 0.18 s on the same machine under load.
CHECKPOINT_TEXELS = 4096 * 4096
# llvmpipe shades 4x4 pixel blocks and bins 64x64 tiles, one thread a tile: rows in fours
# waste no lanes, and a power of two of 64-column tiles shares out evenly over its threads.
BLOCK_ROWS = 4
TILE_COLUMNS = 64


@dataclass(frozen=True)
class Step:
    """One draw of long work: ``rect`` (x, y, width, height) of the target, and ``work``,
    its texture lookups (pixels x lookups a pixel)."""

    rect: tuple
    work: int


def steps_over(rect: tuple, lookups_per_pixel: int, budget: int | None = None) -> list[Step]:
    """``rect`` (x, y, width, height) cut into steps of at most ``budget`` lookups where a
    pixel costs ``lookups_per_pixel``, in reading order: bands of whole rows, or where a
    band of BLOCK_ROWS rows is over the budget, pieces of such bands TILE_COLUMNS wide
    times a power of two (one piece TILE_COLUMNS wide over the budget is still one step).
    ``budget``: STEP_LOOKUPS where None."""
    x, y, width, height = rect
    budget = STEP_LOOKUPS if budget is None else budget
    pixels = max(budget // max(lookups_per_pixel, 1), 1)
    if pixels >= width * BLOCK_ROWS:
        rows = min(height, pixels // width // BLOCK_ROWS * BLOCK_ROWS)
        bands = [(top, min(rows, y + height - top)) for top in range(y, y + height, rows)]
        return [Step((x, top, width, band), lookups_per_pixel * width * band) for top, band in bands]
    tiles = max(pixels // BLOCK_ROWS // TILE_COLUMNS, 1)
    columns = (1 << (tiles.bit_length() - 1)) * TILE_COLUMNS
    steps = []
    for top in range(y, y + height, BLOCK_ROWS):
        rows = min(BLOCK_ROWS, y + height - top)
        for left in range(x, x + width, columns):
            piece = min(columns, x + width - left)
            steps.append(Step((left, top, piece, rows), lookups_per_pixel * piece * rows))
    return steps


class Waits:
    """Waits for the GPU (PassContext.checkpoint) before sending work that would take what
    was sent since the last wait past ``every`` units (STEP_LOOKUPS where None): long work
    becomes steps a signal stops between, while work that is short all along (every
    default render) waits no more than it did."""

    def __init__(self, ctx, every: int | None = None):
        self.ctx = ctx
        self.every = STEP_LOOKUPS if every is None else every
        self.sent = 0

    def before(self, work: int) -> bool:
        """``work`` is about to be sent: first wait if it would take the total since the
        last wait past ``every``; whether it waited."""
        waited = 0 < self.sent and self.every < self.sent + work
        if waited:
            self.ctx.checkpoint()
            self.sent = 0
        self.sent += work
        return waited


def draw_in_steps(ctx, steps: list[Step], draw, what: str | None = None, waits: Waits | None = None) -> None:
    """Call ``draw()`` under the scissor of each of ``steps``, waiting for the GPU before a
    step that would take the work sent since the last wait past STEP_LOOKUPS (counted by
    ``waits``, where several calls share them); ``what``: the work's name, its share done
    told at each wait (PassContext.report_work)."""
    total = sum(step.work for step in steps)
    waits = waits or Waits(ctx)
    done = 0
    if what is not None:
        ctx.report_work(what, 0.0)
    try:
        for step in steps:
            if waits.before(step.work) and what is not None:
                ctx.report_work(what, done / total)
            ctx.gl.scissor = step.rect
            draw()
            done += step.work
    finally:
        ctx.gl.scissor = None
    if what is not None:
        ctx.report_work(what, 1.0)
