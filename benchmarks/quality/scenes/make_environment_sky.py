"""Write environment_sky.hdr, the light of benchmarks/quality/scenes/environment.yaml: a
512 x 256 equirectangular sky, made here from formulas (no photographed asset).

    python benchmarks/quality/scenes/make_environment_sky.py

Linear radiance, by direction d (y up; the image's centre column looks down -Z):

- sky (y > 0): from the horizon's pale blue-white (0.60, 0.66, 0.75) to the zenith's deeper
  blue (0.16, 0.30, 0.62), mixed by sqrt(y);
- ground (y < 0): a dark warm brown, (0.10, 0.085, 0.065) at the horizon to half that at
  the nadir; sky and ground blend over 2 degrees about the horizon;
- sun: a warm disc (1.0, 0.86, 0.62) x 400, 2.5 degrees in radius with a limb darkened
  to 60 % at its edge (its rim anti-aliased over a tenth of a degree), 35 degrees up and
  40 degrees to the right of the camera's back (azimuth measured from +Z towards +X), plus
  an aureole (1.0, 0.85, 0.6) x 2.5 exp(-angle / 4 degrees).

Each texel is the mean of 4 x 4 points over it, so the disc's edge is area-weighted. On a
surface facing it the sun (within 3 degrees) gives 1.6 times the irradiance, in luminance,
of all the rest.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from scenerender.world.environment_light import equirect_directions
from scenerender.world.environment_files import write_hdr

WIDTH, HEIGHT = 512, 256
SUPERSAMPLE = 4
HORIZON = np.array([0.60, 0.66, 0.75])
ZENITH = np.array([0.16, 0.30, 0.62])
GROUND = np.array([0.10, 0.085, 0.065])
SUN_COLOR, SUN_RADIANCE = np.array([1.0, 0.86, 0.62]), 400.0
SUN_RADIUS = math.radians(2.5)
SUN_ELEVATION, SUN_AZIMUTH = math.radians(35.0), math.radians(40.0)
AUREOLE_COLOR, AUREOLE_RADIANCE, AUREOLE_WIDTH = np.array([1.0, 0.85, 0.6]), 2.5, math.radians(4.0)
HORIZON_BLEND = math.radians(2.0)


def sun_direction() -> np.ndarray:
    return np.array([math.cos(SUN_ELEVATION) * math.sin(SUN_AZIMUTH), math.sin(SUN_ELEVATION),
                     math.cos(SUN_ELEVATION) * math.cos(SUN_AZIMUTH)])


def radiance(d: np.ndarray) -> np.ndarray:
    """(..., 3) the sky's linear radiance towards unit directions d (..., 3)."""
    y = d[..., 1:2]
    sky = HORIZON + (ZENITH - HORIZON) * np.sqrt(np.maximum(y, 0.0))
    ground = GROUND * (1.0 - 0.5 * np.maximum(-y, 0.0))
    blend = np.clip(0.5 + np.arcsin(np.clip(y, -1.0, 1.0)) / HORIZON_BLEND, 0.0, 1.0)
    angle = np.arccos(np.clip(d @ sun_direction(), -1.0, 1.0))[..., None]
    limb = 1.0 - 0.4 * (angle / SUN_RADIUS) ** 2
    edge = np.clip((SUN_RADIUS - angle) / math.radians(0.1) + 0.5, 0.0, 1.0)
    sun = SUN_COLOR * SUN_RADIANCE * limb * edge
    aureole = AUREOLE_COLOR * AUREOLE_RADIANCE * np.exp(-angle / AUREOLE_WIDTH)
    return ground + (sky - ground) * blend + sun + aureole


def sky_image() -> np.ndarray:
    """(HEIGHT, WIDTH, 3) float32: each texel the mean of SUPERSAMPLE^2 points over it."""
    fine = radiance(equirect_directions(HEIGHT * SUPERSAMPLE, WIDTH * SUPERSAMPLE))
    return fine.reshape(HEIGHT, SUPERSAMPLE, WIDTH, SUPERSAMPLE, 3).mean(axis=(1, 3)).astype(np.float32)


def main() -> None:
    path = Path(__file__).with_name("environment_sky.hdr")
    write_hdr(path, sky_image())
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
