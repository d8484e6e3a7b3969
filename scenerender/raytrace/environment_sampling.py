"""Light from an environment image in the reference renderer, by Monte Carlo.

A surface point reflects towards the eye

    Ka * integral over the hemisphere of f(l, v) L_env(l) (N.l) dl

with L_env the environment's radiance (scenerender.world.environment_light) and f the material's
BRDF: the pbr model's whole BRDF, or for Phong and Blinn-Phong materials (only where the
light has ``classic: true``) a Lambert surface, base / pi, with no specular part.

Each sample point draws ``samples`` directions, each by one of three strategies picked at
random: the image (``ImageSampler``: a texel in proportion to the brightness around it
times its solid angle, then uniformly in the texel's (u, v), so a small bright sun is found; picked
with probability IMAGE_CHOICE times how concentrated the image's light is, nothing for a
uniform image), cosine-weighted over the hemisphere (pdf N.l / pi) or
the GGX distribution of visible normals (Heitz 2018, "Sampling the GGX Distribution of
Visible Normals") reflected about the sampled half vector (pdf G1(v) D(h) / (4 N.v), the
half vector's pdf G1(v) max(v.h, 0) D(h) / N.v times the reflection's Jacobian
1 / (4 v.h)). A direction is weighted by its pdf under the mixture of all three (the
balance heuristic of multiple importance sampling in its one-sample form), so any strategy
may find any direction; Lambert surfaces leave GGX out. Of the rest, GGX is picked with the
share of the Fresnel reflectance at N.v in what the surface reflects, kept within
[0.25, 0.9].

One uniform number, the pick, chooses the strategy and, rescaled to [0, 1), is the chosen
strategy's first random number (the image's position along its texels' cumulative
distribution; the cosine's and GGX's squared radius). Picks are stratified: each of a
pixel's sample points x directions gets its own stratum of [0, 1) (``pixel_strata``: a
golden-ratio step through them from a random start), so every pixel draws close to its
expected number of directions towards a sun, instead of a binomial number of them. Each
direction on its own still follows the mixture (its stratum is uniformly random), so the
estimate stays unbiased.

Vectors are float64 (P, 3), one row per sample point, as in scenerender.raytrace.shading.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scenerender.raytrace import shading
from scenerender.world.environment_light import equirect_uv, texel_solid_angles

MIN_GGX_CHOICE, MAX_GGX_CHOICE = 0.25, 0.9  # the probability of the GGX strategy, for pbr surfaces
MIN_SAMPLING_COS = 1e-3  # a view at or below the horizon is sampled as if just above it
IMAGE_CHOICE = 0.5  # the most probability of drawing from the image (see ImageSampler.choice)
MIN_IMAGE_CHOICE = 0.02  # below this, a nearly uniform image is not drawn from at all
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0  # the step through a pixel's strata, as a fraction of their count


class ImageSampler:
    """Directions drawn from an equirectangular image (H, W, 3): a texel in proportion to
    its solid angle times the brightest (channel mean of image x ``scale``) of it and its
    eight neighbours, then uniformly in (u, v) inside it. The image is read bilinearly, so
    the radiance inside a texel comes from its neighbours too: weighing by their brightest
    keeps radiance over density bounded (a texel beside the sun, dim itself, is drawn as
    often as the sun's own texels and not 100 times less). ``to_image`` (3, 3) turns world
    directions into the image's frame (scenerender.world.environment_light.EnvironmentState)."""

    def __init__(self, image: np.ndarray, scale: np.ndarray, to_image: np.ndarray):
        height, width = image.shape[:2]
        brightness = np.maximum(np.asarray(image, dtype=np.float64) @ np.asarray(scale, dtype=np.float64) / 3.0, 0.0)
        weights = _neighbourhood_max(brightness) * texel_solid_angles(height, width)
        self.shape = (height, width)
        self.to_image = np.asarray(to_image, dtype=np.float64)
        self.cdf = np.cumsum(weights.ravel())
        self.total = float(self.cdf[-1])
        self.probability = weights / max(self.total, 1e-300)
        choice = IMAGE_CHOICE * (1.0 - _uniformity(brightness, texel_solid_angles(height, width)))
        self.choice = choice if choice >= MIN_IMAGE_CHOICE else 0.0

    def draw(self, r1: np.ndarray, r2: np.ndarray, r3: np.ndarray) -> np.ndarray:
        """(N, 3) unit world directions from uniform numbers (N,) each."""
        height, width = self.shape
        texel = np.minimum(np.searchsorted(self.cdf, r1 * self.total, side="right"), height * width - 1)
        row, column = np.divmod(texel, width)
        theta = (row + r3) / height * np.pi
        phi = ((column + r2) / width - 0.5) * 2.0 * np.pi
        sin_t = np.sin(theta)
        in_image = np.stack([sin_t * np.sin(phi), np.cos(theta), -sin_t * np.cos(phi)], axis=1)
        return in_image @ self.to_image

    def pdf(self, directions: np.ndarray) -> np.ndarray:
        """(N,) solid-angle density of unit world ``directions`` (N, 3): the texel's
        probability over its (u, v) area, times 1 / (2 pi^2 sin theta) from (u, v) to solid angle."""
        height, width = self.shape
        in_image = directions @ self.to_image.T
        u, v = equirect_uv(in_image)
        row = np.clip(np.floor(v * height).astype(np.int64), 0, height - 1)
        column = np.floor(u * width).astype(np.int64) % width
        sin_t = np.sqrt(np.maximum(1.0 - np.clip(in_image[:, 1], -1.0, 1.0) ** 2, 0.0))
        return self.probability[row, column] * height * width / (2.0 * np.pi * np.pi * np.maximum(sin_t, 1e-12))


def _neighbourhood_max(values: np.ndarray) -> np.ndarray:
    """(H, W) the largest of each texel and its eight neighbours (columns wrap around, rows
    are clamped: the equirectangular image's own neighbourhood)."""
    rows = np.maximum(values, np.maximum(np.vstack([values[:1], values[:-1]]), np.vstack([values[1:], values[-1:]])))
    return np.maximum(rows, np.maximum(np.roll(rows, 1, axis=1), np.roll(rows, -1, axis=1)))


def _uniformity(brightness: np.ndarray, solid_angles: np.ndarray) -> float:
    """(mean b)^2 / mean(b^2) over the sphere, b the brightness (H, W) and the means
    weighted by solid angle (H, 1): 1 for a uniform image, near 0 where a small part of it
    holds the light; 1 for a black one."""
    area = float(np.sum(solid_angles)) * brightness.shape[1]
    mean = float(np.sum(brightness * solid_angles)) / area
    square = float(np.sum(brightness * brightness * solid_angles)) / area
    return mean * mean / square if square > 0.0 else 1.0


def tangent_frame(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(tangent, bitangent), each (P, 3): with unit normals ``n`` an orthonormal frame."""
    helper = np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    tangent = shading.safe_normalize(np.cross(n, helper))
    return tangent, np.cross(n, tangent)


def cosine_directions(r1: np.ndarray, r2: np.ndarray) -> np.ndarray:
    """(P, 3) cosine-distributed directions about +Z from uniform numbers (P,) each."""
    radius, angle = np.sqrt(r1), 2.0 * np.pi * r2
    return np.stack([radius * np.cos(angle), radius * np.sin(angle), np.sqrt(np.maximum(1.0 - r1, 0.0))], axis=1)


def ggx_visible_normals(view: np.ndarray, alpha: np.ndarray, r1: np.ndarray, r2: np.ndarray) -> np.ndarray:
    """(P, 3) half vectors about +Z drawn from GGX's distribution of normals visible from
    ``view`` (P, 3), unit with z > 0 (Heitz 2018, listing 1)."""
    a = alpha[:, None]
    stretched = shading.safe_normalize(np.concatenate([view[:, :2] * a, view[:, 2:]], axis=1))
    lensq = stretched[:, 0] ** 2 + stretched[:, 1] ** 2
    t1 = np.where((lensq > 1e-20)[:, None],
                  np.stack([-stretched[:, 1], stretched[:, 0], np.zeros_like(lensq)], axis=1)
                  / np.sqrt(np.maximum(lensq, 1e-20))[:, None], [[1.0, 0.0, 0.0]])
    t2 = np.cross(stretched, t1)
    radius, angle = np.sqrt(r1), 2.0 * np.pi * r2
    p1, p2 = radius * np.cos(angle), radius * np.sin(angle)
    s = 0.5 * (1.0 + stretched[:, 2])
    p2 = (1.0 - s) * np.sqrt(np.maximum(1.0 - p1 * p1, 0.0)) + s * p2
    p3 = np.sqrt(np.maximum(1.0 - p1 * p1 - p2 * p2, 0.0))
    normal = t1 * p1[:, None] + t2 * p2[:, None] + stretched * p3[:, None]
    return shading.safe_normalize(np.stack([normal[:, 0] * alpha, normal[:, 1] * alpha,
                                            np.maximum(normal[:, 2], 0.0)], axis=1), np.array([0.0, 0.0, 1.0]))


def smith_g1(n_dot_v: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(P,) GGX's Smith masking G1 = 2 N.v / (N.v + sqrt(alpha^2 + (1 - alpha^2) (N.v)^2))."""
    a2 = alpha * alpha
    return 2.0 * n_dot_v / (n_dot_v + np.sqrt(a2 + (1.0 - a2) * n_dot_v * n_dot_v))


def ggx_reflection_pdf(light: np.ndarray, view: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(P,) solid-angle density of ``light`` (P, 3, about +Z) under the GGX strategy from
    ``view`` (P, 3, z > 0): G1(v) D(h) / (4 N.v); zero below the horizon."""
    h = shading.safe_normalize(light + view, np.array([0.0, 0.0, 1.0]))
    density = smith_g1(view[:, 2], alpha) * shading.ggx_distribution(h[:, 2], alpha) / (4.0 * view[:, 2])
    return np.where((light[:, 2] > 0.0) & (h[:, 2] > 0.0), density, 0.0)


def mixture_pdf(light: np.ndarray, view: np.ndarray, alpha: np.ndarray, ggx_choice: np.ndarray) -> np.ndarray:
    """(P,) density of ``light`` under the two strategies mixed, the GGX one picked with
    probability ``ggx_choice`` (P,)."""
    cosine = np.maximum(light[:, 2], 0.0) / np.pi
    ggx = np.zeros_like(cosine)
    rows = ggx_choice > 0.0
    if rows.any():
        ggx[rows] = ggx_reflection_pdf(light[rows], view[rows], alpha[rows])
    return (1.0 - ggx_choice) * cosine + ggx_choice * ggx


def draw_directions(rng, view: np.ndarray, alpha: np.ndarray, ggx_choice: np.ndarray,
                    pick: np.ndarray) -> np.ndarray:
    """(P, 3) one direction a point about +Z: by the GGX strategy where ``pick`` (P,) in
    [0, 1) falls below ``ggx_choice`` (P,), else cosine-weighted; the pick, rescaled, is
    the strategy's first random number."""
    ggx = pick < ggx_choice
    r1 = np.where(ggx, pick / np.maximum(ggx_choice, 1e-300), (pick - ggx_choice) / (1.0 - ggx_choice))
    r1 = np.clip(r1, 0.0, 1.0)
    r2 = rng.random(len(view))
    light = cosine_directions(r1, r2)
    if ggx.any():
        h = ggx_visible_normals(view[ggx], alpha[ggx], r1[ggx], r2[ggx])
        light[ggx] = 2.0 * np.sum(view[ggx] * h, axis=1, keepdims=True) * h - view[ggx]
    return light


def sampling_view(n: np.ndarray, tangent: np.ndarray, bitangent: np.ndarray, view: np.ndarray) -> np.ndarray:
    """(P, 3) the view in the (tangent, bitangent, n) frame, lifted to at least
    MIN_SAMPLING_COS above the horizon: the GGX strategy needs N.v > 0 (any proposal
    serves, as long as its density is the one the weights use)."""
    local = np.stack([np.sum(view * tangent, axis=1), np.sum(view * bitangent, axis=1),
                      np.maximum(np.sum(view * n, axis=1), MIN_SAMPLING_COS)], axis=1)
    return shading.safe_normalize(local, np.array([0.0, 0.0, 1.0]))


def ggx_choice(n_dot_v: np.ndarray, base: np.ndarray, metallic: np.ndarray) -> np.ndarray:
    """(P,) probability of the GGX strategy for pbr surfaces: Schlick's F(N.v) over F plus
    the diffuse part (1 - F) (1 - metallic) base, channel means, within the bounds."""
    m = metallic[:, None]
    f0 = 0.04 * (1.0 - m) + base * m
    fresnel = shading.fresnel_schlick(f0, np.clip(n_dot_v, 0.0, 1.0)).mean(axis=1)
    diffuse = ((1.0 - fresnel[:, None]) * (1.0 - m) * base).mean(axis=1)
    share = fresnel / np.maximum(fresnel + diffuse, 1e-12)
    return np.clip(share, MIN_GGX_CHOICE, MAX_GGX_CHOICE)


class TangentFrame:
    """An orthonormal frame (tangent, bitangent, normal) a point, each (P, 3)."""

    def __init__(self, n: np.ndarray):
        self.normal = n
        self.tangent, self.bitangent = tangent_frame(n)

    def to_world(self, local: np.ndarray) -> np.ndarray:
        return self.tangent * local[:, :1] + self.bitangent * local[:, 1:2] + self.normal * local[:, 2:]

    def to_local(self, world: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """(R, 3) world directions (R, 3) of points ``rows`` (R,) in their frames."""
        return np.stack([np.sum(world * axis[rows], axis=1) for axis in (self.tangent, self.bitangent, self.normal)],
                        axis=1)


def draw_mixed(rng, frame: TangentFrame, view: np.ndarray, alpha: np.ndarray, choice: np.ndarray,
               image: ImageSampler | None, pick: np.ndarray):
    """(l world (P, 3), l local (P, 3), pdf (P,)): one direction a point, from the image
    where ``pick`` (P,) falls below ``image.choice`` (never without an image), else from
    the cosine and GGX strategies (``view`` local, ``choice`` their GGX share); the pdf is
    the mixture's."""
    image_choice = image.choice if image is not None else 0.0
    from_image = pick < image_choice
    rest = np.clip((pick - image_choice) / (1.0 - image_choice), 0.0, 1.0 - 1e-16)
    local = draw_directions(rng, view, alpha, choice, rest)
    world = frame.to_world(local)
    rows = np.flatnonzero(from_image)
    if len(rows):
        r2, r3 = rng.random((2, len(rows)))
        world[rows] = image.draw(pick[rows] / image_choice, r2, r3)
        local[rows] = frame.to_local(world[rows], rows)
    pdf = (1.0 - image_choice) * mixture_pdf(local, view, alpha, choice)
    if image_choice:
        pdf = pdf + image_choice * image.pdf(world)
    return world, local, pdf


@dataclass(frozen=True)
class Strata:
    """Each direction's stratum of [0, 1) for its pick, one of ``count`` equal ones:
    direction k of a point takes stratum (step (first + k) + offset) mod count, ``first``
    (P,) the point's first index among its pixel's directions, ``offset`` (P,) its pixel's
    shift; ``step`` is coprime with count, so a pixel's directions take every stratum once."""

    first: np.ndarray
    offset: np.ndarray
    count: int
    step: int = 1

    def stratum(self, k: int) -> np.ndarray:
        return (self.step * (self.first + k) + self.offset) % self.count

    def __getitem__(self, rows) -> Strata:
        return Strata(self.first[rows], self.offset[rows], self.count, self.step)


def pixel_strata(rng, pixels: int, points: int, samples: int) -> Strata:
    """Strata for pixels x points sample points (a pixel's points consecutive), samples
    directions each: a pixel's points x samples directions take the strata in the order of
    a golden-ratio step, shifted by a random amount for each pixel (so that each direction's
    stratum, on its own, is uniformly random)."""
    count = points * samples
    step = round(count * GOLDEN)
    while math.gcd(step, count) != 1:
        step += 1
    first = np.tile(np.arange(points) * samples, pixels)
    offset = np.repeat(rng.integers(0, count, pixels), points)
    return Strata(first, offset, count, step)


def gather(n: np.ndarray, view: np.ndarray, alpha: np.ndarray, choice: np.ndarray, samples: int, rng,
           reflected, visible, image: ImageSampler | None = None, strata: Strata | None = None) -> np.ndarray:
    """(P, 3) the estimate of the integral of f L_env (N.l) over the hemisphere about ``n``:
    the mean over ``samples`` drawn directions of reflected(l) / pdf(l), where
    ``reflected(rows, l)`` (R, 3) is f L_env(l) (N.l) at those rows (R,) for their world
    directions l (R, 3), and ``visible(rows, l)`` (R,) bool says which of them see the
    environment along l.

    alpha: (P,) GGX alpha; choice: (P,) probability of the GGX strategy (0: cosine only);
    image: draws directions from the environment's image too (see the module's docstring);
    strata: each direction's stratum (``pixel_strata``); default each point's samples in
    strata of its own, in order."""
    if strata is None:
        strata = Strata(np.zeros(len(n), np.int64), np.zeros(len(n), np.int64), samples)
    frame = TangentFrame(n)
    local_view = sampling_view(n, frame.tangent, frame.bitangent, view)
    total = np.zeros_like(n)
    for k in range(samples):
        pick = (strata.stratum(k) + rng.random(len(n))) / strata.count
        l, local, pdf = draw_mixed(rng, frame, local_view, alpha, choice, image, pick)
        value = np.zeros_like(n)
        rows = np.flatnonzero((local[:, 2] > 0.0) & (pdf > 0.0))
        value[rows] = reflected(rows, l[rows]) / pdf[rows, None]
        lit = rows[np.any(value[rows] > 0.0, axis=1)]
        value[lit[~visible(lit, l[lit])]] = 0.0
        total += value
    return total / samples
