"""Fit linearly transformed cosines (Heitz, Dupuy, Hill and Neubelt 2016) to the pbr
model's GGX lobe: writes scenerender/rendering/ltc_ggx.npy, which the rectangle lights'
specular term reads (shaders/lighting/area.glsl).

The BRDF is glTF's (shaders/lighting/pbr.glsl) without Fresnel: f cos = D V N.L, D GGX with
alpha = roughness^2 (kept above 0.002 as the shader keeps it), V height-correlated Smith.
Per cell of a grid over (roughness, sqrt(1 - N.V)), in the frame where N is z and V lies in
the xz plane (x towards V), the cosine distribution D_o(w) = max(w.z, 0) / pi transformed by
M (its density D_o(M^-1 w / |M^-1 w|) |M^-1| / |M^-1 w|^3) is fitted to f cos / |f cos| by Nelder-Mead on the L3 distance between the two, estimated
with fixed samples of both (multiple importance sampling, balance heuristic) so that the
objective is smooth in the parameters. Each cell starts from its neighbour's fit: rows from
the roughest down, along a row from normal incidence to grazing. M is R [[a, 0, b], [0, c, 0],
[0, 0, 1]], R the rotation about y taking z to the lobe's average direction (worked out per
cell, as in the paper, so that a warm start follows the lobe as it turns); a, b, c are
fitted. Up to scale M^-1 then has the paper's form [[1, 0, m02], [0, m11, 0], [m20, 0, m22]].

Also per cell: the magnitude |f cos| (its hemisphere integral, F = 1) and the Fresnel part
of it, the integral of f cos (1 - V.H)^5, so that with Schlick's Fresnel the lobe's integral
is F0 (magnitude - fresnel) + fresnel.

Output, float32 (N_ROUGHNESS, N_VIEW, 6): M^-1 scaled to m00 = 1 as (m02, m11, m20, m22),
then the magnitude and the Fresnel part.
Run: python benchmarks/ltc/fit_ltc.py [--size 32] [--samples 256]
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.optimize import minimize

from scenerender.raytrace.shading import ggx_distribution, smith_visibility

MIN_ALPHA = 0.002
OUTPUT = Path(__file__).resolve().parents[2] / "scenerender" / "rendering" / "ltc_ggx.npy"


def grid(size: int):
    """Roughness rows (0 .. 1) and N.V columns (cos theta with sqrt(1 - cos) = 0 .. 1,
    the last kept at 0.02: the lookup clamps there)."""
    roughness = np.linspace(0.0, 1.0, size)
    t = np.linspace(0.0, 1.0, size)
    mu = np.maximum(1.0 - t * t, 0.02)
    return roughness, mu


def brdf_cos(l, v, alpha):
    """D V N.L (F = 1) for unit directions l (..., 3); 0 below the horizon."""
    n_dot_l = l[..., 2]
    h = l + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    nl = np.maximum(n_dot_l, 0.0)
    return np.where(n_dot_l > 0.0, ggx_distribution(h[..., 2], alpha) * smith_visibility(v[2], nl, alpha) * nl, 0.0)


def sample_ggx(u1, u2, v, alpha):
    """Directions l reflected about GGX normals (pdf D N.H / (4 V.H)); returns l, pdf."""
    a2 = alpha * alpha
    phi = 2.0 * np.pi * u1
    cos2 = (1.0 - u2) / (1.0 + (a2 - 1.0) * u2)
    cos_t = np.sqrt(cos2)
    sin_t = np.sqrt(np.maximum(1.0 - cos2, 0.0))
    h = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1)
    v_dot_h = h @ v
    l = 2.0 * v_dot_h[:, None] * h - v
    pdf = ggx_distribution(cos_t, alpha) * cos_t / (4.0 * np.maximum(np.abs(v_dot_h), 1e-12))
    return l, pdf, v_dot_h


def ggx_pdf(l, v, alpha):
    h = l + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    n_dot_h = h[..., 2]
    d = ggx_distribution(n_dot_h, alpha)
    return np.where(n_dot_h > 0.0, d * n_dot_h / (4.0 * np.maximum(np.abs(np.sum(l * h, axis=-1)), 1e-12)), 0.0)


def matrix(p, theta):
    """M from the fit's parameters (log a, log c, b): the rotation by theta about y (z to
    the lobe's average direction) times [[a, 0, b], [0, c, 0], [0, 0, 1]]."""
    rotation = np.array([[np.cos(theta), 0.0, np.sin(theta)], [0.0, 1.0, 0.0], [-np.sin(theta), 0.0, np.cos(theta)]])
    return rotation @ np.array([[np.exp(p[0]), 0.0, p[2]], [0.0, np.exp(p[1]), 0.0], [0.0, 0.0, 1.0]])


def ltc_density(l, m_inv, det_inv):
    w = l @ m_inv.T
    length = np.linalg.norm(w, axis=-1)
    return np.maximum(w[..., 2] / length, 0.0) / np.pi * det_inv / length ** 3


def stratified(count: int, seed: int):
    """count 2D points, one per cell of a jittered sqrt(count) square grid."""
    side = int(round(np.sqrt(count)))
    rng = np.random.default_rng(seed)
    i, j = np.meshgrid(np.arange(side), np.arange(side), indexing="ij")
    return ((i.ravel() + rng.random(side * side)) / side, (j.ravel() + rng.random(side * side)) / side)


def fit_cell(alpha, mu, start, samples: int, brdf_u, cos_u):
    v = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    l_b, pdf_b_all, _ = sample_ggx(*brdf_u, v, alpha)
    keep = l_b[:, 2] > 0.0
    l_b = l_b[keep]
    # the magnitude and Fresnel integrals, from many more samples
    mu1, mu2 = stratified(256 * 256, 7)
    l_m, pdf_m, v_dot_h = sample_ggx(mu1, mu2, v, alpha)
    weight = np.where(l_m[:, 2] > 0.0, brdf_cos(l_m, v, alpha) / np.maximum(pdf_m, 1e-30), 0.0)
    magnitude = weight.mean()
    fresnel = (weight * (1.0 - np.clip(v_dot_h, 0.0, 1.0)) ** 5).mean()
    average = (weight[:, None] * np.where(l_m[:, 2:3] > 0.0, l_m, 0.0)).sum(axis=0)
    theta = np.arctan2(average[0], average[2])

    f_b = brdf_cos(l_b, v, alpha) / magnitude
    pdf_b = ggx_pdf(l_b, v, alpha)
    # cosine samples to push through M
    r = np.sqrt(cos_u[0])
    phi = 2.0 * np.pi * cos_u[1]
    w_o = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(1.0 - cos_u[0], 0.0))], axis=-1)
    n_b = len(brdf_u[0])
    n_c = len(w_o)

    def error(p):
        m = matrix(p, theta)
        det = np.linalg.det(m)
        if not np.isfinite(det) or det <= 1e-12:
            return 1e30
        m_inv = np.linalg.inv(m)
        det_inv = 1.0 / det
        # samples of the LTC
        l_c = w_o @ m.T
        l_c /= np.linalg.norm(l_c, axis=-1, keepdims=True)
        g_c = ltc_density(l_c, m_inv, det_inv)
        f_c = brdf_cos(l_c, v, alpha) / magnitude
        pdf_bc = ggx_pdf(l_c, v, alpha)
        g_b = ltc_density(l_b, m_inv, det_inv)
        # balance heuristic over both sample sets (n_b BRDF, n_c LTC samples)
        e_b = np.abs(f_b - g_b) ** 3 / (n_b * pdf_b + n_c * g_b)
        e_c = np.abs(f_c - g_c) ** 3 / (n_b * pdf_bc + n_c * g_c)
        return e_b.sum() + e_c.sum()

    simplex = np.array(start)[None, :] + np.vstack([np.zeros(3), 0.1 * np.eye(3)])
    best = minimize(error, start, method="Nelder-Mead", options=dict(initial_simplex=simplex, xatol=1e-4, fatol=1e-8, maxiter=600))
    return best.x, theta, magnitude, fresnel


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=32)
    parser.add_argument("--samples", type=int, default=256, help="BRDF and LTC samples each, per objective")
    parser.add_argument("--output", type=Path, default=OUTPUT)
    args = parser.parse_args(argv)
    roughness, mus = grid(args.size)
    brdf_u = stratified(args.samples, 1)
    cos_u = stratified(args.samples, 2)
    table = np.zeros((args.size, args.size, 6))
    started = time.perf_counter()
    row_start = np.array([0.0, 0.0, 0.0])  # roughness 1, normal incidence: about the cosine
    for i in range(args.size - 1, -1, -1):
        alpha = max(roughness[i] ** 2, MIN_ALPHA)
        start = row_start
        for j, mu in enumerate(mus):
            p, theta, magnitude, fresnel = fit_cell(alpha, mu, start, args.samples, brdf_u, cos_u)
            if j == 0:
                row_start = p
            start = p
            m_inv = np.linalg.inv(matrix(p, theta))
            m_inv /= m_inv[0, 0]
            table[i, j] = (m_inv[0, 2], m_inv[1, 1], m_inv[2, 0], m_inv[2, 2], magnitude, fresnel)
        print(f"roughness {roughness[i]:.3f}: {time.perf_counter() - started:.1f} s", flush=True)
    np.save(args.output, table.astype(np.float32))
    print(f"wrote {args.output} in {time.perf_counter() - started:.1f} s")


if __name__ == "__main__":
    main()
