"""The directional albedo of KHR_materials_sheen's lobe, and the polynomial fit of it that
the GPU and the reference evaluate.

With the Charlie distribution D and its visibility V (raytrace/shading.py, shaders/
lighting/sheen.glsl), E(c, r) = int D V N.L over the hemisphere, for a view at N.V = c and
sheen roughness r: the share of light a white sheen reflects, which the extension takes
from the layer beneath (its albedo scaling, 1 - max(sheen colour) E) and which a uniform
ambient light gives back (sheen colour x E). Integrated here by the midpoint rule over
the hemisphere on a grid over c and r, then fitted by least squares as a polynomial of
degree DEGREE in sqrt(c) and in r. ``python -m scenerender.raytrace.sheen_fit`` writes
shaders/lighting/sheen_albedo.glsl, which the reference parses for the same numbers.
"""
from __future__ import annotations

import re
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np

from scenerender.gpu.shaders import shader_dir

DEGREE = 6
GRID = 33
STEPS = 256  # midpoint rule steps in each of the polar and azimuthal angles
FILE = "lighting/sheen_albedo.glsl"


# below this sheen roughness the Charlie lobe is kept at this one: its albedo's fit (and
# float32's powers of sin^2) stay smooth; the lobe is a grazing sliver there either way
MIN_SHEEN_ROUGHNESS = 0.07


def sheen_alpha(roughness) -> np.ndarray:
    """alpha = sheen roughness^2, the roughness kept at MIN_SHEEN_ROUGHNESS or above."""
    return np.maximum(np.asarray(roughness, dtype=np.float64), MIN_SHEEN_ROUGHNESS) ** 2


def charlie_distribution(n_dot_h: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(P,) KHR_materials_sheen's "Charlie" D = (2 + 1 / alpha) sin(theta_h)^(1 / alpha) / (2 pi)."""
    sin2 = np.clip(1.0 - n_dot_h * n_dot_h, 0.0, 1.0)
    return (2.0 + 1.0 / alpha) * sin2 ** (0.5 / alpha) / (2.0 * np.pi)


def _sheen_lambda_helper(x: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """The exponent of Estevez and Kulla's fitted Lambda (KHR_materials_sheen's table)."""
    t = (1.0 - alpha) ** 2
    a = 21.5473 + (25.3245 - 21.5473) * t
    b = 3.82987 + (3.32435 - 3.82987) * t
    c = 0.19823 + (0.16801 - 0.19823) * t
    d = -1.97760 + (-1.27393 + 1.97760) * t
    e = -4.32054 + (-4.85967 + 4.32054) * t
    return a / (1.0 + b * np.power(x, c)) + d * x + e


def _sheen_lambda(cosine: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    cosine = np.abs(cosine)
    low = np.exp(_sheen_lambda_helper(cosine, alpha))
    high = np.exp(2.0 * _sheen_lambda_helper(0.5, alpha) - _sheen_lambda_helper(1.0 - cosine, alpha))
    return np.where(cosine < 0.5, low, high)


def sheen_visibility(n_dot_v: np.ndarray, n_dot_l: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(P,) the Charlie sheen's visibility 1 / ((1 + Lambda(N.V) + Lambda(N.L)) 4 N.V N.L),
    clamped to [0, 1] (as the Khronos Sample Viewer does); 0 where N.V or N.L is 0."""
    product = 4.0 * n_dot_v * n_dot_l
    denominator = (1.0 + _sheen_lambda(n_dot_v, alpha) + _sheen_lambda(n_dot_l, alpha)) * product
    return np.where(product > 0.0, np.clip(1.0 / np.where(product > 0.0, denominator, 1.0), 0.0, 1.0), 0.0)


def albedo(n_dot_v: float, roughness: float, steps: int = STEPS) -> float:
    """E at one view angle and roughness: int D V N.L d omega over the hemisphere."""
    c = min(max(n_dot_v, 1e-4), 1.0)
    v = np.array([np.sqrt(1.0 - c * c), 0.0, c])
    theta = (np.arange(steps) + 0.5) * (0.5 * np.pi / steps)
    phi = (np.arange(steps) + 0.5) * (2.0 * np.pi / steps)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    l = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1).reshape(-1, 3)
    h = l + v
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    alpha = sheen_alpha(np.full(len(l), roughness))
    f = charlie_distribution(h[:, 2], alpha) * sheen_visibility(np.full(len(l), c), l[:, 2], alpha)
    weight = (np.sin(t) * np.cos(t)).reshape(-1) * (0.5 * np.pi / steps) * (2.0 * np.pi / steps)
    return float(np.sum(f * weight))


def _basis(n_dot_v: np.ndarray, roughness: np.ndarray) -> np.ndarray:
    s = np.sqrt(np.clip(n_dot_v, 0.0, 1.0))
    r = np.maximum(roughness, MIN_SHEEN_ROUGHNESS)
    return np.stack([s**i * r**j for i in range(DEGREE + 1) for j in range(DEGREE + 1)], axis=-1)


def fit() -> np.ndarray:
    """((DEGREE+1)^2,) coefficients (index i * (DEGREE+1) + j multiplies sqrt(c)^i r^j)."""
    grid = np.linspace(0.0, 1.0, GRID)
    roughness = np.linspace(MIN_SHEEN_ROUGHNESS, 1.0, GRID)
    c, r = np.meshgrid(grid, roughness, indexing="ij")
    values = np.array([albedo(x, y) for x, y in zip(c.ravel(), r.ravel())])
    return np.linalg.lstsq(_basis(c.ravel(), r.ravel()), values, rcond=None)[0]


def glsl(coefficients: np.ndarray) -> str:
    rows = ",\n    ".join(f"{value:.9g}" for value in coefficients)
    count = DEGREE + 1
    return f"""// The directional albedo E(N.V, r) of KHR_materials_sheen's Charlie lobe
// (scenerender/raytrace/sheen_fit.py wrote this file; the reference reads the same
// numbers): a polynomial of degree {DEGREE} in sqrt(N.V) and the sheen roughness (kept at
// {MIN_SHEEN_ROUGHNESS} or above).

const float SHEEN_ALBEDO[{count * count}] = float[](
    {rows});

float sheen_albedo(float n_dot_v, float roughness) {{
    float s = sqrt(clamp(n_dot_v, 0.0, 1.0));
    float r = max(roughness, {MIN_SHEEN_ROUGHNESS});
    float sum = 0.0;
    for (int i = {DEGREE}; i >= 0; --i) {{
        float row = 0.0;
        for (int j = {DEGREE}; j >= 0; --j) {{
            row = row * r + SHEEN_ALBEDO[i * {count} + j];
        }}
        sum = sum * s + row;
    }}
    return sum;
}}
"""


@lru_cache(maxsize=1)
def coefficients() -> np.ndarray:
    """The committed coefficients, read from the GLSL file: ((DEGREE+1)^2,)."""
    text = (shader_dir() / FILE).read_text(encoding="utf-8")
    body = re.search(r"SHEEN_ALBEDO\[\d+\] = float\[\]\((.*?)\);", text, re.S).group(1)
    return np.array(re.findall(r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?", body), dtype=np.float64)


def evaluate(n_dot_v: np.ndarray, roughness: np.ndarray) -> np.ndarray:
    """E of the committed fit, per point: (P,)."""
    return _basis(np.asarray(n_dot_v, dtype=np.float64), np.asarray(roughness, dtype=np.float64)) @ coefficients()


def main(argv: list[str]) -> int:
    path = Path(argv[0]) if argv else shader_dir() / FILE
    path.write_text(glsl(fit()), encoding="utf-8")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
