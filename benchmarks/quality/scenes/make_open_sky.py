"""Write open_sky.hdr, the light of benchmarks/quality/scenes/sky_contact.yaml: the sky of
make_contact_sky.py without its bright patch (a sky gradient over a dark ground, no sun),
256 x 128 equirectangular, made here from formulas (no photographed asset).

    python benchmarks/quality/scenes/make_open_sky.py
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from make_contact_sky import GROUND, HEIGHT, HORIZON, HORIZON_BLEND, SUPERSAMPLE, WIDTH, ZENITH
from scenerender.world.environment_files import write_hdr
from scenerender.world.environment_light import equirect_directions


def radiance(d: np.ndarray) -> np.ndarray:
    """(..., 3) the sky's linear radiance towards unit directions d (..., 3): the contact
    sky's gradient and ground, no patch."""
    y = d[..., 1:2]
    sky = HORIZON + (ZENITH - HORIZON) * np.sqrt(np.maximum(y, 0.0))
    blend = np.clip(0.5 + np.arcsin(np.clip(y, -1.0, 1.0)) / HORIZON_BLEND, 0.0, 1.0)
    return GROUND + (sky - GROUND) * blend


def sky_image(width: int = WIDTH, height: int = HEIGHT) -> np.ndarray:
    """(height, width, 3) float32: each texel the mean of SUPERSAMPLE^2 points over it."""
    fine = radiance(equirect_directions(height * SUPERSAMPLE, width * SUPERSAMPLE))
    return fine.reshape(height, SUPERSAMPLE, width, SUPERSAMPLE, 3).mean(axis=(1, 3)).astype(np.float32)


if __name__ == "__main__":
    target = Path(__file__).resolve().parent / "open_sky.hdr"
    write_hdr(target, sky_image())
    print(f"wrote {target}")
