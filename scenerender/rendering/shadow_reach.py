"""Where on a flat surface the scene's shadows can fall, as a rectangle of the screen.

The sun's lookup (shaders/lighting/shadows.glsl) is about 40 % of the benchmark scene's
frame, and llvmpipe pays it for every fragment it shades, also where no caster's shadow can
reach. A shadow map holds nothing but its casters: a texel no caster covers keeps the
cleared far depth, and every filtered tap there returns exactly 1, as does a point outside
the view's tile. So a surface whose lookup touches no caster's texel is lit to the bit by
the program without shadows (x * 1.0 is x). For a flat receiver under orthographic views
(directional lights) the points whose lookups can touch a caster lie in a parallelogram of
its plane: the casters' bounds projected into the light's view, widened by the filter's
reach, and carried back along the light onto the plane. Its corners projected into the
camera bound the screen rectangle that keeps the shadowed program; the rest of the
surface is drawn without shadows (passes/forward.py)."""
from __future__ import annotations

import numpy as np

# Texels around the casters' footprint in the map that a lookup may still read: the pcf
# filter's taps (half its width) and their bilinear neighbours, the normal offset (at most
# 1.5 texels) and one to spare.
REACH_TEXELS = 4
# Pixels around the rectangle: a pixel's footprint points lie within half a pixel of its
# centre, and the corners' projection is rounded outwards.
REACH_PIXELS = 2


def shadowed_rectangle(views: list, caster_bounds: np.ndarray, axis: int, plane: float, camera,
                       size: tuple, pcf: int):
    """(x0, y0, x1, y1) in window pixels (lower-left origin, x1 and y1 exclusive) outside
    which no shadow of ``views`` falls on the plane ``world[axis] == plane``; an empty one
    where none falls on it at all; None where that cannot be told (a view that is not
    orthographic, a light along the plane, a corner behind the camera).

    views: (ShadowView, tile size in texels) of every shadowed light; caster_bounds:
    (n, 2, 3) world bounds of the casters; camera: CameraState; pcf: the widest filter."""
    width, height = size
    if len(caster_bounds) == 0:
        return (0, 0, 0, 0)
    lo, hi = caster_bounds[:, 0], caster_bounds[:, 1]
    corners = np.stack([np.where(np.array([(k >> j) & 1 for j in range(3)], dtype=bool), hi, lo)
                        for k in range(8)], axis=1).reshape(-1, 3)
    points = []
    for view, texels in views:
        to_clip = view.projection @ view.view
        if view.radial or np.any(to_clip[3, :3] != 0.0) or to_clip[3, 3] != 1.0:
            return None
        xy = corners @ to_clip[:2, :3].T + to_clip[:2, 3]
        reach = (REACH_TEXELS + 0.5 * pcf) * 2.0 / texels
        (x0, y0), (x1, y1) = xy.min(axis=0) - reach, xy.max(axis=0) + reach
        system = np.zeros((3, 3))
        system[:2] = to_clip[:2, :3]
        system[2, axis] = 1.0
        if abs(np.linalg.det(system)) < 1e-9 * np.abs(system).max() ** 3:
            return None
        targets = np.array([[x - to_clip[0, 3], y - to_clip[1, 3], plane] for x in (x0, x1) for y in (y0, y1)])
        points.append(np.linalg.solve(system, targets.T).T)
    relative = np.concatenate(points) - np.asarray(camera.position, dtype=np.float64)
    clip = relative @ camera.view_proj_relative()[:, :3].T + camera.view_proj_relative()[:, 3]
    if np.any(clip[:, 3] <= 1e-6 * np.abs(clip[:, :3]).max()):
        return None
    ndc = clip[:, :2] / clip[:, 3:4]
    pixels = (ndc * 0.5 + 0.5) * np.array([width, height])
    x0, y0 = np.floor(pixels.min(axis=0)).astype(int) - REACH_PIXELS
    x1, y1 = np.ceil(pixels.max(axis=0)).astype(int) + REACH_PIXELS
    x0, x1 = min(max(x0, 0), width), min(max(x1, 0), width)
    y0, y1 = min(max(y0, 0), height), min(max(y1, 0), height)
    if x0 >= x1 or y0 >= y1:
        return (0, 0, 0, 0)
    return (int(x0), int(y0), int(x1), int(y1))


def around(rectangle: tuple, size: tuple) -> list:
    """The up to four rectangles that cover ``size`` less ``rectangle``, without overlap."""
    width, height = size
    x0, y0, x1, y1 = rectangle
    if x0 >= x1 or y0 >= y1:
        return [(0, 0, width, height)]
    pieces = [(0, 0, width, y0), (0, y1, width, height), (0, y0, x0, y1), (x1, y0, width, y1)]
    return [p for p in pieces if p[2] > p[0] and p[3] > p[1]]
