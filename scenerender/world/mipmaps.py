"""Mipmap levels of a texture, made on the CPU. No GL.

Each level is the one above shrunk to half its size (rounded down, at least 1), every
output texel the area-weighted mean of the texels it covers: the 2 x 2 box filter where a
side is even, a three-texel window where it is odd. Colour maps are averaged in linear
light (sRGB decoded, then encoded back, exactly rounded), as a GPU filters an sRGB
texture; other maps (normals, specular) as stored.

Made here rather than by ``glGenerateMipmap`` for two reasons: the levels are the same
bytes on every driver (a GPU's and llvmpipe's frames sample identical textures), and Mesa
llvmpipe compiles a blit program for each texture format on its first mipmap build, which
cost 100-150 ms of a run's start-up (measured: the first 256 x 256 build 145 ms, the next
0.9 ms).
"""
from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from scenerender.colorspace import srgb_decode
from scenerender.machine import available_cores

# 8-bit sRGB code -> linear light; and the linear values halfway between codes, so that
# the encoded code of a linear value is how many of them lie at or below it (exact
# rounding). _GRID_CODES[k] is that count at k / _GRID: the edges are never closer than
# 1 / (255 * 12.92) apart, more than a grid step, so a value's code is its grid cell's
# count plus one at most.
_DECODE = srgb_decode(np.arange(256) / 255.0).astype(np.float32)
_ENCODE_EDGES = srgb_decode((np.arange(255) + 0.5) / 255.0).astype(np.float32)
_GRID = 4096
_GRID_CODES = np.searchsorted(_ENCODE_EDGES, np.arange(_GRID + 1, dtype=np.float32) / _GRID, side="right")
_EDGES_PADDED = np.append(_ENCODE_EDGES, np.float32(np.inf))


def mip_chain(pixels: np.ndarray, srgb: bool) -> list[np.ndarray]:
    """Every level below ``pixels`` (H, W, 4) uint8 down to 1 x 1, each (h, w, 4) uint8.

    srgb: the first three channels are sRGB-encoded colour (alpha is always linear). Each
    level is averaged from the one above before rounding (float32, linear), and rounded
    once, while the level above has at most EXACT_LEVEL_TEXELS texels; a larger level is
    averaged from its own 8-bit values, so that no float copy of a large level is ever held
    (one more rounding: at most half a level). Large levels are split into bands of rows
    worked on by one thread per core. Memory: the levels themselves (a third of the
    image), plus float32 bands of _BAND_ROWS rows."""
    levels = []
    current = pixels
    while current.shape[0] > 1 or current.shape[1] > 1:
        below_texels = max(1, current.shape[0] // 2) * max(1, current.shape[1] // 2)
        keep_linear = below_texels <= EXACT_LEVEL_TEXELS
        linear, encoded = _level_below(current, srgb, keep_linear)
        levels.append(encoded)
        current = linear if keep_linear else encoded
    return levels


# A level of more texels than this is not kept in float32 to make the next one (2048 x 2048:
# 64 MiB of float32 RGBA), so a 12,000 x 12,000 texture's chain needs no 550 MiB float level.
EXACT_LEVEL_TEXELS = 2048 * 2048

# rows above which a level is made in bands, one thread per core (NumPy frees the GIL)
_BAND_ROWS = 256


def _level_below(values: np.ndarray, srgb: bool, keep_linear: bool = True) -> tuple[np.ndarray | None, np.ndarray]:
    """(linear float32 or None when not ``keep_linear``, encoded uint8) of the level below
    ``values`` (uint8 for the image itself or a large level, else the linear level above)."""
    height, width = values.shape[:2]
    if height > _BAND_ROWS and height % 2 == 0 and width % 2 == 0:
        bands = [values[start:start + _BAND_ROWS] for start in range(0, height, _BAND_ROWS)]
        with ThreadPoolExecutor(max_workers=available_cores()) as pool:
            done = list(pool.map(lambda band: _level_below(band, srgb, keep_linear), bands))
        linear = np.concatenate([d[0] for d in done]) if keep_linear else None
        return linear, np.concatenate([d[1] for d in done])
    linear = _to_linear(values, srgb) if values.dtype == np.uint8 else values
    if height % 2 == 0 and width % 2 == 0:
        below = (linear[0::2, 0::2] + linear[1::2, 0::2] + linear[0::2, 1::2] + linear[1::2, 1::2]) * np.float32(0.25)
    else:
        below = _halve(_halve(linear, axis=0), axis=1)
    return (below if keep_linear else None), _to_bytes(below, srgb)


def _to_linear(pixels: np.ndarray, srgb: bool) -> np.ndarray:
    if not srgb:
        return pixels.astype(np.float32) / 255.0
    linear = _DECODE[pixels]
    linear[..., 3] = pixels[..., 3] / np.float32(255.0)
    return linear


def _to_bytes(values: np.ndarray, srgb: bool) -> np.ndarray:
    if not srgb:
        return np.rint(np.clip(values, 0.0, 1.0) * 255.0).astype(np.uint8)
    clipped = np.clip(values, 0.0, 1.0)
    codes = _GRID_CODES[(clipped * _GRID).astype(np.int32)]
    codes += clipped >= _EDGES_PADDED[codes]
    out = codes.astype(np.uint8)
    out[..., 3] = np.rint(clipped[..., 3] * 255.0).astype(np.uint8)
    return out


def _halve(values: np.ndarray, axis: int) -> np.ndarray:
    """``values`` with ``axis`` shrunk to max(1, n // 2): area-weighted means."""
    n = values.shape[axis]
    if n == 1:
        return values
    m = n // 2
    if n % 2 == 0:
        pairs = values.reshape(values.shape[:axis] + (m, 2) + values.shape[axis + 1:])
        return pairs.mean(axis=axis + 1, dtype=np.float32)
    # n = 2m + 1: output i covers the input span [i s, (i + 1) s), s = n / m, which lies
    # within texels 2i, 2i + 1 and 2i + 2; each is weighted by its share of the span
    s = n / m
    i = np.arange(m)
    starts, ends = i * s, (i + 1) * s
    total = np.zeros(values.shape[:axis] + (m,) + values.shape[axis + 1:], dtype=np.float32)
    for offset in range(3):
        texel = 2 * i + offset  # the texels output i can touch (s < 3)
        overlap = np.clip(np.minimum(ends, texel + 1) - np.maximum(starts, texel), 0.0, None) / s
        taken = np.take(values, np.minimum(texel, n - 1), axis=axis)
        shape = [1] * values.ndim
        shape[axis] = m
        total += taken * overlap.reshape(shape).astype(np.float32)
    return total
