"""The pure part of the Sample Viewer comparison: two renders of one model as linear light,
their mean differences, the side-by-side picture and the table. No browser, no GPU.

The Khronos Sample Viewer writes ``pow(colour, 1 / 2.2)`` into an 8-bit canvas (its
``linearTosRGB``), brought back to linear light here; scenerender gives its linear colour
itself (``Frame.linear``; its PNGs carry the piecewise sRGB curve). So the comparison is of
radiance, not of the two encodings.
"""
from __future__ import annotations

import json
from dataclasses import asdict, dataclass

import numpy as np

VIEWER_GAMMA = 2.2
# a pixel is on a surface where either linear image has more than this in some channel
SURFACE_THRESHOLD = 1.0 / 255.0
# a pixel's ratio counts where both images lie between these in every channel's sum...
# above 8-bit noise and below the clip at white, where a ratio says nothing
RATIO_RANGE = (0.02, 0.95)
DIFFERENCE_SCALE = 4.0


def gamma_to_linear(pixels: np.ndarray) -> np.ndarray:
    """(H, W, 3) uint8 written as ``pow(linear, 1 / 2.2)`` -> float64 linear in [0, 1]."""
    return (np.asarray(pixels, dtype=np.float64) / 255.0) ** VIEWER_GAMMA


def linear_to_gamma8(linear: np.ndarray) -> np.ndarray:
    """(H, W, 3) float linear -> uint8 ``round(255 pow(clip(linear, 0, 1), 1 / 2.2))``."""
    return np.round(255.0 * np.clip(linear, 0.0, 1.0) ** (1.0 / VIEWER_GAMMA)).astype(np.uint8)


@dataclass(frozen=True)
class Difference:
    """Mean absolute differences of one model's two renders.

    linear: over all pixels and channels, in % of white (linear light, each clipped to
    [0, 1] as both 8-bit outputs are); surface: the same over the pixels where either image
    shows a surface; levels: 8-bit levels, both encoded with the viewer's 1/2.2 curve;
    light_ratio: scenerender's total linear light over the viewer's; sphere_ratios: per
    column of the image (one sphere each), the median over its pixels of scenerender's
    linear light over the viewer's (``column_ratios``)."""

    linear: float
    surface: float
    levels: float
    light_ratio: float
    sphere_ratios: tuple = ()


def column_ratios(viewer_linear: np.ndarray, ours_linear: np.ndarray, bounds) -> tuple:
    """Per column [x0, x1) of ``bounds`` (pixel columns), the median of the ratio of the
    two (H, W, 3) linear images' RGB sums over the pixels where both sums / 3 lie inside
    RATIO_RANGE (nan where none do): a sphere's brightness, its outline left out."""
    a = np.asarray(viewer_linear, dtype=np.float64).sum(axis=2)
    b = np.asarray(ours_linear, dtype=np.float64).sum(axis=2)
    low, high = 3 * RATIO_RANGE[0], 3 * RATIO_RANGE[1]
    usable = (a > low) & (a < high) & (b > low) & (b < high)
    ratios = []
    for x0, x1 in bounds:
        inside = usable[:, x0:x1]
        ratios.append(float(np.median(b[:, x0:x1][inside] / a[:, x0:x1][inside])) if inside.any() else float("nan"))
    return tuple(ratios)


def difference(viewer_linear: np.ndarray, ours_linear: np.ndarray, bounds=()) -> Difference:
    """The ``Difference`` of two (H, W, 3) linear images of the same shape; ``bounds``
    the pixel columns [x0, x1) of the spheres."""
    if viewer_linear.shape != ours_linear.shape:
        raise ValueError(f"the images differ in shape: {viewer_linear.shape} and {ours_linear.shape}")
    a = np.clip(np.asarray(viewer_linear, dtype=np.float64), 0.0, 1.0)
    b = np.clip(np.asarray(ours_linear, dtype=np.float64), 0.0, 1.0)
    absolute = np.abs(a - b)
    surface = (a.max(axis=2) > SURFACE_THRESHOLD) | (b.max(axis=2) > SURFACE_THRESHOLD)
    levels = np.abs(linear_to_gamma8(a).astype(np.int16) - linear_to_gamma8(b).astype(np.int16))
    return Difference(linear=100.0 * float(absolute.mean()),
                      surface=100.0 * float(absolute[surface].mean()) if surface.any() else 0.0,
                      levels=float(levels.mean()),
                      light_ratio=float(b.sum() / a.sum()) if a.sum() > 0 else float("nan"),
                      sphere_ratios=column_ratios(a, b, bounds))


def side_by_side(viewer_pixels: np.ndarray, ours_pixels: np.ndarray, viewer_linear: np.ndarray,
                 ours_linear: np.ndarray, gap: int = 4) -> np.ndarray:
    """(H, 3 W + 2 gap, 3) uint8: the viewer's output | scenerender's output | the
    difference of the two encoded alike (1/2.2), times DIFFERENCE_SCALE; white gaps."""
    a = linear_to_gamma8(viewer_linear).astype(np.int16)
    b = linear_to_gamma8(ours_linear).astype(np.int16)
    diff = np.clip(np.abs(a - b) * DIFFERENCE_SCALE, 0, 255).astype(np.uint8)
    height = viewer_pixels.shape[0]
    white = np.full((height, gap, 3), 255, dtype=np.uint8)
    return np.concatenate([viewer_pixels, white, ours_pixels, white, diff], axis=1)


def markdown_table(rows: list[tuple[str, str, Difference]]) -> str:
    """A markdown table of (model, what it shows, Difference) rows."""
    lines = ["| model | spheres, left to right | mean abs. difference, linear (% of white) | on surfaces (%) | "
             "8-bit levels (both 1/2.2) | light, scenerender / viewer | per sphere (median pixel ratio) |",
             "|---|---|---:|---:|---:|---:|---|"]
    for name, title, d in rows:
        spheres = " ".join(f"{r:.3f}" for r in d.sphere_ratios)
        lines.append(f"| {name} | {title} | {d.linear:.2f} | {d.surface:.2f} | {d.levels:.2f} | "
                     f"{d.light_ratio:.3f} | {spheres} |")
    return "\n".join(lines) + "\n"


def json_table(rows: list[tuple[str, str, Difference]], about: dict) -> str:
    """The same rows as JSON, with ``about`` (versions, sizes) beside them."""
    return json.dumps({"about": about, "models": [{"model": name, "shows": title, **asdict(d)}
                                                  for name, title, d in rows]}, indent=2) + "\n"
