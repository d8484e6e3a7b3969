"""Error of a GPU frame against the reference where a light with a size casts its shadow.

Regions from the reference's per-pixel shadow record (ReferenceFrame.shadow: the fraction
of a pixel's samples whose ray towards the light, drawn over the light's surface, is
blocked), over the pixels whose samples all see one surface and no silhouette:
- umbra: every sample blocked (shadow 1);
- penumbra band: some samples blocked, some not;
- open ground: none blocked.

Each region's error is the GPU's mean linear radiance over the reference's, less 1
(``*_bias``), and the RMS of the per-pixel difference over the reference's mean in the
region (``*_rms``), both images first averaged over SMOOTH x SMOOTH pixels of one surface:
the reference draws one point of the light per sample, so a band pixel of 64 samples is
noisy by about 6 % of the lit level on its own, which the average brings to about 2 %
(unsmoothed, the GPU's band error reads 13 % where the smoothed one reads 7 %). The umbra, where the reference is near black, is measured against the
open ground's mean instead: the light the GPU lets through, in percent of the lit level.
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

# A pixel is in the band when between these fractions of its samples are blocked; a few
# samples either side are left to the umbra and the open ground.
BAND = (0.05, 0.95)
SMOOTH = 3


def _smoothed(values: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """(H, W) ``values`` averaged over SMOOTH x SMOOTH pixels, counting only ``mask``'s."""
    total = ndimage.uniform_filter(np.where(mask, values, 0.0), SMOOTH, mode="constant")
    weight = ndimage.uniform_filter(mask.astype(np.float64), SMOOTH, mode="constant")
    return np.where(weight > 0.0, total / np.maximum(weight, 1e-12), 0.0)


def penumbra_regions(reference, light: int = 0) -> dict:
    """{"umbra", "penumbra", "open"}: (H, W) bool masks for shadowed light ``light``
    (a frame with no shadowed light is open ground throughout)."""
    clean = ~reference.mixed
    if reference.shadow.shape[2] <= light:
        return {"umbra": np.zeros_like(clean), "penumbra": np.zeros_like(clean), "open": clean}
    fraction = reference.shadow[:, :, light]
    return {"umbra": clean & (fraction >= 1.0), "penumbra": clean & (fraction > BAND[0]) & (fraction < BAND[1]),
            "open": clean & (fraction <= 0.0)}


def penumbra_errors(reference, linear: np.ndarray, light: int = 0) -> dict:
    """{"umbra_leak", "penumbra_bias", "penumbra_rms", "open_bias", "open_rms"} in percent,
    and the pixel count of each region (``*_pixels``)."""
    masks = penumbra_regions(reference, light)
    clean = ~reference.mixed
    ref = _smoothed(reference.linear.astype(np.float64).mean(axis=2), clean)
    gpu = _smoothed(np.asarray(linear, dtype=np.float64)[:, :, :3].mean(axis=2), clean)
    out = {f"{name}_pixels": int(mask.sum()) for name, mask in masks.items()}
    open_level = float(ref[masks["open"]].mean()) if masks["open"].any() else 1.0
    for name in ("penumbra", "open"):
        mask = masks[name]
        if not mask.any():
            out[f"{name}_bias"] = out[f"{name}_rms"] = None
            continue
        level = float(ref[mask].mean())
        out[f"{name}_bias"] = 100.0 * (float(gpu[mask].mean()) / level - 1.0)
        out[f"{name}_rms"] = 100.0 * float(np.sqrt(np.mean((gpu[mask] - ref[mask]) ** 2))) / level
    umbra = masks["umbra"]
    out["umbra_leak"] = 100.0 * float((gpu[umbra] - ref[umbra]).mean()) / open_level if umbra.any() else None
    return out


def penumbra_columns(reference, linear: np.ndarray) -> dict:
    """The band's numbers for the bench table of a frame whose first shadowed light has a
    size: {"penumbra_rms", "penumbra_bias"}."""
    errors = penumbra_errors(reference, linear)
    return {"penumbra_rms": errors["penumbra_rms"], "penumbra_bias": errors["penumbra_bias"]}
