"""The exact sRGB transfer function (IEC 61966-2-1) on NumPy arrays, both ways; the curve
shaders/post/encode.glsl applies."""
from __future__ import annotations

import numpy as np


def srgb_encode(linear) -> np.ndarray:
    """Linear light -> display values, both in [0, 1] (input clamped); any shape, float64."""
    c = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    return np.where(c < 0.0031308, c * 12.92, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def srgb_decode(encoded) -> np.ndarray:
    """Display values in [0, 1] -> linear light; any shape, float64."""
    e = np.asarray(encoded, dtype=np.float64)
    return np.where(e <= 0.04045, e / 12.92, ((e + 0.055) / 1.055) ** 2.4)


# -- tone curves -------------------------------------------------------------------------
# Scene-linear light (any value >= 0) -> display-linear light in [0, 1], per pixel, before
# the output transform encodes it; the curves of shaders/post/tone_aces.glsl and
# tone_agx.glsl, which the reference renderer applies too. docs/scene-notes.md says where
# each fit comes from.

TONE_MAPS = ("none", "aces", "agx")

# ACES: Stephen Hill's fit of the ACES reference rendering transform and sRGB output
# transform (RRT + ODT), as published in MJP's BakingLab (ACES.hlsl). Rows: out = M @ in.
# sRGB -> XYZ -> D65 to D60 -> AP1, with the RRT's saturation adjustment folded in:
ACES_INPUT = np.array([[0.59719, 0.35458, 0.04823],
                       [0.07600, 0.90834, 0.01566],
                       [0.02840, 0.13383, 0.83777]])
# the ODT's saturation adjustment -> XYZ -> D60 to D65 -> sRGB:
ACES_OUTPUT = np.array([[1.60475, -0.53108, -0.07367],
                        [-0.10208, 1.10813, -0.00605],
                        [-0.00327, -0.07276, 1.07602]])

# AgX: Benjamin Wrensch's (Missing Deadlines) minimal AgX, after Troy Sobotka's AgX: the
# inset matrix, a log2 encoding from 2^AGX_MIN_EV to 2^AGX_MAX_EV, a 6th-order polynomial
# fit of the default contrast curve (AGX_CONTRAST, highest power first), the outset matrix.
AGX_INSET = np.array([[0.842479062253094, 0.0784335999999992, 0.0792237451477643],
                      [0.0423282422610123, 0.878468636469772, 0.0791661274605434],
                      [0.0423756549057051, 0.0784336, 0.879142973793104]])
AGX_OUTSET = np.array([[1.19687900512017, -0.0980208811401368, -0.0990297440797205],
                       [-0.0528968517574562, 1.15190312990417, -0.0989611768448433],
                       [-0.0529716355144438, -0.0980434501171241, 1.15107367264116]])
AGX_MIN_EV = -12.47393
AGX_MAX_EV = 4.026069
AGX_CONTRAST = (15.5, -40.14, 31.96, -6.868, 0.4298, 0.1191, -0.00232)
AGX_DISPLAY_GAMMA = 2.2  # the contrast curve's output is display-encoded with a 2.2 power


def aces_fitted(linear) -> np.ndarray:
    """Hill's ACES fit on (..., 3) linear sRGB: input matrix, per channel
    (v (v + 0.0245786) - 0.000090537) / (v (0.983729 v + 0.432951) + 0.238081), output
    matrix, clamped to [0, 1]; float64."""
    v = np.asarray(linear, dtype=np.float64) @ ACES_INPUT.T
    v = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081)
    return np.clip(v @ ACES_OUTPUT.T, 0.0, 1.0)


def agx(linear) -> np.ndarray:
    """Minimal AgX on (..., 3) linear sRGB, back to linear light: inset matrix, log2
    encoded over [AGX_MIN_EV, AGX_MAX_EV] to [0, 1], the contrast polynomial, outset
    matrix, clamped to [0, 1], raised to 2.2; float64."""
    v = np.asarray(linear, dtype=np.float64) @ AGX_INSET.T
    v = np.clip(np.log2(np.maximum(v, 1e-10)), AGX_MIN_EV, AGX_MAX_EV)
    v = (v - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV)
    v = np.polyval(AGX_CONTRAST, v)
    return np.power(np.clip(v @ AGX_OUTSET.T, 0.0, 1.0), AGX_DISPLAY_GAMMA)


def tone_map(linear, curve: str, exposure: float = 0.0) -> np.ndarray:
    """Scene-linear (..., 3) -> display-linear: times 2^``exposure`` (stops), then the tone
    curve ``curve`` ("none" leaves the values as they are: the output transform clamps);
    float64."""
    scaled = np.asarray(linear, dtype=np.float64) * 2.0 ** exposure
    if curve == "aces":
        return aces_fitted(scaled)
    if curve == "agx":
        return agx(scaled)
    return scaled


def encode_output(linear: np.ndarray, transform: str, gamma: float = 2.2) -> np.ndarray:
    """Linear colour -> 8-bit display values as the output pass stores them.

    transform: "srgb" | "gamma" | "linear". Any (..., 3) float array -> same shape uint8,
    rounded to nearest."""
    c = np.clip(linear, 0.0, 1.0)
    if transform == "srgb":
        encoded = srgb_encode(c)
    elif transform == "gamma":
        encoded = np.power(c, 1.0 / gamma)
    else:
        encoded = c
    return np.floor(encoded * 255.0 + 0.5).astype(np.uint8)
