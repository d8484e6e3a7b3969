"""Error of a GPU frame with render.indirect against a path-traced reference, by region of
the Cornell box (benchmarks/quality/scenes/cornell_box.yaml).

Regions, each over pixels inside one surface (the reference's object map eroded by one
pixel, so no pixel mixes two surfaces or an edge's anti-aliasing):
- ``ceiling``: lit only by bounced light;
- ``floor_under_light``: the floor where the direct-only reference is within 20 % of its
  brightest; ``floor_in_shadow``: where it is below a quarter of that (the boxes' shadows
  and the corners);
- ``red_wall``, ``green_wall``, ``back_wall``;
- ``box_sides``: the boxes' faces the lamp does not see (|normal y| < 0.5);
- ``tall_box_front`` (turned 17 degrees towards the green wall) and ``short_box_front``
  (17 degrees towards the red one): the side faces the camera sees, where the coloured
  walls' light bleeds.

A region's error is its mean GPU luminance over the reference's, less 1. The whole image's
relative RMSE is sqrt(mean((gpu - ref)^2)) / mean(ref) over every pixel and channel. The
colour bleeding: a face's red over green (its mean red channel over its mean green) against
the reference's.
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

# the scene's objects, in its order
OBJECTS = ("floor", "ceiling", "back_wall", "front_wall", "left_wall", "right_wall", "tall_box", "short_box")


def bounce_regions(objects: np.ndarray, normals: np.ndarray, direct: np.ndarray) -> dict:
    """name -> (H, W) bool mask. ``objects``: (H, W) int, the object index each pixel shows
    (-1 none); ``normals``: (H, W, 3) world-space unit normals; ``direct``: (H, W, 3) the
    direct-only reference."""
    inside = {name: ndimage.binary_erosion(objects == index) for index, name in enumerate(OBJECTS)}
    floor_direct = direct.mean(axis=2)
    brightest = np.percentile(floor_direct[inside["floor"]], 99)
    boxes = inside["tall_box"] | inside["short_box"]
    side = np.abs(normals[..., 1]) < 0.5
    tall_axes = _box_axes(17.0)
    short_axes = _box_axes(-17.0)
    return {
        "ceiling": inside["ceiling"],
        "floor_under_light": inside["floor"] & (floor_direct > 0.8 * brightest),
        "floor_in_shadow": inside["floor"] & (floor_direct < 0.25 * brightest),
        "red_wall": inside["left_wall"],
        "green_wall": inside["right_wall"],
        "back_wall": inside["back_wall"],
        "box_sides": boxes & side,
        "tall_box_front": inside["tall_box"] & (normals @ tall_axes[2] > 0.9),
        "short_box_front": inside["short_box"] & (normals @ short_axes[2] > 0.9),
    }


def outdoor_regions(objects: np.ndarray, normals: np.ndarray, direct: np.ndarray, boxes: tuple) -> dict:
    """name -> (H, W) bool mask of a ground (object 0) and boxes (the indices ``boxes``)
    under a sky and a sun (benchmarks/quality/scenes/outdoor_bounce.yaml); ``objects``,
    ``normals`` and ``direct`` as for bounce_regions:

    - ``vertical_faces``: the boxes' faces (|normal y| < 0.5) the camera sees;
    - ``faces_in_shadow``: those the sun does not reach (direct light below 40 % of the
      brightest vertical face's);
    - ``ground_in_shadow``: the ground where the direct light is below half its median;
    - ``ground_beside``: the ground within 6 pixels of a box, out of the shadows."""
    light = direct.mean(axis=2)
    ground = ndimage.binary_erosion(objects == 0)
    solid = np.isin(objects, boxes)
    vertical = ndimage.binary_erosion(solid) & (np.abs(normals[..., 1]) < 0.5)
    shadow = ground & (light < 0.5 * np.median(light[ground]))
    return {"vertical_faces": vertical,
            "faces_in_shadow": vertical & (light < 0.4 * np.percentile(light[vertical], 99)),
            "ground_in_shadow": shadow,
            "ground_beside": ground & ~shadow & ndimage.binary_dilation(solid, iterations=6)}


def _box_axes(yaw_degrees: float) -> np.ndarray:
    """(3, 3): a box's x, y, z axes (rows) turned ``yaw_degrees`` about y."""
    angle = np.radians(yaw_degrees)
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])


def region_errors(gpu: np.ndarray, reference: np.ndarray, regions: dict) -> dict:
    """name -> GPU mean luminance / reference mean luminance - 1, for each region with pixels."""
    found = {}
    for name, mask in regions.items():
        if mask.sum() >= 4:
            found[name] = float(gpu[mask].mean() / reference[mask].mean() - 1.0)
    return found


def relative_rmse(gpu: np.ndarray, reference: np.ndarray) -> float:
    return float(np.sqrt(((gpu - reference) ** 2).mean()) / reference.mean())


def red_over_green(image: np.ndarray, mask: np.ndarray) -> float:
    """The face's mean red over its mean green."""
    return float(image[mask][:, 0].mean() / image[mask][:, 1].mean())
