"""Compare rendered images with references, the way golden-image tests and
``scenerender diff`` do.

Three numbers decide:
- the mean absolute difference over all pixels and channels (8-bit levels): overall shifts
  such as a wrong colour, exposure or output transform;
- the worst tile: the largest mean difference over any 8x8 block. A small moved or
  recoloured object changes few pixels but all in one place, while rounding and
  anti-aliasing differences between drivers are spread thinly along edges;
- the percentage of pixels where some channel differs by more than a threshold.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, display_path

TILE = 8


@dataclass(frozen=True)
class DiffReport:
    mean_abs: float          # mean |a - b| over all pixels and channels, 8-bit levels
    max_abs: int             # largest channel difference
    bad_percent: float       # % of pixels with a channel differing by more than threshold
    psnr: float              # dB; inf for identical images
    threshold: int
    bad_mask: np.ndarray     # (H, W) bool
    worst_tile: float = 0.0  # largest mean |diff| of any TILE x TILE block, levels

    def within(self, tolerance: float, max_bad_percent: float, max_tile: float = float("inf")) -> bool:
        return self.mean_abs <= tolerance and self.bad_percent <= max_bad_percent and self.worst_tile <= max_tile

    def line(self) -> str:
        psnr = "inf" if np.isinf(self.psnr) else f"{self.psnr:.1f}"
        return (f"mean |diff| {self.mean_abs:.3f} levels, worst {TILE}x{TILE} tile {self.worst_tile:.2f}, "
                f"max {self.max_abs}, {self.bad_percent:.3f}% pixels off by >{self.threshold}, PSNR {psnr} dB")


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
        bad_mask=bad, worst_tile=worst_tile_mean(diff.mean(axis=2)),
    )


def worst_tile_mean(per_pixel: np.ndarray, tile: int = TILE) -> float:
    """The largest mean of ``per_pixel`` (H, W) over tile x tile blocks (edges padded)."""
    h, w = per_pixel.shape
    padded = np.zeros((-(-h // tile) * tile, -(-w // tile) * tile))
    padded[:h, :w] = per_pixel
    blocks = padded.reshape(padded.shape[0] // tile, tile, padded.shape[1] // tile, tile)
    return float(blocks.mean(axis=(1, 3)).max())


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
