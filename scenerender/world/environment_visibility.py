"""How much of the environment light the scene blocks at a surface, CPU side. No GL.

The environment image is split into K regions by median cut (Debevec, "A median cut
algorithm for light probe sampling", 2005): the region holding the most of the measure is
cut across its longer side (its width taken at its middle row's latitude) where half its
measure lies on each side, until there are K. The measure is half power (channel mean x
solid angle), half solid angle, each as a share of the whole: by power alone a bright
patch takes most directions and leaves the dim horizon and ground, which light the lower
half of a resting object, one or two. Each region becomes one direction (its
power-weighted centroid) with a weight (its share of the image's power, whatever the cut
shared out). Each direction gets an orthographic shadow map over the casters' footprint,
as a directional light's (world.shadows), on one depth texture of K tiles; the shader
(shaders/lighting/environment_visibility.glsl) turns the lookups into the fraction of the
light that reaches a point:

    V_d = sum_k w_k max(N.l_k, 0) s_k / sum_k w_k max(N.l_k, 0)
    V_s = sum_k w_k max(N.l_k, 0) D(N.h_k) s_k / sum_k w_k max(N.l_k, 0) D(N.h_k)

(s_k: 1 lit, 0 shadowed; D: GGX of the surface's roughness, at least the directions'
spacing), which scale the split sum's diffuse and specular terms. A point no direction
is blocked at gets exactly 1, so a convex object alone is not darkened by itself.

Where the directions are shared out over pixel blocks, each region is cut once more
(region_halves): two maps a region, one looked up in each block, the halves taking turns
from block to block, so that a region's hard shadow edge becomes two edges of half the
step each, which the blocks' blur mixes (the blotches on a ground beside objects, where
32 directions' shadows end one by one: benchmarks/quality/sky_contact.md).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from scenerender.world.environment_light import area_average, equirect_directions, texel_solid_angles
from scenerender.world.shadows import Tile, directional_rotation, directional_view

CUT_WIDTH = 128  # the image is area-averaged to at most this wide before the cut
MAX_TEXTURE_SIDE = 16384  # what every GL 4.3 device offers (world.directional_views)
AREA_SHARE = 0.5  # the cuts share out this much solid angle beside power (see median_cut)
MAX_MAPS = 64  # the shaders' arrays of maps are no longer (the scene's visibility_directions: at most 64)
# A region's halves' maps, each of this share of visibility_map_size a side (320 of 512):
# what a frame's lookups read costs on llvmpipe more than their count: against 32 whole
# maps of 512, 64 maps of 512 made the visibility pass 1.23x as long on the quality scene
# (256x192, process CPU), 64 of 362 (a direction's texels, shared) 1.07-1.08x, of 320
# 1.03x, with the contact as close to the reference (benchmarks/quality/sky_contact.md:
# the ground within 10 cm of a box -1.6 % at 362, -1.0 % at 320)
HALF_MAP_SIDE = 0.625


def median_cut(image: np.ndarray, count: int, area_share: float = AREA_SHARE,
               halves: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """((count x halves, 3) unit directions in the image's frame, (count x halves,) weights
    summing to 1): the centroids and power shares of ``count`` regions of about equal
    measure (the module's docstring; ``area_share`` 0 is Debevec's equal power); with
    ``halves`` 2, each region cut once more at its measure's median, direction k + count
    the second half of region k's (a region too small to cut: itself twice, each of half
    its power)."""
    small = area_average(np.asarray(image, dtype=np.float64), CUT_WIDTH)
    while small.shape[0] * small.shape[1] < count:  # a tiny image: texels enough for every region
        small = np.repeat(np.repeat(small, 2, axis=0), 2, axis=1)
    height, width = small.shape[:2]
    area = np.broadcast_to(texel_solid_angles(height, width), (height, width))
    power = np.maximum(small.mean(axis=2), 0.0) * area
    if not np.any(power > 0.0):
        power = area.copy()
    # what the cuts share out: power, and with ``area_share`` of it solid angle
    measure = (1.0 - area_share) * power / power.sum() + area_share * area / area.sum()
    regions = [(0, height, 0, width)]
    while len(regions) < count:
        cuttable = sorted((r for r in regions if r[1] - r[0] > 1 or r[3] - r[2] > 1),
                          key=lambda r: -measure[r[0]:r[1], r[2]:r[3]].sum())
        if not cuttable:
            break
        for region in cuttable[:count - len(regions)]:
            regions.remove(region)
            regions.extend(_cut(region, measure, height))
    if halves == 2:
        regions = _halved(regions, measure, height)
    directions = equirect_directions(height, width)
    found_directions, weights = [], []
    for top, bottom, left, right in regions:
        p = power[top:bottom, left:right]
        total = p.sum()
        d = (directions[top:bottom, left:right] * (p if total > 0 else np.ones_like(p))[..., None]).sum(axis=(0, 1))
        found_directions.append(d / max(np.linalg.norm(d), 1e-12))
        weights.append(total / regions.count((top, bottom, left, right)))  # a region kept whole shares it
    weights = np.asarray(weights)
    return np.asarray(found_directions), weights / weights.sum()


def _halved(regions: list, measure: np.ndarray, height: int) -> list:
    """Each of ``regions`` cut in two (_cut): the first halves in the regions' order, then
    the second halves; a region of one texel stays whole, its power split between both."""
    cut = [_cut(r, measure, height) if r[1] - r[0] > 1 or r[3] - r[2] > 1 else [r, r] for r in regions]
    return [first for first, _ in cut] + [second for _, second in cut]


def _cut(region: tuple, power: np.ndarray, height: int) -> list:
    """``region`` (top, bottom, left, right) in two, across its longer side, at its power's median."""
    top, bottom, left, right = region
    middle = math.sin((top + bottom) / 2.0 / height * math.pi)  # a row's width shrinks towards the poles
    across_columns = (right - left) * middle >= (bottom - top) and right - left > 1 or bottom - top == 1
    p = power[top:bottom, left:right]
    profile = p.sum(axis=0) if across_columns else p.sum(axis=1)
    cumulative = np.cumsum(profile)
    at = int(np.searchsorted(cumulative, cumulative[-1] / 2.0)) + 1
    at = min(max(at, 1), len(profile) - 1)
    if across_columns:
        return [(top, bottom, left, left + at), (top, bottom, left + at, right)]
    return [(top, top + at, left, right), (top + at, bottom, left, right)]


def visibility_tiles(count: int, size: int, halves: int = 1, max_side: int = MAX_TEXTURE_SIDE) -> tuple[tuple, list]:
    """((width, height) of the depth texture, [Tile] per map): ``count`` x ``halves`` tiles
    of ``size`` texels, or HALF_MAP_SIDE of it where each region has two halves
    (region_halves), halved until the texture fits ``max_side``, in the grid of least area,
    the squarer of two equal ones."""
    count *= halves
    size = size if halves == 1 else int(size * HALF_MAP_SIDE)
    columns = min(range(1, count + 1), key=lambda c: (c * math.ceil(count / c), abs(c - math.ceil(count / c))))
    rows = math.ceil(count / columns)
    while max(columns, rows) * size > max_side and size > 16:
        size //= 2
    tiles = [Tile((k % columns) * size, (k // columns) * size, size) for k in range(count)]
    return (columns * size, rows * size), tiles


@dataclass(frozen=True)
class EnvironmentViews:
    """The visibility maps at one instant: ``views`` one ShadowView per direction,
    ``directions`` (K, 3) the world directions towards the light, ``weights`` (K,) their
    power shares."""

    views: list
    directions: np.ndarray
    weights: np.ndarray

    def same_as(self, other) -> bool:
        return (isinstance(other, EnvironmentViews) and len(self.views) == len(other.views)
                and all(a.same_as(b) for a, b in zip(self.views, other.views))
                and np.array_equal(self.directions, other.directions) and np.array_equal(self.weights, other.weights))


def environment_views(directions: np.ndarray, weights: np.ndarray, to_image: np.ndarray, tiles: list, casters,
                      everything) -> EnvironmentViews:
    """One orthographic ShadowView per direction (image frame, (K, 3)), turned into the
    world (``to_image``: world -> image), over the casters' whole footprint."""
    world_directions = directions @ to_image  # (to_image.T @ d) for each d
    if casters is None or everything is None:
        casters = everything = np.array([[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]])
    # to_image turns about +Y, which a view's rotation keeps up: the image frame's
    # rotations, made once, then turned (rather than K look_rotations a frame)
    rotations = view_rotations(directions) @ to_image
    views = [directional_view(rotation, casters, everything, tile) for rotation, tile in zip(rotations, tiles)]
    return EnvironmentViews(views, world_directions, weights)


@lru_cache(maxsize=4)
def _view_rotations(key: bytes, count: int) -> np.ndarray:
    directions = np.frombuffer(key, dtype=np.float64).reshape(count, 3)
    return np.stack([directional_rotation(-d) for d in directions])


def view_rotations(directions: np.ndarray) -> np.ndarray:
    """(K, 3, 3) world -> view rotations of shadow views looking along -``directions``
    (the light travelling from them), in the image's frame."""
    d = np.ascontiguousarray(directions, dtype=np.float64)
    return _view_rotations(d.tobytes(), len(d))


def interleave_pattern(count: int, interleave: int) -> tuple[int, int]:
    """(N, lookups a pixel) of ``count`` directions shared out over N x N blocks, asked
    ``interleave``: pixel (x, y) of the block, i = x % N + N (y % N), looks up directions
    i, i + N^2, i + 2 N^2 ... (shaders/post/environment_visibility.frag). N is no more than
    sqrt(count), so every pixel has one; N 1: each pixel looks up all of them as it shades."""
    n = max(1, min(interleave, math.isqrt(count)))
    return n, place_lookups((0, 0), n, count)  # the block's first pixel has the most


def region_halves(count: int, interleave: int, redrawn: bool = False) -> int:
    """How many maps each of ``count`` regions gets, asked ``interleave``: 2 where the
    directions are shared out over blocks (interleave_pattern's N above 1), both halves of
    every region fit in MAX_MAPS and the maps are drawn once (not ``redrawn`` every frame,
    as where a caster moves: twice the maps are twice the draws a frame, 1.09x a frame of
    the quality scene with one box moving), else 1. A pixel looks up one half of each of
    its regions, the two taking turns from block to block
    (shaders/post/environment_visibility.frag), so a region's hard shadow is two shadows
    half as strong, mixed by the blur, rather than one: the blotches beside an object
    where each direction's shadow ends (benchmarks/quality/sky_contact.md)."""
    n, _ = interleave_pattern(count, interleave)
    return 2 if n > 1 and 2 * count <= MAX_MAPS and not redrawn else 1


def place_lookups(place: tuple, interleave: int, count: int) -> int:
    """How many of ``count`` directions the pixels at ``place`` (x, y) of the
    ``interleave`` x ``interleave`` block look up: i, i + N^2, ... below the count, i = x + N y."""
    return len(range(place[0] + interleave * place[1], count, interleave * interleave))
