"""Shadow-map planning: the atlas layout (once per run) and each frame's light views.

Shadow maps live in depth textures called *pages*; directional and spot lights take one
square tile of a page, point lights six (one per cube face). One page holds the maps drawn
once per run, another the maps redrawn every frame (views that follow the camera or moving
objects), so the shaders bind at most two textures however many lights cast shadows, and
there is no cap on shadowed lights beyond page size. Splitting by redraw keeps each
frame's clear a clear of a whole texture: Mesa llvmpipe clears a 2048 x 2048 depth texture
in about 1.4 ms, but a 2048 x 2048 region of a larger one in 5-10 ms (it draws the region),
and cached maps are never touched.

Depth in a page is linear: (d - near) / (far - near), where d is the distance along the
light's axis (directional, spot) or from the light (point). The shader's bias is in world
units, a multiple of the shadow texel's world size at the receiver, so it means the same
at any scene scale (shaders/lighting/shadows.glsl).

A directional light's view covers only what can both be seen and be shadowed: the part of
the scene's bounds inside the camera's frustum, within the casters' footprint. Its texels
are then as small as the visible region allows, not as the whole scene forces.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scenerender.world.camera import look_rotation, orthographic, perspective
from scenerender.world.facing import hidden_from_eye, hidden_side
from scenerender.world.transforms import box_corners

# Cube faces as (forward, up) pairs; a face is chosen by the major axis of light->point.
CUBE_FACES = (
    ((1, 0, 0), (0, -1, 0)), ((-1, 0, 0), (0, -1, 0)),
    ((0, 1, 0), (0, 0, 1)), ((0, -1, 0), (0, 0, -1)),
    ((0, 0, 1), (0, -1, 0)), ((0, 0, -1), (0, -1, 0)),
)
# their world -> view rotations, worked out once rather than for every light every frame
CUBE_FACE_ROTATIONS = tuple(look_rotation(forward, up) for forward, up in CUBE_FACES)
# A cube face's frustum is a little wider than 90 degrees so filter taps near the face's
# edge still land inside its tile.
CUBE_FACE_FOV = 95.0
SPOT_MARGIN_DEGREES = 2.0


@dataclass(frozen=True)
class Tile:
    """A square region of a page in texels: x, y (lower-left) and size; page: which."""

    x: int
    y: int
    size: int
    page: int = 0


@dataclass(frozen=True)
class AtlasLayout:
    """pages: (width, height) of each page texture; tiles[light index]: the tiles of the
    shadowed light ``World.lights[light index]``."""

    pages: tuple
    tiles: dict

    def page_of(self, light_index: int) -> int:
        return self.tiles[light_index][0].page


def plan_atlas(lights: list, max_size: int = 16384, warn=None, redrawn: frozenset = frozenset(),
               sizes: dict | None = None) -> AtlasLayout | None:
    """Pack the tiles of every shadowed light of ``lights`` (World.lights) into rows
    (largest first); None when no shadows.

    redrawn: indices of the lights whose views change during the run; their tiles get a
    page of their own, after the page of the others (see the module's docstring).
    sizes: {light index: tile size} where it is not the light's own map size.
    If a page would exceed ``max_size`` the tiles are halved until it fits, with a warning.
    """
    sizes = sizes or {}
    requests = [(i, sizes.get(i, light.shadow.size), view_count(light))
                for i, light in enumerate(lights) if light.shadow is not None]
    if not requests:
        return None
    groups = [group for group in ([r for r in requests if r[0] not in redrawn], [r for r in requests if r[0] in redrawn])
              if group]
    scale = 1
    while True:
        packed = [_pack([(i, max(16, size // scale), n) for i, size, n in group], page)
                  for page, group in enumerate(groups)]
        if max(max(size) for size, _ in packed) <= max_size:
            break
        scale *= 2
    if scale > 1 and warn is not None:
        warn(f"shadow maps reduced to 1/{scale} of their size to fit a {max_size}px atlas")
    tiles = {owner: owned for _, page_tiles in packed for owner, owned in page_tiles.items()}
    return AtlasLayout(tuple(size for size, _ in packed), tiles)


def _pack(requests, page: int) -> tuple:
    """((width, height), {owner: [Tile]}) of one page: tiles in rows, largest first, at
    the width (a multiple of the largest tile) that gives the smallest page (a page is
    cleared whole, so its area is time)."""
    tiles_wanted = [(size, i) for i, size, n in requests for _ in range(n)]
    tiles_wanted.sort(key=lambda item: -item[0])
    largest = tiles_wanted[0][0]
    widths = [largest * k for k in range(1, len(tiles_wanted) + 1)]
    packed = [_rows(tiles_wanted, width, page) for width in widths]
    return min(packed, key=lambda p: (p[0][0] * p[0][1], max(p[0])))


def _rows(tiles_wanted, width: int, page: int) -> tuple:
    tiles: dict = {}
    x = y = row_height = 0
    used = 0
    for size, owner in tiles_wanted:
        if x + size > width:
            x, y, row_height = 0, y + row_height, 0
        tiles.setdefault(owner, []).append(Tile(x, y, size, page))
        x += size
        used = max(used, x)
        row_height = max(row_height, size)
    return (used, y + row_height), tiles


@dataclass(frozen=True)
class ShadowView:
    """One rendered shadow view at one instant.

    view:       (4, 4) float64 world -> light view.
    projection: (4, 4) float64 light view -> clip.
    near, far:  the linear depth range stored in the atlas.
    radial:     depth is the distance to the light (point lights) rather than along -Z.
    tile:       where it lives in the atlas.
    """

    view: np.ndarray
    projection: np.ndarray
    near: float
    far: float
    radial: bool
    tile: Tile

    @property
    def eye(self) -> np.ndarray:
        """(3,) float64 world position of the view's eye."""
        return -self.view[:3, :3].T @ self.view[:3, 3]

    def same_as(self, other: "ShadowView") -> bool:
        """Whether ``other`` is the same view, to the bit."""
        return (self.tile == other.tile and self.near == other.near and self.far == other.far
                and self.radial == other.radial and np.array_equal(self.view, other.view)
                and np.array_equal(self.projection, other.projection))


# lights whose shadow is a cube map from their centre, radial depth: point lights, and the
# one-sided area lights (rect, disk), whose light reaches all of the half space before them
CUBE_MAP_KINDS = ("point", "rect", "disk")


def view_count(light) -> int:
    """How many shadow views a shadowed light (LightDef) has: six cube faces for a point
    light, one for the others."""
    return 6 if light.kind in CUBE_MAP_KINDS else 1


def first_shadow_views(lights: list) -> tuple:
    """Per light of ``lights`` (World.lights), the index of its first view in the frame's
    list of shadow views, or -1 without shadows: the shadowed lights' views in light order,
    as the lighting shaders read them (rendering.light_buffers)."""
    firsts, count = [], 0
    for light in lights:
        firsts.append(count if light.shadow is not None else -1)
        count += view_count(light) if light.shadow is not None else 0
    return tuple(firsts)


def atlas_page_name(page: int) -> str:
    """The graph's name for atlas page ``page`` (its sampler is "u_" + this name)."""
    return "shadow_atlas" if page == 0 else f"shadow_atlas_{page + 1}"


def back_page_name(page: int) -> str:
    """The graph's name for the back faces of atlas page ``page`` (the casters' far side as
    the lights see it, render.shadows.casters: solid; its sampler is "u_" + this name)."""
    return "shadow_back" if page == 0 else f"shadow_back_{page + 1}"


def hidden_from_light(view: ShadowView, winding: int, bounds: np.ndarray) -> str | None:
    """The faces of a closed surface (world bounds (2, 3)) that ``view`` cannot see, which
    its shadow map may skip (world.facing), or None. An orthographic (directional) view's
    depth range spans every caster, so it sees every closed surface from outside."""
    if view.projection[3, 3] == 1.0:
        return hidden_side(winding)
    return hidden_from_eye(winding, bounds, view.eye, -view.view[2, :3], view.near, view.projection)


def light_views(state, tiles: list, casters: np.ndarray | None, everything: np.ndarray | None,
                visible: np.ndarray | None = None) -> list[ShadowView]:
    """The views of one shadowed light ``state`` (a LightState), fitted to the scene.

    casters: (2, 3) bounds of shadow-casting objects; everything: (2, 3) bounds of all;
    visible: (K, 3) float64 points whose hull is the receivers the camera sees
    (``visible_region``), or None to cover the casters' whole footprint.
    """
    if casters is None or everything is None:
        casters = everything = np.array([[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]])
    if state.kind == "directional":
        return [_directional(state.direction, casters, everything, tiles[0], visible, state.definition.size)]
    if state.kind == "spot":
        return [_spot(state, everything, tiles[0])]
    return [_cube_face(state.position, rotation, everything, tile)
            for rotation, tile in zip(CUBE_FACE_ROTATIONS, tiles)]


def _view(rotation: np.ndarray, eye: np.ndarray) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = rotation
    m[:3, 3] = -rotation @ eye
    return m


def _directional(direction, casters, everything, tile, visible=None, size: float = 0.0) -> ShadowView:
    return directional_view(directional_rotation(direction), casters, everything, tile, visible, size)


def directional_view(rotation, casters, everything, tile, visible=None, size: float = 0.0) -> ShadowView:
    """An orthographic view across a directional light (its ``directional_rotation``)
    covering the casters' footprint where the camera sees receivers (``visible``); depth
    spans all casters and receivers so nothing between them is clipped. ``size``: tan of a
    sun's half angle (0 for a point), whose penumbra reaches past the footprint by up to
    size x the scene's depth across the light: the view grows by that much, so the
    penumbra's outer half is drawn rather than cut off."""
    c = box_corners(casters) @ rotation.T
    a = box_corners(everything) @ rotation.T
    footprint = _footprint(rotation, casters, visible)
    if footprint is None:  # no visible receiver can be shadowed: any small view will do
        seen = visible @ rotation[:2].T
        footprint = seen.min(axis=0), seen.min(axis=0) + 1e-3
    lo, hi = footprint
    if size > 0.0:
        spread = size * float(a[:, 2].max() - a[:, 2].min())
        lo, hi = lo - spread, hi + spread
    center = (lo + hi) / 2.0
    half = _half_width(lo, hi)
    # the eye sits on the view's centre line level with the casters' centre, so the
    # matrices' translations stay small wherever the scene is (float32 on the GPU)
    eye_depth = float(c[:, 2].mean())
    eye = rotation.T @ np.array([center[0], center[1], eye_depth])
    depth_all = eye_depth - np.concatenate([c[:, 2], a[:, 2]])
    margin = 0.01 * max(float(depth_all.max() - depth_all.min()), 1e-3)
    near, far = float(depth_all.min()) - margin, float(depth_all.max()) + margin
    projection = orthographic(2.0 * half, 1.0, near, far)
    return ShadowView(_view(rotation, eye), projection, near, far, False, tile)


def _footprint(rotation: np.ndarray, casters: np.ndarray, visible: np.ndarray | None) -> tuple | None:
    """(lo, hi) (2,) of the casters' footprint across the light (light view x, y), within
    the visible region's where given; None when the two do not overlap."""
    c = box_corners(casters) @ rotation.T
    lo, hi = c[:, :2].min(axis=0), c[:, :2].max(axis=0)
    if visible is not None and len(visible):
        seen = visible @ rotation[:2].T
        lo, hi = np.maximum(lo, seen.min(axis=0)), np.minimum(hi, seen.max(axis=0))
        if np.any(hi <= lo):
            return None
    return lo, hi


def _half_width(lo: np.ndarray, hi: np.ndarray) -> float:
    """Half the side of the square view over a footprint, with a 2 % margin."""
    return max(float((hi - lo).max()) / 2.0, 1e-4) * 1.02


def directional_rotation(direction) -> np.ndarray:
    """(3, 3) world -> view rotation of a directional light's shadow view."""
    return look_rotation(direction, (0.0, 1.0, 0.0))


def directional_half_width(rotation: np.ndarray, casters: np.ndarray, visible: np.ndarray | None) -> float | None:
    """Half the side of the view a directional light (``directional_rotation``) fits over
    the casters' footprint, within the ``visible`` region's when given, in world units;
    None where no visible receiver can be shadowed."""
    footprint = _footprint(rotation, casters, visible)
    return None if footprint is None else _half_width(*footprint)


def visible_region(camera, bounds: np.ndarray | None) -> np.ndarray | None:
    """(K, 3) float64 world points whose convex hull is ``bounds`` (2, 3) clipped to the
    camera's frustum, or None when the two do not meet.

    The vertices of the intersection of two convex solids are where the edges of each
    cross the other: each solid's 12 edges are clipped to the other solid (in clip space
    for the frustum, where its planes are linear), and the clipped ends kept.
    """
    if bounds is None:
        return None
    clip = camera.view_proj_relative()
    inverse = np.linalg.inv(clip)
    cube = np.array([[x, y, z, 1.0] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    frustum = cube @ inverse.T
    frustum = frustum[:, :3] / frustum[:, 3:4] + camera.position
    frustum_starts, frustum_ends = frustum[_BOX_EDGES[:, 0]], frustum[_BOX_EDGES[:, 1]]
    box = box_corners(bounds)
    box_starts, box_ends = box[_BOX_EDGES[:, 0]], box[_BOX_EDGES[:, 1]]

    def inside_frustum(p):
        h = np.concatenate([p - camera.position, np.ones(p.shape[:-1] + (1,))], axis=-1) @ clip.T
        w = h[..., 3:4]
        return np.concatenate([w - h[..., :3], w + h[..., :3]], axis=-1)

    points = np.concatenate([
        _clip_segments(frustum_starts, frustum_ends, lambda p: np.concatenate([p - bounds[0], bounds[1] - p], axis=-1)),
        _clip_segments(box_starts, box_ends, inside_frustum)])
    return points if len(points) else None


# The 12 edges of a box given as 8 corners indexed by (x, y, z) bits (x slowest).
_BOX_EDGES = np.array([(a, a | bit) for a in range(8) for bit in (1, 2, 4) if not a & bit])


def _clip_segments(starts: np.ndarray, ends: np.ndarray, constraints) -> np.ndarray:
    """(2M, 3): the two ends of each segment starts[i]..ends[i] (each (N, 3)) cut to where
    every value of ``constraints(points)`` (..., C) is >= 0 (each linear along a segment),
    for the M segments that keep a part."""
    f0, f1 = constraints(starts), constraints(ends)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = f0 / (f0 - f1)  # where a constraint's value crosses 0
    enter = np.max(np.where(f0 < 0, t, 0.0), axis=1, initial=0.0)
    leave = np.min(np.where((f0 >= 0) & (f1 < 0), t, 1.0), axis=1, initial=1.0)
    kept = ~np.any((f0 < 0) & (f1 < 0), axis=1) & (enter <= leave)
    starts, step = starts[kept], (ends - starts)[kept]
    return np.concatenate([starts + enter[kept, None] * step, starts + leave[kept, None] * step])


def _depth_range(eye: np.ndarray, rotation: np.ndarray, bounds: np.ndarray, radial: bool) -> tuple[float, float]:
    corners = box_corners(bounds) - eye
    if radial:
        far = float(np.linalg.norm(corners, axis=1).max())
    else:
        far = float((-(corners @ rotation[2])).max())
    far = max(far * 1.01, 1e-3)
    return far * 1e-3, far


def _spot(state, everything, tile) -> ShadowView:
    rotation = look_rotation(state.direction, (0.0, 1.0, 0.0))
    near, far = _depth_range(state.position, rotation, everything, radial=False)
    outer = math.degrees(math.acos(min(1.0, max(-1.0, state.cos_outer))))
    fov = min(170.0, 2.0 * outer + SPOT_MARGIN_DEGREES)
    return ShadowView(_view(rotation, state.position), perspective(fov, 1.0, near, far), near, far, False, tile)


def _cube_face(position, rotation, everything, tile) -> ShadowView:
    near, far = _depth_range(position, rotation, everything, radial=True)
    projection = perspective(CUBE_FACE_FOV, 1.0, near, far)
    return ShadowView(_view(rotation, position), projection, 0.0, far, True, tile)
