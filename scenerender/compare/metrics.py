"""Per-frame difference metrics between a reference and an output image.

Every function takes (H, W, 3) uint8 sRGB images of the same shape. Scores grow with the
difference (SSIM is reported as is, 1 = identical). Differences are in 8-bit levels.

The edge-tolerant scores count only differences that no sub-pixel shift explains. For each
pixel and channel, the *unexplained* difference is how far the output's colour lies outside
the colour range of the reference's 3x3 neighbourhood, or the reference's colour outside the
output's, whichever is smaller (a difference is excused when either image's neighbourhood
holds the other's colour, as in pixelmatch's anti-aliasing test), less a tolerance of a
level or so for rounding; a pixel's score is the largest over its channels. A sub-pixel
shift blends neighbouring colours, so it stays inside the ranges; a moved, dropped or
recoloured object puts colours where neither image had them. The price: a change one or two
pixels wide (a thin pole dropped) also finds its colours next door, and is excused.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from scenerender.compare.rule import TILE


PIXEL_THRESHOLD = 24  # levels: a "bad" pixel in the plain (not edge-tolerant) count


@dataclass(frozen=True)
class FrameMetrics:
    """The numbers for one frame pair. ``None`` where a metric is not available (FLIP
    without the optional package, for passing frames and for changed frames past the report's
    picture cap; SSIM on images under 3x3)."""

    mean_abs: float          # mean |diff| over all pixels and channels, levels
    max_abs: int             # largest channel difference, levels
    worst_tile: float        # largest mean |diff| of any TILE x TILE block, levels
    bad_percent: float       # % of pixels with a channel off by more than PIXEL_THRESHOLD
    psnr: float              # dB; inf for identical images
    unexplained_mean: float  # mean unexplained difference per pixel, levels
    worst_tile_aa: float     # largest mean unexplained difference of any TILE x TILE block, levels
    changed_percent: float   # % of pixels with an unexplained difference
    ssim: float | None       # structural similarity, 1 = identical
    flip: float | None       # mean FLIP error (0 = identical, 1 = as different as can be)

    def to_json(self) -> dict:
        """Plain JSON values: inf PSNR becomes null."""
        out = asdict(self)
        out["psnr"] = None if math.isinf(self.psnr) else round(self.psnr, 3)
        for key in ("mean_abs", "worst_tile", "bad_percent", "worst_tile_aa", "changed_percent", "flip"):
            if out[key] is not None:
                out[key] = round(out[key], 4)
        out["unexplained_mean"] = round(self.unexplained_mean, 6)
        if out["ssim"] is not None:
            out["ssim"] = round(out["ssim"], 5)
        return out


@dataclass(frozen=True)
class DiffMaps:
    """Per-pixel maps behind the scores, for heatmaps and outlined regions."""

    magnitude: np.ndarray    # (H, W) int16: largest channel |diff|
    unexplained: np.ndarray  # (H, W) float32: unexplained difference, levels (0 where excused)

    @property
    def excused(self) -> np.ndarray:
        """(H, W) bool: pixels that differ, but no more than an edge shift and the tolerance explain."""
        return (self.magnitude > 0) & (self.unexplained == 0)


def absolute_difference(reference: np.ndarray, output: np.ndarray) -> np.ndarray:
    """(H, W, 3) uint8 x2 -> (H, W, 3) int16 |reference - output|."""
    return np.abs(reference.astype(np.int16) - output.astype(np.int16))


def neighbourhood_range(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per-channel min and max over each pixel's 3x3 neighbourhood (edges repeated).
    (H, W, C) -> two (H, W, C) int16 arrays."""
    h, w = image.shape[:2]
    padded = np.pad(image.astype(np.int16), ((1, 1), (1, 1), (0, 0)), mode="edge")
    low = padded[1:h + 1, 1:w + 1].copy()
    high = low.copy()
    for dy in range(3):
        for dx in range(3):
            window = padded[dy:dy + h, dx:dx + w]
            np.minimum(low, window, out=low)
            np.maximum(high, window, out=high)
    return low, high


def unexplained_difference(reference: np.ndarray, output: np.ndarray, tolerance: int) -> np.ndarray:
    """(H, W) float32: per pixel, the largest over channels of the difference no sub-pixel
    shift explains (see the module notes), less ``tolerance`` levels, at least 0."""
    ref_low, ref_high = neighbourhood_range(reference)
    out_low, out_high = neighbourhood_range(output)
    ref, out = reference.astype(np.int16), output.astype(np.int16)
    outside_ref = np.maximum(np.maximum(ref_low - out, out - ref_high), 0)
    outside_out = np.maximum(np.maximum(out_low - ref, ref - out_high), 0)
    excess = np.minimum(outside_ref, outside_out).max(axis=2)
    return np.maximum(excess - tolerance, 0).astype(np.float32)


def tile_means(per_pixel: np.ndarray, tile: int = TILE) -> np.ndarray:
    """Mean of ``per_pixel`` (H, W) over tile x tile blocks -> (ceil(H/tile), ceil(W/tile))
    float64. Partial blocks at the right and bottom edges average only their own pixels, so
    a change in a thin edge strip is not diluted."""
    h, w = per_pixel.shape
    rows, cols = -(-h // tile), -(-w // tile)
    sums = np.zeros((rows * tile, cols * tile))
    counts = np.zeros_like(sums)
    sums[:h, :w] = per_pixel
    counts[:h, :w] = 1
    shape = (rows, tile, cols, tile)
    return sums.reshape(shape).sum(axis=(1, 3)) / counts.reshape(shape).sum(axis=(1, 3))


def psnr(diff: np.ndarray) -> float:
    """Peak signal-to-noise ratio in dB of an int16 difference array; inf when all zero."""
    mse = float(np.mean(diff.astype(np.float64) ** 2))
    return math.inf if mse == 0 else 10.0 * math.log10(255.0 ** 2 / mse)


def ssim(reference: np.ndarray, output: np.ndarray) -> float | None:
    """Mean structural similarity over the colour channels (scikit-image, 7x7 windows or
    the largest odd window that fits); None for images under 3 pixels on a side."""
    side = min(reference.shape[:2])
    window = min(7, side if side % 2 else side - 1)
    if window < 3:
        return None
    from skimage.metrics import structural_similarity  # slow to import: only when used

    return float(structural_similarity(reference, output, channel_axis=2, data_range=255, win_size=window))


def flip_error(reference: np.ndarray, output: np.ndarray) -> float | None:
    """Mean FLIP error (0..1) for LDR sRGB images, or None when the optional
    ``flip-evaluator`` package is not installed."""
    try:
        import flip_evaluator
    except ImportError:
        return None
    as_float = [np.ascontiguousarray(image, dtype=np.float32) / 255.0 for image in (reference, output)]
    _, mean, _ = flip_evaluator.evaluate(as_float[0], as_float[1], "LDR", applyMagma=False)
    return float(mean)


def flip_available() -> bool:
    try:
        import flip_evaluator  # noqa: F401
    except ImportError:
        return False
    return True


def _flip_score(reference: np.ndarray, output: np.ndarray, identical: bool) -> float | None:
    if not flip_available():
        return None
    return 0.0 if identical else flip_error(reference, output)


def measure(reference: np.ndarray, output: np.ndarray, aa_tolerance: int,
            with_flip: bool = True) -> tuple[FrameMetrics, DiffMaps]:
    """All metrics for two (H, W, 3) uint8 images of one shape, and the maps behind them."""
    diff = absolute_difference(reference, output)
    magnitude = diff.max(axis=2)
    identical = not magnitude.any()
    if identical:
        unexplained = np.zeros(magnitude.shape, np.float32)
    else:
        unexplained = unexplained_difference(reference, output, aa_tolerance)
    metrics = FrameMetrics(
        mean_abs=float(diff.mean()),
        max_abs=int(magnitude.max()),
        worst_tile=float(tile_means(diff.mean(axis=2, dtype=np.float32)).max()),
        bad_percent=100.0 * float((magnitude > PIXEL_THRESHOLD).mean()),
        psnr=psnr(diff),
        unexplained_mean=float(unexplained.mean()),
        worst_tile_aa=float(tile_means(unexplained).max()),
        changed_percent=100.0 * float((unexplained > 0).mean()),
        ssim=1.0 if identical else ssim(reference, output),
        flip=_flip_score(reference, output, identical) if with_flip else None,
    )
    return metrics, DiffMaps(magnitude, unexplained)
