"""What a comparison found: one entry per frame pair, the frames only one side has, and the
lines and JSON that ``scenerender diff`` prints."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from scenerender.compare.metrics import FrameMetrics
from scenerender.compare.objects import ObjectMetrics
from scenerender.compare.rule import SHIFT_WINDOW, DiffRule
from scenerender.compare.sources import Side
from scenerender.version import __version__

Box = tuple[int, int, int, int]  # x, y, width, height in pixels


@dataclass
class FrameImages:
    """The pictures a report shows for a frame that differs, each (H, W, 3) uint8. ``output``
    has the reference's size only when the sizes matched; ``heatmap`` and ``shifts`` (each
    differing tile coloured by its best shift) are None otherwise; ``objects`` (the objects
    an object limit failed) only where both sides have object ids and one did."""

    reference: np.ndarray
    output: np.ndarray
    heatmap: np.ndarray | None
    shifts: np.ndarray | None
    objects: np.ndarray | None = None   # the objects a limit failed, each in a colour of its own
    focus: tuple[int, int, int, int] | None = None  # (x, y, w, h): the window the report shows close up
    focus_note: str = ""                # what that window holds, in words


@dataclass(frozen=True)
class Forgiven:
    """A large difference a pass excused: its box (x, y, w, h), the excused pixels off by 5
    levels or more in it, those off by more than 50, and the largest difference, levels."""

    box: Box
    pixels: int
    large: int
    levels: int

    def text(self) -> str:
        return (f"{self.pixels} px off by 5 levels or more, {self.large} of them by over 50, up to {self.levels}, "
                f"at {_box_text(self.box)}")


@dataclass
class FrameComparison:
    """One frame pair. ``reason`` says why it failed ("" when it passed); ``metrics`` is
    None when the sizes differ; ``regions`` box the connected changed tiles; ``objects``:
    the scores by object where both sides have object ids, else None, and ``colour_only``
    says why."""

    name: str
    passed: bool
    reason: str = ""
    metrics: FrameMetrics | None = None
    regions: list[Box] = field(default_factory=list)
    size: tuple[int, int] | None = None          # (width, height) of the reference frame
    images: FrameImages | None = None           # kept for frames that differ, up to a cap
    objects: ObjectMetrics | None = None
    colour_only: str = ""   # why it was judged by its colours alone ("" when by object ids too)
    forgiven: list = field(default_factory=list)  # Forgiven: large, connected differences a pass excused
    ignored: int = 0        # pixels left out: the reference folder's ignore regions (compare.ignore)

    def forgiven_line(self) -> str:
        """A passing frame's large excused differences in words ("" when none)."""
        if not self.forgiven:
            return ""
        return (f"PASS {self.name}, but it excused a large, connected difference: "
                + "; ".join(f.text() for f in self.forgiven)
                + " (judged a sub-pixel edge shift; look at the boxes in the report)")

    def attribution(self) -> str:
        """The changed pixels by object ('bunny: 482 px; new: thin_pole 111 px'), or ''."""
        return self.objects.attribution() if self.objects is not None else ""

    def summary_line(self) -> str:
        text = f"CHANGED {self.name}: {self.reason}"
        if self.metrics is not None:
            m = self.metrics
            psnr = "inf" if math.isinf(m.psnr) else f"{m.psnr:.1f}"
            extras = [f"mean {m.mean_abs:.2f}", f"PSNR {psnr} dB"]
            if m.ssim is not None:
                extras.append(f"SSIM {m.ssim:.4f}")
            if m.flip is not None:
                extras.append(f"FLIP {m.flip:.4f}")
            text += f" ({', '.join(extras)})"
        if self.regions:
            text += f"; {len(self.regions)} region(s), largest at {_box_text(max(self.regions, key=_area))}"
        if self.attribution():
            text += f"; by object: {self.attribution()}"
        return text

    def excused_line(self) -> str:
        """What a passing frame that differs forgave ("" when nothing differs)."""
        m = self.metrics
        if m is None or m.excused_pixels == 0:
            return ""
        text = (f"PASS {self.name}: {m.excused_pixels} px excused as sub-pixel edge shifts and rounding (tiles "
                f"shifted <= {m.largest_shift:g} px; left after the shift: window {m.shift_tile:.2f}, "
                f"pixel {m.shift_pixel:.0f} levels)")
        if self.objects is not None:
            o = self.objects
            text += (f"; objects moved <= {o.shift:.2f} px against the frame, interiors <= {o.interior:.2f} levels"
                     + (f"; by object: {self.attribution()}" if self.attribution() else ""))
        return text

    def to_json(self) -> dict:
        return {"name": self.name, "passed": self.passed, "reason": self.reason,
                "size": list(self.size) if self.size else None,
                "metrics": self.metrics.to_json() if self.metrics else None,
                "regions": [list(box) for box in self.regions],
                "objects": self.objects.to_json() if self.objects is not None else None,
                "judged_by": "colour" if self.colour_only else "object ids and colour",
                "ignored_pixels": self.ignored,
                "forgiven": [{"box": list(f.box), "pixels": f.pixels, "over_50": f.large, "levels": f.levels}
                             for f in self.forgiven],
                "colour_only_because": self.colour_only or None}


def _area(box: Box) -> int:
    return box[2] * box[3]


def _box_text(box: Box) -> str:
    x, y, w, h = box
    return f"x {x}..{x + w - 1}, y {y}..{y + h - 1}"


@dataclass
class CompareResult:
    """The outcome of ``compare_paths``. Frames are in reference order; ``missing`` are in
    the reference only, ``extra`` in the output only (both are failures)."""

    reference: Side
    output: Side
    rule: DiffRule
    frames: list[FrameComparison] = field(default_factory=list)
    missing: list[str] = field(default_factory=list)
    extra: list[str] = field(default_factory=list)
    images_kept: int = 0      # frames that differ whose pictures are kept for the report
    images_dropped: int = 0   # changed frames whose pictures were not kept (cap reached)
    pictures: bool = True     # keep what a report shows (pictures, SSIM, FLIP); False: the verdict alone
    ignore: object = None     # compare.ignore.IgnoreRegions of the reference folder

    @property
    def changed(self) -> list[FrameComparison]:
        return [frame for frame in self.frames if not frame.passed]

    @property
    def passed(self) -> bool:
        return not self.changed and not self.missing and not self.extra

    @property
    def verdict(self) -> str:
        return "same" if self.passed else "changed"

    def counts(self) -> dict:
        return {"compared": len(self.frames), "passed": len(self.frames) - len(self.changed),
                "changed": len(self.changed), "missing": len(self.missing), "extra": len(self.extra)}

    def total_line(self) -> str:
        return self._total() + "; " + self.judged_by() + self.ignored_text()

    def ignored_text(self) -> str:
        """'; ignored: 640 px in 1 frame(s) (ignore.json: clock)', or ''."""
        frames = [frame for frame in self.frames if frame.ignored]
        if not frames:
            return ""
        return (f"; ignored: {sum(f.ignored for f in frames)} px in {len(frames)} frame(s) "
                f"({self.ignore.describe()})")

    def judged_by(self) -> str:
        """How the frames were judged, in words: by object ids and colour, or by colour
        alone and why (the first reason; a CI run that silently lost its ids must say so)."""
        measured = [frame for frame in self.frames if frame.metrics is not None]
        by_colour = [frame for frame in measured if frame.colour_only]
        if not measured:
            return "nothing judged"
        if not by_colour:
            return f"judged by object ids and colour ({len(measured)} frame(s))"
        why = by_colour[0].colour_only
        if len(by_colour) == len(measured):
            return f"judged by colour alone: {why}"
        return (f"judged by object ids and colour: {len(measured) - len(by_colour)} of {len(measured)} frame(s); "
                f"by colour alone: {len(by_colour)} ({why})")

    def _total(self) -> str:
        c = self.counts()
        if self.passed:
            measured = [f.metrics for f in self.frames if f.metrics]
            excused = sum(m.excused_pixels for m in measured)
            if not any(m.max_abs for m in measured):
                return f"PASS: {c['compared']} frame(s) match (identical)"
            if not excused:
                return f"PASS: {c['compared']} frame(s) match (differences within {self.rule.aa_tolerance} level(s))"
            shift = max(m.largest_shift for m in measured)
            worst = max(m.shift_tile for m in measured)
            return (f"PASS: {c['compared']} frame(s) match; {excused} px excused as sub-pixel edge shifts and "
                    f"rounding (tiles shifted <= {shift:g} px; worst {SHIFT_WINDOW}x{SHIFT_WINDOW} window after the shift "
                    f"{worst:.2f} levels)")
        return (f"FAIL: {c['changed']} of {c['compared']} frame(s) changed, {c['missing']} missing, "
                f"{c['extra']} extra")

    def summary_lines(self, excused: bool = False) -> list[str]:
        """One line per changed, missing and extra frame, then the total line; with
        ``excused``, first a line per passing frame that differs, saying what it forgave."""
        passing = [frame for frame in self.frames if frame.passed] if excused else []
        lines = [line for line in (frame.excused_line() for frame in passing) if line]
        lines += [frame.forgiven_line() for frame in self.frames if frame.passed and frame.forgiven]
        lines += [frame.summary_line() for frame in self.changed]
        lines += [f"MISSING {name}: in the reference, not in the output" for name in self.missing]
        lines += [f"EXTRA {name}: in the output, not in the reference" for name in self.extra]
        return lines + [self.total_line()]

    def to_json(self) -> dict:
        """What ``scenerender diff --json`` prints."""
        return {
            "verdict": self.verdict,
            "passed": self.passed,
            "counts": self.counts(),
            "rule": self.rule.to_json(),
            "reference": self.reference.to_json(),
            "output": self.output.to_json(),
            "frames": [frame.to_json() for frame in self.frames],
            "missing": list(self.missing),
            "extra": list(self.extra),
            "judged_by": self.judged_by(),
            "compared_by": f"scenerender {__version__}",
        }
