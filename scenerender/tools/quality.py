"""Error of a GPU frame against a reference frame, whole-image and by region.

Regions come from the reference's per-pixel records (ReferenceFrame.shadow, .cone, .mixed):
- shadow edge: pixels within ``radius`` pixels of a shadow boundary (a pixel partly in
  shadow, or next to a pixel whose shadow fraction differs by more than a half), less the
  pixels whose samples see more than one surface;
- cone edge: within ``radius`` pixels of where a spot cone factor changes by more than 0.2
  between neighbours (a hard or narrow cone edge; a wide smooth falloff is not an edge),
  less those same pixels;
- geometry edge: within one pixel of a pixel that sees more than one object;
- interior: everything else, where only the shading equations can differ.

A silhouette pixel's error is how well the pixel's MSAA samples cover the geometry, the
same for every light and with shadows off, so it counts as geometry edge only: where an
object stands on the floor, its silhouette runs along its own contact shadow, and with 4
samples its coverage error alone (0.033 RMS on the GPU; 0.037 with exact shading at the
four sample points) outweighed every shadow pixel of a hard spot's shadow-edge region.

RMSE is over pixels and channels, in percent of full scale: "linear" on linear colour
clamped to [0, 1] (what the GPU stores before encoding), "srgb" on the 8-bit display values;
"_rel" numbers are in percent of the reference's mean linear radiance over the image (a
spot light lighting a third of the image has a third of the radiance to be wrong about).
Umbra leak: over the pixels fully in some light's shadow (and partly in none), the light
the GPU lets through, in percent of the light the reference's shadows take away there.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from scenerender.compare.metrics import flip_available, flip_error, psnr

EDGE_RADIUS = 2


def _neighbour_range(values: np.ndarray) -> np.ndarray:
    """(H, W) float -> (H, W) max - min over each pixel's 3x3 neighbourhood."""
    return ndimage.maximum_filter(values, size=3, mode="nearest") - ndimage.minimum_filter(values, size=3,
                                                                                          mode="nearest")


def _dilate(mask: np.ndarray, radius: int) -> np.ndarray:
    if radius <= 0 or not mask.any():
        return mask
    return ndimage.binary_dilation(mask, structure=np.ones((2 * radius + 1, 2 * radius + 1), bool))


def region_masks(reference, radius: int = EDGE_RADIUS) -> dict:
    """{"shadow_edge", "cone_edge", "geometry_edge", "interior"}: (H, W) bool masks."""
    height, width = reference.object.shape
    shadow = np.zeros((height, width), bool)
    for s in range(reference.shadow.shape[2]):
        fraction = reference.shadow[:, :, s]
        shadow |= ((fraction > 0.0) & (fraction < 1.0)) | (_neighbour_range(fraction) > 0.5)
    cone = np.zeros((height, width), bool)
    for c in range(reference.cone.shape[2]):
        cone |= _neighbour_range(reference.cone[:, :, c]) > 0.2
    shadow = _dilate(shadow, radius) & ~reference.mixed
    cone = _dilate(cone, radius) & ~reference.mixed
    geometry = _dilate(reference.mixed, 1)
    return {"shadow_edge": shadow, "cone_edge": cone, "geometry_edge": geometry,
            "interior": ~(shadow | cone | geometry)}


def rmse_percent(a: np.ndarray, b: np.ndarray, mask: np.ndarray | None = None, scale: float = 1.0) -> float | None:
    """RMSE of (H, W, 3) images over ``mask`` (H, W) pixels, in percent of ``scale``; None
    for an empty mask."""
    diff = (a.astype(np.float64) - b.astype(np.float64)) / scale
    if mask is not None:
        if not mask.any():
            return None
        diff = diff[mask]
    return 100.0 * math.sqrt(float(np.mean(diff * diff)))


def frame_errors(reference, pixels: np.ndarray, linear: np.ndarray | None, with_flip: bool = True) -> dict:
    """Every error number of one GPU frame against ``reference`` (a ReferenceFrame).

    pixels: (H, W, 3) uint8 display values; linear: (H, W, 3) float linear colour, or None
    (then the linear numbers are None). Returns a flat dict of floats (None where a region
    is empty or a metric is unavailable) and the pixel count of each region."""
    masks = region_masks(reference)
    ref_linear = np.clip(reference.linear, 0.0, 1.0)
    out_linear = None if linear is None else np.clip(linear, 0.0, 1.0)
    result = {
        "rmse_srgb": rmse_percent(reference.pixels, pixels, scale=255.0),
        "psnr": _finite(psnr(np.abs(reference.pixels.astype(np.int16) - pixels.astype(np.int16)))),
        "flip": flip_error(reference.pixels, pixels) if with_flip and flip_available() else None,
    }
    mean = float(ref_linear.mean())
    for name in ("whole", "shadow_edge", "cone_edge", "geometry_edge", "interior"):
        mask = None if name == "whole" else masks[name]
        key = "rmse_linear" if name == "whole" else f"{name}_rmse"
        result[key] = None if out_linear is None else rmse_percent(ref_linear, out_linear, mask)
        if name in ("shadow_edge", "cone_edge"):
            result[f"{name}_rel"] = (None if result[key] is None or mean <= 0.0
                                     else rmse_percent(ref_linear, out_linear, mask, scale=mean))
    result["umbra_leak"] = None if linear is None else umbra_leak(reference, linear)
    result["pixels"] = {name: int(mask.sum()) for name, mask in masks.items()}
    return result


def umbra_leak(reference, linear: np.ndarray) -> float | None:
    """Percent of the light the reference's shadows take away that ``linear`` (H, W, 3)
    still shows, over the pixels fully in some shadowed light's shadow and partly in none
    (silhouettes left out); None without such pixels."""
    if reference.blocked is None or reference.shadow.shape[2] == 0:
        return None
    full, none = reference.shadow == 1.0, reference.shadow == 0.0
    umbra = full.any(axis=2) & (full | none).all(axis=2) & ~reference.mixed
    taken = float(reference.blocked[umbra].sum())
    if taken <= 0.0:
        return None
    extra = (linear.astype(np.float64) - reference.linear).mean(axis=2)[umbra]
    return 100.0 * float(extra.sum()) / taken


def _finite(value: float) -> float | None:
    return None if math.isinf(value) else float(value)
