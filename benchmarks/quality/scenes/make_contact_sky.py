"""Write contact_sky.hdr, the light of benchmarks/quality/scenes/environment_contact.yaml: a
256 x 128 equirectangular sky, made here from formulas (no photographed asset).

    python benchmarks/quality/scenes/make_contact_sky.py

Linear radiance, by direction d (y up; the image's centre column looks down -Z):

- sky (y > 0): from the horizon's pale (0.75, 0.78, 0.82) to the zenith's blue
  (0.35, 0.48, 0.75), mixed by sqrt(y);
- ground (y < 0): a dark grey 0.08, blending into the sky over 2 degrees about the horizon;
- patch: a bright disc of radiance 12 (warm white), 10 degrees in radius (20 wide), 45
  degrees up towards +X (to the camera's right), its rim anti-aliased over half a degree.

On a surface facing up, the patch gives about as much irradiance as the rest of the sky,
so its shadow is plain where the sky's own occlusion is soft. Each texel is the mean of
4 x 4 points over it.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from scenerender.world.environment_light import equirect_directions
from scenerender.world.environment_files import write_hdr

WIDTH, HEIGHT = 256, 128
SUPERSAMPLE = 4
HORIZON, ZENITH = np.array([0.75, 0.78, 0.82]), np.array([0.35, 0.48, 0.75])
GROUND = np.array([0.08, 0.08, 0.08])
PATCH_COLOR, PATCH_RADIANCE = np.array([1.0, 0.95, 0.88]), 12.0
PATCH_RADIUS = math.radians(10.0)
PATCH_ELEVATION = math.radians(45.0)
HORIZON_BLEND = math.radians(2.0)


def patch_direction() -> np.ndarray:
    """(3,) unit direction towards the patch's centre: 45 degrees up towards +X."""
    return np.array([math.cos(PATCH_ELEVATION), math.sin(PATCH_ELEVATION), 0.0])


def open_sky_radiance(d: np.ndarray) -> np.ndarray:
    """(..., 3) the gradient and the ground alone, no patch, towards unit directions d (..., 3)."""
    y = d[..., 1:2]
    sky = HORIZON + (ZENITH - HORIZON) * np.sqrt(np.maximum(y, 0.0))
    blend = np.clip(0.5 + np.arcsin(np.clip(y, -1.0, 1.0)) / HORIZON_BLEND, 0.0, 1.0)
    return GROUND + (sky - GROUND) * blend


def radiance(d: np.ndarray) -> np.ndarray:
    """(..., 3) the sky's linear radiance towards unit directions d (..., 3)."""
    angle = np.arccos(np.clip(d @ patch_direction(), -1.0, 1.0))[..., None]
    inside = np.clip((PATCH_RADIUS - angle) / math.radians(0.5) + 0.5, 0.0, 1.0)
    return open_sky_radiance(d) + PATCH_COLOR * PATCH_RADIANCE * inside


def sky_image(width: int = WIDTH, height: int = HEIGHT, radiance_towards=radiance) -> np.ndarray:
    """(height, width, 3) float32: each texel the mean of SUPERSAMPLE^2 points over it of
    ``radiance_towards`` (directions -> radiance)."""
    fine = radiance_towards(equirect_directions(height * SUPERSAMPLE, width * SUPERSAMPLE))
    return fine.reshape(height, SUPERSAMPLE, width, SUPERSAMPLE, 3).mean(axis=(1, 3)).astype(np.float32)


if __name__ == "__main__":
    target = Path(__file__).resolve().parent / "contact_sky.hdr"
    write_hdr(target, sky_image())
    print(f"wrote {target}")
