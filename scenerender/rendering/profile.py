"""The per-pass profile: where a run's time went, pass by pass.

A GraphRenderer made with ``profile=True`` waits for the GPU before and after each pass
(``glFinish``), so each pass's time is its own and not the queue's; that makes the run
slower than a normal one, but the shares are right. Static passes run once per run and
are listed as such, not averaged into the per-frame figures. A pass that keeps its result
in frames where nothing it read changed (a shadow map whose views stayed put) shows its
median when it ran, and adds its mean over all frames to the per-frame total.
"""
from __future__ import annotations

import statistics
from dataclasses import dataclass

CPU_SETUP = "frame setup (CPU)"  # evaluating the frame and uploading instances and lights


@dataclass(frozen=True)
class PassTiming:
    """One row of the profile. Times in milliseconds."""

    name: str
    runs: int
    median_ms: float
    total_ms: float
    once: bool  # a static pass: it ran on the first frame only


def summarise(timings: dict, frames: int, static_names: set) -> list[PassTiming]:
    """``timings``: pass name -> list of seconds (GraphRenderer.timings) -> rows in run order."""
    rows = []
    for name, seconds in timings.items():
        if not seconds:
            continue
        rows.append(PassTiming(name, len(seconds), statistics.median(seconds) * 1000.0,
                               sum(seconds) * 1000.0, name in static_names and frames > 1))
    return rows


def format_table(rows: list[PassTiming], frames: int) -> str:
    """A Markdown table: ms per frame (median), total ms and share of the run's total."""
    total = sum(row.total_ms for row in rows) or 1.0
    per_frame = sum(row.median_ms if row.runs >= frames else row.total_ms / frames for row in rows if not row.once)
    lines = [f"per-pass profile over {frames} frame(s), GPU-synchronised:", "",
             "| pass | runs | ms per frame (median) | total ms | share |", "|---|---|---|---|---|"]
    for row in rows:
        median = f"{row.median_ms:.2f}"
        if row.once:
            median += " (once)"
        elif row.runs < frames:
            median += f" (in {row.runs} of {frames} frames)"
        lines.append(f"| {row.name} | {row.runs} | {median} | {row.total_ms:.1f} | "
                     f"{100.0 * row.total_ms / total:.0f}% |")
    lines.append(f"| **every frame** | | **{per_frame:.2f}** | {total:.1f} | 100% |")
    return "\n".join(lines)


def profile_report(renderer, frames: int) -> str:
    """The table for a GraphRenderer made with ``profile=True`` after ``frames`` renders."""
    static = {node.render_pass.name for node in renderer.compiled.passes if node.index in renderer.compiled.static}
    return format_table(summarise(renderer.timings or {}, frames, static), frames)
