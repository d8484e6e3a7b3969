"""Which faces of a closed surface a viewpoint cannot see.

A closed, consistently wound surface seen from outside shows only the faces turned towards
the viewpoint; the others are hidden behind them. Drawing those hidden faces changes no
pixel of a camera image and no depth of a shadow map (the nearest surface along any ray
into a closed solid is a face turned towards the ray's origin), but costs the rasterizer
as much as a visible face. These tests say which faces a pass may skip.
"""
from __future__ import annotations

import numpy as np

from scenerender.world.transforms import box_corners


def hidden_side(winding: int) -> str | None:
    """The faces turned away from any outside viewpoint: "back" for a counter-clockwise
    winding (+1), "front" for clockwise (-1), None for an open surface (0)."""
    return None if winding == 0 else ("back" if winding > 0 else "front")


def hidden_from_eye(winding: int, bounds: np.ndarray, eye: np.ndarray, forward: np.ndarray, near: float,
                    projection: np.ndarray) -> str | None:
    """hidden_side for a perspective viewpoint at ``eye`` looking along ``forward``, or
    None when the viewpoint might see the surface from inside, that is unless one of
    these holds:
    - the surface's bounds (2, 3) lie wholly beyond the near plane;
    - the bounds are farther from the eye than the near plane's corners (so the near
      plane cannot cut into the surface, and the eye is outside it)."""
    if winding == 0:
        return None
    depths = (box_corners(bounds) - eye) @ forward
    reach = near * float(np.sqrt(1.0 + 1.0 / projection[0, 0] ** 2 + 1.0 / projection[1, 1] ** 2))
    outside_by = np.linalg.norm(np.maximum(np.maximum(bounds[0] - eye, eye - bounds[1]), 0.0))
    if depths.min() <= near and outside_by <= reach:
        return None
    return hidden_side(winding)
