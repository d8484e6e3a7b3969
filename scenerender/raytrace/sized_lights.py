"""Lights with a size in the reference: directions drawn over the light's solid angle, or
points over an area light's surface.

A point or spot light with a ``radius`` is a uniform sphere, a directional light with an
``angular_diameter`` a disc of that angular size at infinity (the same cone of directions as
a sphere at distance 1 with radius tan(half angle)). Its radiance is E / (pi sin^2 sigma),
E the colour x intensity x attenuation at its centre and sigma its angular radius, so that
wherever the whole light is above the horizon it gives what the point light of the same
intensity gives (docs/scene-notes.md, "Lights with a size"). Each sample point draws one
direction uniformly over the cone the light subtends (seeded, so the reference stays
deterministic); its light term is the BRDF's at that direction, weighted by the cone's
solid angle over pi sin^2 sigma, and its shadow ray stops where the ray meets the sphere.
"""
from __future__ import annotations

import numpy as np

from scenerender.raytrace import shading
from scenerender.raytrace.environment_sampling import tangent_frame
from scenerender.world.light_states import area_axes

# A point inside the sphere sees (almost) a whole hemisphere of it.
MAX_SIN2 = 0.9999


def sphere_directions(to_centre: np.ndarray, radius: float, rng) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Directions drawn uniformly over the cone a sphere of ``radius`` centred
    ``to_centre`` (P, 3) away subtends: (l (P, 3) unit, weight (P,) = the cone's solid angle
    over pi sin^2 sigma, reach (P,) the distance along l to the sphere's near side)."""
    distance = np.maximum(np.linalg.norm(to_centre, axis=1), 1e-20)
    centre = to_centre / distance[:, None]
    sin2 = np.minimum((radius / distance) ** 2, MAX_SIN2)
    cos_max = np.sqrt(1.0 - sin2)
    u1, u2 = rng.random((2, len(to_centre)))
    cos_a = 1.0 - u1 * (1.0 - cos_max)
    sin_a = np.sqrt(np.maximum(1.0 - cos_a * cos_a, 0.0))
    angle = 2.0 * np.pi * u2
    tangent, bitangent = tangent_frame(centre)
    l = (tangent * (sin_a * np.cos(angle))[:, None] + bitangent * (sin_a * np.sin(angle))[:, None]
         + centre * cos_a[:, None])
    l = shading.safe_normalize(l, centre)
    weight = 2.0 * np.pi * (1.0 - cos_max) / (np.pi * sin2)
    # the ray's first meeting with the sphere: d cos a - sqrt(R^2 - d^2 sin^2 a)
    reach = distance * cos_a - np.sqrt(np.maximum(radius * radius - (distance * sin_a) ** 2, 0.0))
    return l, weight, np.maximum(reach, 0.0)


def disc_directions(direction: np.ndarray, tan_half: float, count: int, rng) -> tuple[np.ndarray, np.ndarray]:
    """A directional light of half angle atan(tan_half), travelling along ``direction``
    (3,): (l (P, 3) towards it, weight (P,)), as sphere_directions with the sphere at
    distance 1."""
    to_centre = np.broadcast_to(-np.asarray(direction, dtype=np.float64), (count, 3))
    l, weight, _ = sphere_directions(np.ascontiguousarray(to_centre), tan_half, rng)
    return l, weight


def area_directions(centre: np.ndarray, direction: np.ndarray, kind: str, extent: tuple, p: np.ndarray,
                    rng) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A one-sided rectangle or disk facing ``direction``, centred at ``centre`` (3,), seen
    from points ``p`` (P, 3): one point drawn uniformly over its surface per sample point.
    (l (P, 3) unit towards it, weight (P,) = cos at the light x area / (pi d^2), reach (P,)
    the distance to it). Its radiance is colour x intensity / pi, so the weight's mean is the
    form factor (docs/scene-notes.md, "Area lights")."""
    u, v = area_axes(np.asarray(direction, dtype=np.float64))
    half_u, half_v = extent
    r1, r2 = rng.random((2, len(p)))
    if kind == "rect":
        offsets = ((2.0 * r1 - 1.0) * half_u)[:, None] * u + ((2.0 * r2 - 1.0) * half_v)[:, None] * v
        area = 4.0 * half_u * half_v
    else:
        radius, angle = half_u * np.sqrt(r1), 2.0 * np.pi * r2
        offsets = (radius * np.cos(angle))[:, None] * u + (radius * np.sin(angle))[:, None] * v
        area = np.pi * half_u * half_u
    to_light = centre[None, :] + offsets - p
    distance = np.maximum(np.linalg.norm(to_light, axis=1), 1e-20)
    l = to_light / distance[:, None]
    facing = np.maximum(-(l @ np.asarray(direction, dtype=np.float64)), 0.0)
    return l, facing * area / (np.pi * distance * distance), distance
