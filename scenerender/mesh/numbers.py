"""The range of the numbers a mesh or material file may hold.

Positions, normals, texture coordinates and material values are stored and drawn as 32-bit
floats. A number beyond their range (about 3.4e38 in size) becomes infinity when it is
rounded, and everything computed from it after that is meaningless (a triangle with an
infinite corner has no area, a normal no direction). The readers therefore refuse such a
number where they read it, naming the file and line, as the scene reader does for the
numbers of the scene file (``scene.values.check_number``).
"""
from __future__ import annotations

import numpy as np

from scenerender.scene.values import FLOAT32_MAX

# How messages say that a value (a number read, or one computed from them) is too large.
BEYOND_FLOAT32 = "beyond 32-bit floats (at most 3.4e38 in size)"


def fits_float32(values: np.ndarray) -> np.ndarray:
    """Elementwise: whether each value is finite and no larger in size than the largest
    32-bit float (False for NaN and infinity too, so one test covers both)."""
    return np.abs(values) <= FLOAT32_MAX


def beyond_float32(value: float, key: str | None = None) -> str:
    """The message for a finite number too large for a 32-bit float (read after ``key``)."""
    after = f" after '{key}'" if key else ""
    return f"expected a number at most 3.4e38 in size (32-bit floats){after}, got {float(value):g}"
