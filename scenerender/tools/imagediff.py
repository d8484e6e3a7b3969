"""Compare rendered images with references, the way golden-image tests and
``scenerender diff`` do.

Two numbers decide: the mean absolute difference over all channels (in 8-bit levels),
which catches overall shifts such as a wrong colour or exposure; and the percentage of
pixels where some channel differs by more than a threshold, which catches a moved object
even when most of the image is unchanged. Anti-aliased edges and driver rounding move a
few pixels by a few levels; the defaults allow that and nothing more.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, display_path


@dataclass(frozen=True)
class DiffReport:
    mean_abs: float          # mean |a - b| over all pixels and channels, 8-bit levels
    max_abs: int             # largest channel difference
    bad_percent: float       # % of pixels with a channel differing by more than threshold
    psnr: float              # dB; inf for identical images
    threshold: int
    bad_mask: np.ndarray     # (H, W) bool

    def within(self, tolerance: float, max_bad_percent: float) -> bool:
        return self.mean_abs <= tolerance and self.bad_percent <= max_bad_percent

    def line(self) -> str:
        psnr = "inf" if np.isinf(self.psnr) else f"{self.psnr:.1f}"
        return (f"mean |diff| {self.mean_abs:.3f} levels, max {self.max_abs}, "
                f"{self.bad_percent:.3f}% pixels off by >{self.threshold}, PSNR {psnr} dB")


def compare(reference: np.ndarray, candidate: np.ndarray, pixel_threshold: int = 16) -> DiffReport:
    """Compare two (H, W, C) uint8 images of the same shape."""
    if reference.shape != candidate.shape:
        raise ValueError(f"images differ in size: {reference.shape} vs {candidate.shape}")
    diff = np.abs(reference.astype(np.int16) - candidate.astype(np.int16))
    mse = float(np.mean(diff.astype(np.float64) ** 2))
    bad = diff.max(axis=2) > pixel_threshold
    return DiffReport(
        mean_abs=float(diff.mean()), max_abs=int(diff.max()), bad_percent=100.0 * float(bad.mean()),
        psnr=float("inf") if mse == 0 else 10.0 * np.log10(255.0 ** 2 / mse), threshold=pixel_threshold,
        bad_mask=bad,
    )


def load_rgb(path: Path) -> np.ndarray:
    from PIL import Image

    try:
        with Image.open(path) as image:
            return np.asarray(image.convert("RGB"))
    except OSError as exc:
        raise UserError(f"cannot read image ({exc})", SourceLocation(display_path(path))) from None


def compare_files(reference: Path, candidate: Path, heatmap: Path | None = None,
                  pixel_threshold: int = 16) -> DiffReport:
    a, b = load_rgb(reference), load_rgb(candidate)
    if a.shape != b.shape:
        raise UserError(f"sizes differ: {a.shape[1]}x{a.shape[0]} vs {b.shape[1]}x{b.shape[0]}",
                        SourceLocation(display_path(candidate)))
    report = compare(a, b, pixel_threshold)
    if heatmap is not None:
        write_heatmap(a, b, report, heatmap)
    return report


def write_heatmap(a: np.ndarray, b: np.ndarray, report: DiffReport, path: Path) -> None:
    """A grey version of the reference with differing pixels in red (brighter = larger)."""
    from PIL import Image

    grey = (a.mean(axis=2) * 0.5).astype(np.uint8)
    out = np.stack([grey, grey, grey], axis=2)
    magnitude = np.abs(a.astype(np.int16) - b.astype(np.int16)).max(axis=2)
    changed = magnitude > 0
    out[changed, 0] = np.clip(128 + magnitude[changed] * 4, 0, 255)
    out[changed, 1:] = 0
    Image.fromarray(out).save(path)
