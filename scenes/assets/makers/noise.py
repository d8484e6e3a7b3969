"""Seeded gradient (Perlin-style) noise and fractal sums of it; a period makes it tile seamlessly."""
from __future__ import annotations

import itertools
import math

import numpy as np


def _fade(t):
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def gradient_noise(coords, seed: int, period=None) -> np.ndarray:
    """Gradient noise at `coords` (shape (..., D), in lattice cells), roughly in [-1, 1].

    With `period` (cells per axis, at most 256) the noise repeats exactly, which is what
    makes textures tile. The lattice hash is a seeded permutation, so results only depend
    on the seed."""
    coords = np.asarray(coords, dtype=float)
    dim = coords.shape[-1]
    gen = np.random.default_rng(seed)
    perm = gen.permutation(256)
    grads = gen.normal(size=(256, dim))
    grads /= np.linalg.norm(grads, axis=1, keepdims=True)
    base = np.floor(coords).astype(np.int64)
    frac = coords - base
    fade = _fade(frac)
    total = np.zeros(coords.shape[:-1])
    for corner in itertools.product((0, 1), repeat=dim):
        lattice = base + np.array(corner)
        if period is not None:
            lattice = lattice % np.asarray(period, dtype=np.int64)
        h = np.zeros(coords.shape[:-1], dtype=np.int64)
        for axis in range(dim):
            h = perm[(h + lattice[..., axis]) % 256]
        weight = np.ones(coords.shape[:-1])
        for axis in range(dim):
            weight = weight * (fade[..., axis] if corner[axis] else 1.0 - fade[..., axis])
        total += weight * np.sum(grads[h] * (frac - np.array(corner)), axis=-1)
    return total * math.sqrt(2.0)


def fbm(coords, seed: int, octaves: int = 5, gain: float = 0.5, period=None) -> np.ndarray:
    """Fractal sum of noise octaves (each twice the frequency of the last), about [-1, 1]."""
    coords = np.asarray(coords, dtype=float)
    total = np.zeros(coords.shape[:-1])
    amplitude, norm = 1.0, 0.0
    for octave in range(octaves):
        scale = 2 ** octave
        octave_period = None if period is None else np.asarray(period, dtype=np.int64) * scale
        total += amplitude * gradient_noise(coords * scale, seed + 101 * octave, octave_period)
        norm += amplitude
        amplitude *= gain
    return total / norm


def texture_uv(width: int, height: int):
    """Pixel-centre (u, v) grids of shape (height, width); v = 1 on the top row, as an OBJ
    texture coordinate sees the image."""
    u = (np.arange(width) + 0.5) / width
    v = 1.0 - (np.arange(height) + 0.5) / height
    return np.meshgrid(u, v)


def tiling_fbm(width: int, height: int, cells, seed: int, octaves: int = 5, gain: float = 0.5):
    """fbm over a whole image that tiles seamlessly: `cells` = (across, down) lattice cells."""
    u, v = texture_uv(width, height)
    cu, cv = (cells, cells) if np.isscalar(cells) else cells
    coords = np.stack([u * cu, v * cv], axis=-1)
    return fbm(coords, seed, octaves, gain, period=(cu, cv))


def wrapped_distance(width: int, height: int, cx: float, cy: float):
    """Per-pixel (dx, dy) from a point in pixels, wrapped so that shapes near an edge
    continue on the opposite edge (keeps stamped textures tileable)."""
    x = np.arange(width) + 0.5
    y = np.arange(height) + 0.5
    dx = (x[None, :] - cx + width / 2) % width - width / 2
    dy = (y[:, None] - cy + height / 2) % height - height / 2
    return np.broadcast_to(dx, (height, width)), np.broadcast_to(dy, (height, width))


def normal_map_from_height(height: np.ndarray, strength: float) -> np.ndarray:
    """Tangent-space normal map (OpenGL convention: red = +U, green = +V = up in the image)
    from a tiling height field; `strength` scales slopes measured in height per pixel."""
    dh_du = (np.roll(height, -1, axis=1) - np.roll(height, 1, axis=1)) * 0.5
    dh_dv = (np.roll(height, 1, axis=0) - np.roll(height, -1, axis=0)) * 0.5  # row above = +v
    n = np.stack([-strength * dh_du, -strength * dh_dv, np.ones_like(height)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return n * 0.5 + 0.5
