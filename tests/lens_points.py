"""The lens's test scene, shared by tests/test_depth_of_field.py and
benchmarks/quality/film_exact.py: tiny unlit white spheres in front of a pinhole camera,
one on each of three columns of the middle row, and what the thin lens says their discs
should be. Pure text and NumPy: nothing here renders."""
from __future__ import annotations

import math

import numpy as np

WIDTH, HEIGHT, FOV, SENSOR = 160, 120, 40.0, 36.0
# the focal length in pixels, and where three points sit across the image
FOCAL_PX = WIDTH / 2 / (math.tan(math.radians(FOV) / 2) * WIDTH / HEIGHT)
COLUMNS = (36, 80, 124)


def points_scene(depths, aperture, focus, render_keys: str = "", radius_px: float = 0.5) -> str:
    """Tiny unlit white spheres (``radius_px`` in radius) at ``depths`` in front of a camera
    at the origin looking down -Z, one at each of COLUMNS on the middle row; a thin lens of
    ``aperture`` focused at ``focus`` unless aperture is None. ``render_keys``: more of the
    render mapping, ``", film_samples: 16"``."""
    objects = []
    for column, depth in zip(COLUMNS, depths):
        x = (column + 0.5 - WIDTH / 2) / FOCAL_PX * depth
        objects.append(f"  - {{mesh: {{primitive: sphere, radius: {radius_px * depth / FOCAL_PX:.6g}}}, "
                       f"position: [{x:.6g}, 0, {-depth:.6g}], material: {{diffuse: [1, 1, 1], unlit: true}}}}")
    lens = f", aperture: {aperture}, focus_distance: {focus}" if aperture is not None else ""
    return (f"render: {{size: [{WIDTH}, {HEIGHT}], samples: 4, background: [0, 0, 0]{render_keys}}}\n"
            f"camera: {{position: [0, 0, 0], target: [0, 0, -1], fov: {FOV}, near: 0.01, far: 10{lens}}}\n"
            "lights: []\nobjects:\n" + "\n".join(objects) + "\n")


def thin_lens_coc_px(depth: float, focus: float, aperture: float) -> float:
    """The circle of confusion's diameter in pixels, by the thin-lens equation: the
    focal length f from 1/f = 1/v + 1/focus (v: the image distance at which the sensor
    spans the field of view), the aperture f / N, c = A f |depth - focus| / (depth (focus - f))."""
    image_distance = SENSOR * 1e-3 * FOCAL_PX / WIDTH
    f = image_distance * focus / (image_distance + focus)
    coc = (f / aperture) * f * abs(depth - focus) / (depth * (focus - f))
    return coc / (SENSOR * 1e-3) * WIDTH


def disc(light: np.ndarray, column: int) -> tuple:
    """The centroid (x, y) and the mean squared distance from it (px^2) of the light
    ((H, W) float) in the 40 px band around ``column``."""
    band = light[:, column - 20:column + 20]
    y, x = np.mgrid[:band.shape[0], :band.shape[1]]
    total = band.sum()
    cx, cy = (band * x).sum() / total, (band * y).sum() / total
    return cx, cy, float((band * ((x - cx) ** 2 + (y - cy) ** 2)).sum() / total)
