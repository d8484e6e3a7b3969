"""The exact sRGB transfer function (IEC 61966-2-1) on NumPy arrays, both ways; the curve
shaders/post/encode.glsl applies."""
from __future__ import annotations

import numpy as np


def srgb_encode(linear) -> np.ndarray:
    """Linear light -> display values, both in [0, 1] (input clamped); any shape, float64."""
    c = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    return np.where(c < 0.0031308, c * 12.92, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def srgb_decode(encoded) -> np.ndarray:
    """Display values in [0, 1] -> linear light; any shape, float64."""
    e = np.asarray(encoded, dtype=np.float64)
    return np.where(e <= 0.04045, e / 12.92, ((e + 0.055) / 1.055) ** 2.4)
