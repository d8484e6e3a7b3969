"""Environment images (equirectangular, linear radiance, Radiance .hdr)."""
from __future__ import annotations

import numpy as np

from .common import ENVIRONMENTS, mix, smoothstep


def soft_box(d: np.ndarray, centre, half_size: tuple, softness: float = 0.08) -> np.ndarray:
    """0..1: a rectangular light panel seen from the origin, centred on direction ``centre``,
    ``half_size`` (tangent of its half angles, across and up), with soft edges."""
    forward = np.asarray(centre, float) / np.linalg.norm(centre)
    across = np.cross(forward, [0.0, 1.0, 0.0])
    across /= np.linalg.norm(across)
    up = np.cross(across, forward)
    depth = np.sum(d * forward, axis=-1)
    ahead = np.maximum(depth, 1e-6)
    x = np.abs(np.sum(d * across, axis=-1) / ahead) / half_size[0]
    y = np.abs(np.sum(d * up, axis=-1) / ahead) / half_size[1]
    inside = (1.0 - smoothstep(1.0 - softness, 1.0 + softness, x)) * (1.0 - smoothstep(1.0 - softness, 1.0 + softness, y))
    return np.where(depth > 0.0, inside, 0.0)


def studio_environment(width: int = 256) -> np.ndarray:
    """(W / 2, W, 3) linear radiance: a dim studio (warm grey floor, darker ceiling) with a
    large warm key panel front-left above, a cool strip light behind right and a small
    fill panel low on the right. Lights a pbr scene as a product photograph is lit."""
    from scenerender.world.environment_light import equirect_directions

    d = equirect_directions(width // 2, width)
    y = d[..., 1]
    room = np.where((y > 0)[..., None], mix(np.array([0.10, 0.10, 0.11]), np.array([0.03, 0.03, 0.035]),
                                            np.clip(y, 0, 1)),
                    mix(np.array([0.12, 0.105, 0.09]), np.array([0.05, 0.045, 0.04]), np.clip(-y, 0, 1)))
    key = soft_box(d, (-0.6, 0.75, 0.55), (0.55, 0.4))[..., None] * np.array([7.0, 6.3, 5.4])
    rim = soft_box(d, (0.7, 0.35, -0.65), (0.12, 0.9))[..., None] * np.array([3.2, 3.8, 4.6])
    fill = soft_box(d, (0.9, 0.1, 0.4), (0.3, 0.25))[..., None] * np.array([0.9, 0.95, 1.0])
    return (room + key + rim + fill).astype(np.float32)


def write_environments() -> None:
    from scenerender.world.environment_files import write_hdr

    ENVIRONMENTS.mkdir(exist_ok=True)
    write_hdr(ENVIRONMENTS / "studio.hdr", studio_environment())
