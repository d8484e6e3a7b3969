"""What a uniform ambient light gives under the pbr model: the BRDF integrated over the
hemisphere, and the polynomial fit of it that the GPU and the reference evaluate.

For a view at N.V = c and roughness r, with Schlick's F = F0 + (1 - F0) Fc, Fc = (1 - V.H)^5,
the integral of f cos over the hemisphere splits into

    specular:  F0 A(c, r) + B(c, r),   A = int (1 - Fc) D V N.L,   B = int Fc D V N.L
    diffuse:   (1 - metallic) base (1 - F0) (1 - Cd(c)),   Cd = int Fc N.L / pi

(D, V as in shaders/lighting/pbr.glsl; Cd does not depend on roughness). A and B are
integrated here by importance sampling the GGX distribution (a Hammersley set), Cd by
cosine sampling, on a grid over c and r; then fitted by least squares, A and B as
polynomials of degree 6 in sqrt(c) and in r, Cd of degree 4 in 1 - c.
``python -m scenerender.raytrace.ambient_fit`` writes shaders/lighting/ambient_brdf.glsl,
the coefficients both implementations read (the reference parses that file).
"""
from __future__ import annotations

import re
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np

from scenerender.gpu.shaders import shader_dir

DEGREE = 6            # of A and B, in sqrt(N.V) and in roughness
DIFFUSE_DEGREE = 4    # of Cd, in 1 - N.V
GRID = 33
SAMPLES = 1 << 16
MIN_ALPHA = 0.002     # shaders/lighting/pbr.glsl
FILE = "lighting/ambient_brdf.glsl"


def hammersley(count: int) -> tuple[np.ndarray, np.ndarray]:
    """A Hammersley point set in the unit square: (i + 0.5) / n and the radical inverse of i."""
    index = np.arange(count, dtype=np.uint64)
    bits = index.copy()
    bits = ((bits << np.uint64(16)) | (bits >> np.uint64(16))) & np.uint64(0xFFFFFFFF)
    for mask, shift in ((0x55555555, 1), (0x33333333, 2), (0x0F0F0F0F, 4), (0x00FF00FF, 8)):
        high = np.uint64(mask << shift & 0xFFFFFFFF)
        bits = ((bits & np.uint64(mask)) << np.uint64(shift)) | ((bits & high) >> np.uint64(shift))
    return (index + 0.5) / count, bits.astype(np.float64) / 2.0**32


def specular_integrals(n_dot_v: float, roughness: float, samples: int = SAMPLES) -> tuple[float, float]:
    """(A, B) at one view angle and roughness: half vectors drawn from D(h) N.H."""
    u1, u2 = hammersley(samples)
    alpha = max(roughness * roughness, MIN_ALPHA)
    a2 = alpha * alpha
    n_dot_v = max(n_dot_v, 1e-4)
    v = np.array([np.sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v])
    cos_theta = np.sqrt((1.0 - u1) / (1.0 + (a2 - 1.0) * u1))
    sin_theta = np.sqrt(1.0 - cos_theta * cos_theta)
    h = np.stack([sin_theta * np.cos(2 * np.pi * u2), sin_theta * np.sin(2 * np.pi * u2), cos_theta], axis=1)
    v_dot_h = h @ v
    n_dot_l = (2.0 * v_dot_h[:, None] * h - v)[:, 2]
    lit = n_dot_l > 0.0
    n_dot_l, n_dot_h, v_dot_h = n_dot_l[lit], h[lit, 2], v_dot_h[lit]
    visibility = 0.5 / (n_dot_l * np.sqrt(n_dot_v * n_dot_v * (1 - a2) + a2)
                        + n_dot_v * np.sqrt(n_dot_l * n_dot_l * (1 - a2) + a2))
    # f cos / pdf with pdf = D N.H / (4 V.H): D cancels
    weight = 4.0 * visibility * n_dot_l * v_dot_h / n_dot_h
    fresnel = (1.0 - v_dot_h) ** 5
    return float(((1.0 - fresnel) * weight).sum() / samples), float((fresnel * weight).sum() / samples)


def diffuse_fresnel(n_dot_v: float, samples: int = SAMPLES) -> float:
    """Cd at one view angle: Fc averaged over cosine-distributed light directions."""
    u1, u2 = hammersley(samples)
    n_dot_v = max(n_dot_v, 1e-4)
    v = np.array([np.sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v])
    radius = np.sqrt(u1)
    l = np.stack([radius * np.cos(2 * np.pi * u2), radius * np.sin(2 * np.pi * u2), np.sqrt(1.0 - u1)], axis=1)
    h = l + v
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    return float(((1.0 - np.clip(h @ v, 0.0, 1.0)) ** 5).mean())


def _basis(n_dot_v: np.ndarray, roughness: np.ndarray) -> np.ndarray:
    s = np.sqrt(np.clip(n_dot_v, 0.0, 1.0))
    return np.stack([s**i * roughness**j for i in range(DEGREE + 1) for j in range(DEGREE + 1)], axis=-1)


def fit() -> tuple[np.ndarray, np.ndarray]:
    """((DEGREE+1)^2, 2) coefficients of A and B (index i * (DEGREE+1) + j multiplies
    sqrt(c)^i r^j), and the DIFFUSE_DEGREE+1 coefficients of Cd in (1 - c)^k. Each grid
    point weighs sqrt(c): a sphere shows few pixels at grazing angles."""
    grid = np.linspace(0.0, 1.0, GRID)
    c, r = np.meshgrid(grid, grid, indexing="ij")
    values = np.array([specular_integrals(x, y) for x, y in zip(c.ravel(), r.ravel())])
    weight = np.sqrt(np.maximum(c.ravel(), 0.02))[:, None]
    basis = _basis(c.ravel(), r.ravel())
    specular = np.linalg.lstsq(basis * weight, values * weight, rcond=None)[0]
    diffuse_values = np.array([diffuse_fresnel(x) for x in grid])
    powers = np.stack([(1.0 - grid) ** k for k in range(DIFFUSE_DEGREE + 1)], axis=1)
    diffuse = np.linalg.lstsq(powers, diffuse_values, rcond=None)[0]
    return specular, diffuse


def glsl(specular: np.ndarray, diffuse: np.ndarray) -> str:
    rows = ",\n    ".join(f"vec2({a:.9g}, {b:.9g})" for a, b in specular)
    terms = ", ".join(f"{value:.9g}" for value in diffuse)
    count = DEGREE + 1
    return f"""// The pbr model under a uniform ambient light: the fitted hemisphere integrals of its
// BRDF (scenerender/raytrace/ambient_fit.py wrote this file; the reference reads the
// same numbers). Specular: F0 A + B, A and B polynomials of degree {DEGREE} in sqrt(N.V) and
// roughness; diffuse: (1 - F0) (1 - Cd), Cd of degree {DIFFUSE_DEGREE} in 1 - N.V.

const vec2 AMBIENT_SPECULAR[{count * count}] = vec2[](
    {rows});
const float AMBIENT_DIFFUSE[{DIFFUSE_DEGREE + 1}] = float[]({terms});

// (A, B) at N.V = n_dot_v and roughness r
vec2 ambient_specular(float n_dot_v, float r) {{
    float s = sqrt(clamp(n_dot_v, 0.0, 1.0));
    vec2 sum = vec2(0.0);
    for (int i = {DEGREE}; i >= 0; --i) {{
        vec2 row = vec2(0.0);
        for (int j = {DEGREE}; j >= 0; --j) {{
            row = row * r + AMBIENT_SPECULAR[i * {count} + j];
        }}
        sum = sum * s + row;
    }}
    return sum;
}}

// Cd at N.V = n_dot_v
float ambient_diffuse_fresnel(float n_dot_v) {{
    float t = 1.0 - clamp(n_dot_v, 0.0, 1.0);
    float sum = 0.0;
    for (int k = {DIFFUSE_DEGREE}; k >= 0; --k) {{
        sum = sum * t + AMBIENT_DIFFUSE[k];
    }}
    return sum;
}}
"""


@lru_cache(maxsize=1)
def coefficients() -> tuple[np.ndarray, np.ndarray]:
    """The committed coefficients, read from the GLSL file: ((DEGREE+1)^2, 2) and (DIFFUSE_DEGREE+1,)."""
    text = (shader_dir() / FILE).read_text(encoding="utf-8")
    number = r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?"
    specular = re.search(r"AMBIENT_SPECULAR\[\d+\] = vec2\[\]\((.*?)\);", text, re.S).group(1)
    pairs = re.findall(rf"vec2\(({number}), ({number})\)", specular)
    diffuse = re.search(r"AMBIENT_DIFFUSE\[\d+\] = float\[\]\((.*?)\);", text, re.S).group(1)
    return (np.array(pairs, dtype=np.float64),
            np.array(re.findall(number, diffuse), dtype=np.float64))


def evaluate(n_dot_v: np.ndarray, roughness: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A, B, Cd) of the committed fit, per point: (P,) arrays each."""
    specular, diffuse = coefficients()
    n_dot_v = np.clip(np.asarray(n_dot_v, dtype=np.float64), 0.0, 1.0)
    values = _basis(n_dot_v, np.asarray(roughness, dtype=np.float64)) @ specular
    powers = np.stack([(1.0 - n_dot_v) ** k for k in range(DIFFUSE_DEGREE + 1)], axis=-1)
    return values[..., 0], values[..., 1], powers @ diffuse


def main(argv: list[str]) -> int:
    path = Path(argv[0]) if argv else shader_dir() / FILE
    specular, diffuse = fit()
    path.write_text(glsl(specular, diffuse), encoding="utf-8")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
