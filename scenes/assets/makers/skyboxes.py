"""The cube-map skyboxes (skybox/): a day sky and a dusk sky."""
from __future__ import annotations

import math

import numpy as np

from .common import mix, SKYBOX, smoothstep, srgb
from .images import save_image
from .noise import fbm


CUBE_FACES = ("posx", "negx", "posy", "negy", "posz", "negz")


def cube_face_directions(face: str, size: int) -> np.ndarray:
    """Unit view direction of every texel of one cube-map face, inverting the OpenGL
    face-selection table (sc, tc per major axis; texel row 0 is t = 0). Sampling the
    finished cube map with a world direction d therefore returns sky(d), and neighbouring
    faces agree along their shared edges."""
    s = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    sc, tc = np.meshgrid(s, s)            # sc along columns, tc down the rows
    one = np.ones_like(sc)
    d = {
        "posx": (one, -tc, -sc),
        "negx": (-one, -tc, sc),
        "posy": (sc, one, tc),
        "negy": (sc, -one, -tc),
        "posz": (sc, -tc, one),
        "negz": (-sc, -tc, -one),
    }[face]
    d = np.stack(d, axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def cloud_layer(d: np.ndarray, seed: int, scale: float, octaves: int = 5) -> np.ndarray:
    """fbm painted on a flat cloud deck above the viewer (perspective squeezes it towards
    the horizon); zero below the horizon."""
    up = np.clip(d[..., 1], 0.0, None)
    deck = d[..., [0, 2]] / (up[..., None] + 0.12) * scale
    return fbm(deck + 50.0, seed, octaves) * smoothstep(0.0, 0.12, up)


def day_sky(d: np.ndarray) -> np.ndarray:
    """Clear day: blue gradient, sun glow, soft cumulus, pale haze along the horizon."""
    y = d[..., 1]
    sun = np.array(DAY_SUN_DIRECTION) / np.linalg.norm(DAY_SUN_DIRECTION)
    up = np.clip(y, 0.0, 1.0)
    sky = mix(srgb("#b7d3ea"), srgb("#2d6bc4"), up ** 0.55)
    ground = mix(srgb("#aeb9bd"), srgb("#5f6d5c"), smoothstep(0.0, 0.35, -y))
    colour = np.where((y >= 0)[..., None], sky, ground)
    cos_sun = np.clip(np.sum(d * sun, axis=-1), -1.0, 1.0)
    glow = 0.45 * np.exp((cos_sun - 1.0) * 12.0) + 0.5 * np.exp((cos_sun - 1.0) * 300.0)
    colour = colour + glow[..., None] * srgb("#fff1cf")
    # Cumulus: soft-edged puffs, shaded greyer where the cloud is thick.
    n = cloud_layer(d, seed=201, scale=0.8)
    cover = smoothstep(0.16, 0.5, n) * smoothstep(0.04, 0.3, y)   # few clouds, none in the haze
    cloud = mix(srgb("#ffffff"), srgb("#bcc4cf"), smoothstep(0.35, 0.8, n))
    cloud = cloud + (0.25 * np.exp((cos_sun - 1.0) * 6.0))[..., None]
    colour = mix(colour, cloud, 0.9 * cover)
    haze = np.exp(-np.abs(y) * 10.0)
    colour = mix(colour, srgb("#dbe6ee"), 0.65 * haze)
    disk = smoothstep(math.cos(math.radians(1.6)), math.cos(math.radians(1.1)), cos_sun)
    return np.clip(mix(colour, srgb("#fffbef"), disk), 0.0, 1.0)


def dusk_sky(d: np.ndarray) -> np.ndarray:
    """Overcast dusk: low grey cloud deck, a dim orange glow where the sun set, murky
    ground haze (suits fog)."""
    y = d[..., 1]
    sunset = np.array(DUSK_GLOW_DIRECTION) / np.linalg.norm(DUSK_GLOW_DIRECTION)
    towards = np.clip(np.sum(d[..., [0, 2]] * sunset[[0, 2]], axis=-1), 0.0, 1.0) ** 3
    up = np.clip(y, 0.0, 1.0)
    sky = mix(srgb("#8f7565"), srgb("#3a3d47"), up ** 0.45)
    glow = towards * np.exp(-np.abs(y) * 5.0)
    sky = sky + glow[..., None] * (srgb("#c0652c") - 0.3)
    n = cloud_layer(d, seed=301, scale=2.2, octaves=6)
    deck = mix(srgb("#57545a"), srgb("#7a6e6a"), smoothstep(-0.3, 0.5, n))
    deck = deck + (0.35 * glow)[..., None] * srgb("#d07a40")
    colour = mix(sky, deck, 0.75 * smoothstep(-0.35, 0.25, n) * smoothstep(0.0, 0.1, up))
    ground = mix(srgb("#6e6360"), srgb("#2a2727"), smoothstep(0.0, 0.3, -y))
    colour = np.where((y >= 0)[..., None], colour, ground)
    haze = np.exp(-np.abs(y) * 9.0)
    return np.clip(mix(colour, srgb("#8a7c74") + 0.12 * towards[..., None], 0.6 * haze), 0.0, 1.0)


# Where the sun sits (direction from the viewer). A directional light that matches the day
# skybox travels the opposite way: direction [0.45, -0.55, 0.70].
DAY_SUN_DIRECTION = (-0.45, 0.55, -0.70)
DUSK_GLOW_DIRECTION = (0.8, 0.0, -0.6)


def write_skyboxes() -> None:
    for folder, sky, suffix in (("day", day_sky, ".png"), ("dusk", dusk_sky, ".jpg")):
        for face in CUBE_FACES:
            save_image(sky(cube_face_directions(face, 256)), SKYBOX / folder / (face + suffix))
