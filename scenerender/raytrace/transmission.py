"""KHR_materials_transmission and KHR_materials_volume in the reference: light through the
rough surface's GGX lobe (docs/scene-notes.md, "Transmission and volume").

At each interface a path meets, a microfacet normal m is drawn from GGX's distribution of
normals visible from the path (Heitz 2018), and the path goes on

- through a thin wall (thickness 0): the lobe reflected about m, mirrored through the
  surface's plane (the specification's specular BTDF: the BRDF's lobe on the far side);
- into or out of a volume: refracted about m by the index of refraction (Walter et al.
  2007's rough dielectric), or, from inside, reflected back with the probability of the
  Fresnel term (always, past the critical angle);

weighted by what the BSDF over the density it was drawn with leaves: (1 - F) G2 / G1 for
the part that passes (F the model's Schlick Fresnel of the dielectric, F0 and F90 as the
reflection uses), G2 / G1 for a reflection from inside. A weight never exceeds 1, so no
light is made. Inside a volume the path loses exp(-sigma d) over its length d, sigma =
-ln(attenuation_color) / attenuation_distance (Beer-Lambert).

Conventions as in scenerender.raytrace.shading: (P, 3) float64 vectors, (P,) scalars.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenerender.raytrace import shading
from scenerender.raytrace.environment_sampling import TangentFrame, ggx_visible_normals, sampling_view

# the surface values a transmitting path reads at each interface, besides the layers
# (shading.LAYER_KEYS): per material, from transmission_table
SURFACE_KEYS = ("ior", "thickness", "extinction")
# the most interfaces a path through transmissive surfaces crosses or reflects off; a
# path still inside a volume after them is dropped (light lost, never made)
MAX_INTERFACES = 12


def transmission_table(materials: list) -> dict:
    """Per-material arrays: ior (K,), thickness (K,) and extinction sigma (K, 3), 0 where
    the attenuation distance is infinite. ``materials``: Material or None each."""
    def extinction(material) -> np.ndarray:
        if material is None or not np.isfinite(material.attenuation_distance):
            return np.zeros(3)
        color = np.maximum(np.asarray(material.attenuation_color, dtype=np.float64), 1e-12)
        return -np.log(color) / material.attenuation_distance

    return {
        "ior": np.array([m.ior if m is not None else 1.5 for m in materials], dtype=np.float64),
        "thickness": np.array([m.thickness if m is not None else 0.0 for m in materials], dtype=np.float64),
        "extinction": np.array([extinction(m) for m in materials], dtype=np.float64).reshape(-1, 3),
    }


def smith_lambda(cosine: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(P,) GGX's Smith Lambda at |cosine| to the normal: (sqrt(1 + alpha^2 tan^2) - 1) / 2."""
    c2 = np.clip(cosine * cosine, 1e-12, 1.0)
    return 0.5 * (np.sqrt(1.0 + alpha * alpha * (1.0 - c2) / c2) - 1.0)


def masking_ratio(n_dot_v: np.ndarray, n_dot_l: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(P,) G2(v, l) / G1(v), height-correlated: (1 + Lambda(v)) / (1 + Lambda(v) + Lambda(l))."""
    lambda_v = smith_lambda(n_dot_v, alpha)
    return (1.0 + lambda_v) / (1.0 + lambda_v + smith_lambda(n_dot_l, alpha))


@dataclass
class Interface:
    """Points where paths meet a transmissive surface, one row each: n (P, 3) the shading
    normal and view (P, 3) the unit direction back along the path, both on the path's
    side; alpha (P,) GGX alpha; f0 (P, 3), f90 (P,) the dielectric's Fresnel; ior (P,);
    thin (P,) bool thin-walled; inside (P,) the path is inside the volume here."""

    n: np.ndarray
    view: np.ndarray
    alpha: np.ndarray
    f0: np.ndarray
    f90: np.ndarray
    ior: np.ndarray
    thin: np.ndarray
    inside: np.ndarray


@dataclass
class Scattered:
    """Where paths go on from an Interface: l (P, 3) unit; weight (P, 3); crossed (P,)
    bool: the path went through the surface (into or out of a volume, or through a thin
    wall); inside (P,) bool: it is inside a volume after it."""

    l: np.ndarray
    weight: np.ndarray
    crossed: np.ndarray
    inside: np.ndarray


def scatter(at: Interface, rng) -> Scattered:
    """One interface event a path (see the module's docstring). A path from outside always
    passes (its reflection is the surface's BRDF, shaded on its own), weighted by 1 - F;
    from inside it passes or reflects by the chance of F."""
    count = len(at.n)
    frame = TangentFrame(at.n)
    local_view = sampling_view(at.n, frame.tangent, frame.bitangent, at.view)
    m = frame.to_world(ggx_visible_normals(local_view, at.alpha, *rng.random((2, count))))
    v_dot_m = np.clip(np.sum(at.view * m, axis=1), 0.0, 1.0)
    reflected = 2.0 * v_dot_m[:, None] * m - at.view
    # relative index across the interface: 1 / ior going in, ior coming out
    eta = np.where(at.inside, at.ior, 1.0 / at.ior)
    cos_t2 = 1.0 - eta * eta * (1.0 - v_dot_m * v_dot_m)
    total_reflection = (cos_t2 <= 0.0) & ~at.thin
    cos_t = np.sqrt(np.maximum(cos_t2, 0.0))
    refracted = (eta * v_dot_m - cos_t)[:, None] * m - eta[:, None] * at.view
    # Schlick's F at the cosine on the side of the lower index
    cosine = np.where(at.inside & ~at.thin, cos_t, v_dot_m)
    fresnel = at.f0 + (at.f90[:, None] - at.f0) * ((1.0 - cosine) ** 5)[:, None]
    fresnel = np.where(total_reflection[:, None], 1.0, fresnel)
    chance = fresnel.mean(axis=1)
    # from inside: reflect with the chance of F; from outside: always through
    reflect = at.inside & (rng.random(count) < chance)
    through = np.where(at.thin[:, None], reflected - 2.0 * np.sum(reflected * at.n, axis=1)[:, None] * at.n, refracted)
    l = shading.safe_normalize(np.where(reflect[:, None], reflected, through), -at.view)
    n_dot_l = np.sum(at.n * l, axis=1)
    ratio = masking_ratio(np.sum(at.n * at.view, axis=1), n_dot_l, at.alpha)
    passed = (1.0 - fresnel) / np.where(at.inside, np.maximum(1.0 - chance, 1e-12), 1.0)[:, None]
    kept = fresnel / np.maximum(chance, 1e-12)[:, None]
    weight = np.where(reflect[:, None], kept, passed) * ratio[:, None]
    # a direction on the wrong side of the surface is a path the microfacets block
    right_side = np.where(reflect, n_dot_l > 0.0, n_dot_l < 0.0) & ~(total_reflection & ~reflect)
    weight = np.where(right_side[:, None], weight, 0.0)
    crossed = ~reflect
    inside = np.where(at.thin | reflect, at.inside, ~at.inside)
    return Scattered(l, weight, crossed, inside)
