"""A frame's lights and shadow views packed as the lighting shaders read them.

Two arrays: the light structs of shaders/lighting/lights.glsl (one array per light type)
and the ShadowView structs of shaders/lighting/shadows.glsl. Light ``i`` of
``World.lights`` is ``FrameState.lights[i]``, owns the atlas tiles ``atlas.tiles[i]`` and
the views ``FrameState.shadow_views[i]``, which start at ``first_view[i]`` in the view
array: one index throughout. Positions and views are relative to the frame's camera.

Packing is CPU work with no GL; the renderer uploads the result into the buffers of the
graph's ``lights`` input before the passes run (GraphRenderer.import_frame).
"""
from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

from scenerender.world.frame import FrameState
from scenerender.world.light_states import CONE_FALLOFFS, area_axes
from scenerender.world.shadows import AtlasLayout, first_shadow_views

# The binding points of the light arrays and the shadow views, as uniform blocks and as
# storage buffers (the two binding namespaces are separate).
LIGHT_BINDING = 0
SHADOW_VIEW_BINDING = 1


@dataclass(frozen=True)
class PackedLights:
    """lights: the light arrays, std140 / std430 alike (every member a vec4).
    views: the ShadowView structs, shadowed lights in light order.
    first_view: per light, the index of its first view in ``views``, or -1."""

    lights: bytes
    views: bytes
    first_view: tuple


def pack_lights(frame: FrameState, atlas: AtlasLayout | None) -> PackedLights:
    """The lights and shadow views of ``frame``, relative to its camera; ``atlas`` is the
    run's atlas layout."""
    return pack_lights_from(frame.lights, frame.shadow_views, frame.camera.position, atlas)


def pack_lights_from(lights: list, shadow_views: dict, origin: np.ndarray, atlas: AtlasLayout | None) -> PackedLights:
    """``lights`` (world.light_states, one per World.lights) and ``shadow_views`` (light
    index -> its views, shadowed lights only) packed relative to the world point ``origin``
    (float64 (3,)): the camera's position for the camera's passes, another fixed point for
    passes drawn from elsewhere (passes/indirect.py)."""
    views, first_view = _pack_shadow_views(lights, shadow_views, origin, atlas)
    return PackedLights(_pack_light_arrays(lights, origin, first_view), views, first_view)


def _pack_shadow_views(lights: list, shadow_views: dict, origin: np.ndarray,
                       atlas: AtlasLayout | None) -> tuple[bytes, tuple]:
    """ShadowView structs (see shaders/lighting/shadows.glsl), shadowed lights in light
    order, and where each light's start (world.shadows.first_shadow_views, as the
    shaders' compile-time constants have them)."""
    first_view = first_shadow_views([light.definition for light in lights])
    rows = []
    if atlas is not None:
        to_world = np.eye(4)
        to_world[:3, 3] = origin  # origin-relative -> absolute world
        for light_index in sorted(shadow_views):
            settings = lights[light_index].definition.shadow
            for view in shadow_views[light_index]:
                rows.append(_shadow_view_row(view, to_world, settings, atlas.pages[view.tile.page]))
    if not rows:
        return np.zeros(4, dtype=np.float32).tobytes(), first_view
    return np.asarray(rows, dtype=np.float32).tobytes(), first_view


def _pack_light_arrays(lights: list, cam: np.ndarray, first_view: tuple) -> bytes:
    """std430 light arrays in type order (see shaders/lighting/lights.glsl), positions
    relative to ``cam``."""
    dirs, points, spots, areas = [], [], [], []
    for light, first in zip(lights, first_view):
        shadow = [float(first), 0.0, 0.0, 0.0]
        color = [*light.color, 0.0]
        size = light.definition.size  # 0 for a point: the bytes lights always had
        if light.definition.area:
            areas.append(_area_light_row(light, cam, color, shadow))
        elif light.kind == "directional":
            dirs.append([*light.direction, size, *color, *shadow])
        elif light.kind == "point":
            points.append([*(light.position - cam), inverse_range(light.definition), *color,
                           *light.definition.attenuation, size, *shadow])
        else:
            spots.append([*(light.position - cam), inverse_range(light.definition), *light.direction, 0.0, *color,
                          *light.definition.attenuation, size, light.cos_inner, light.cos_outer,
                          CONE_FALLOFFS.index(light.definition.cone_falloff), 0.0,
                          *shadow])
    parts = [np.asarray(group, dtype=np.float64).reshape(-1) for group in (dirs, points, spots, areas) if group]
    parts.append(np.zeros(4))  # lights_end
    return np.concatenate(parts).astype(np.float32).tobytes()


def inverse_range(definition) -> float:
    """1 / the light's range (KHR_lights_punctual), 0 where it has none: position.w of a
    point or spot light (shaders/lighting/lights.glsl, range_window)."""
    return 0.0 if definition.range is None else 1.0 / definition.range


def _area_light_row(light, cam: np.ndarray, color: list, shadow: list) -> list:
    """One AreaLight (shaders/lighting/lights.glsl): centre and shape (0 rectangle, 1 disk),
    facing direction and soft-shadow size, the two half axes, colour, shadow."""
    definition = light.definition
    u, v = area_axes(light.direction)
    half_u, half_v = definition.extent
    shape = 0.0 if definition.kind == "rect" else 1.0
    return [*(light.position - cam), shape, *light.direction, definition.size, *(u * half_u), 0.0,
            *(v * half_v), 0.0, *color, *shadow]


def _shadow_view_row(view, to_world: np.ndarray, settings, page_size) -> np.ndarray:
    """One ShadowView as 36 float64s (see shaders/lighting/shadows.glsl); page_size:
    (width, height) of the atlas page holding the view's tile.

    Everything the lookup needs per fragment is folded into one matrix here, once per
    frame: camera-relative world -> (page u * w, page v * w, linear depth, w), so the
    shader does one matrix product instead of a view, a projection and a tile transform.
    """
    width, height = page_size
    tile = view.tile
    to_light = view.view @ to_world
    clip = view.projection @ to_light
    origin = np.array([tile.x / width, tile.y / height])
    extent = np.array([tile.size / width, tile.size / height])
    to_atlas = np.empty((4, 4))
    to_atlas[:2] = 0.5 * extent[:, None] * clip[:2] + (origin + 0.5 * extent)[:, None] * clip[3]
    depth_range = view.far - view.near
    to_atlas[2] = (-to_light[2] - view.near * np.array([0.0, 0.0, 0.0, 1.0])) / depth_range
    to_atlas[3] = clip[3]
    light_position = np.linalg.inv(to_light)[:3, 3]  # the light's eye, camera-relative
    return np.concatenate([
        to_atlas.T.reshape(-1),
        [*light_position, 1.0 if view.radial else 0.0],
        [*origin, *(origin + extent)],
        [view.near, 1.0 / depth_range, *shadow_bias_texels(settings)],
        [1.0 / width, 1.0 / height, settings.pcf, 0.0],
        _texel_world_size(view),
    ])


@dataclass(frozen=True)
class _VisibilityMapSettings:
    """The shadow settings of the environment's visibility maps: one bilinear tap each."""

    pcf: int = 2
    bias: float = 0.0
    slope_bias: float = 0.0


def environment_view_uniforms(views, camera_position: np.ndarray, page_size: tuple) -> tuple[bytes, bytes, bytes]:
    """The environment's visibility maps (world.environment_visibility) as the shader reads
    them (shaders/lighting/environment_visibility.glsl): each view's camera-relative world
    -> (map u, v, linear depth) matrix, its (texel world size, 1 / depth range,
    constant bias, slope bias) and its tile (min u, v, max u, v), float32 bytes of K of each.

    Only the matrices' translation follows the camera: the rest is made once per list of
    views (they stay the same object while the casters stand still), which takes a static
    scene's frame 0.4 ms less of Python (16 views)."""
    to_map, params, tiles = _environment_view_constants(views, tuple(page_size))
    camera_relative = to_map.copy()  # world -> map, times the translation camera-relative -> world
    camera_relative[:, :, 3] += to_map[:, :, :3] @ np.asarray(camera_position, dtype=np.float64)
    return np.transpose(camera_relative, (0, 2, 1)).astype(np.float32).tobytes(), params, tiles


_VIEW_CONSTANTS: OrderedDict = OrderedDict()  # (id(views), page size) -> (views, what they give)
_VIEW_CONSTANTS_KEPT = 8  # renderers in one process each keep theirs (the benchmarks alternate several)


def _environment_view_constants(views, page_size: tuple) -> tuple[np.ndarray, bytes, bytes]:
    """((K, 4, 4) float64 world -> map matrices, the params' and tiles' float32 bytes) of
    ``views``, remembered for the last few lists of views (kept alive with their entry, so
    an id is never another list's)."""
    key = (id(views), page_size)
    found = _VIEW_CONSTANTS.get(key)
    if found is not None and found[0] is views:
        _VIEW_CONSTANTS.move_to_end(key)
        return found[1]
    rows = np.asarray([_shadow_view_row(view, np.eye(4), _VisibilityMapSettings(), page_size) for view in views])
    # the row's parts: to_atlas (0-15, transposed), depth (24-27: near, 1 / range, biases), texel (32-35)
    params = np.stack([rows[:, 33], rows[:, 25], rows[:, 26], rows[:, 27]], axis=1)
    made = (np.transpose(rows[:, :16].reshape(-1, 4, 4), (0, 2, 1)).copy(), params.astype(np.float32).tobytes(),
            rows[:, 20:24].astype(np.float32).tobytes())
    _VIEW_CONSTANTS[key] = (views, made)
    while len(_VIEW_CONSTANTS) > _VIEW_CONSTANTS_KEPT:
        _VIEW_CONSTANTS.popitem(last=False)
    return made


# The constant depth bias every lookup gets, in shadow texels: covers the depth a texel's
# centre and a point elsewhere in it can differ by on a surface facing the light.
BASE_BIAS_TEXELS = 0.5


def shadow_bias_texels(settings) -> tuple[float, float]:
    """(constant, slope) depth bias in shadow texels at the receiver (see
    shaders/lighting/shadows.glsl): the built-in amounts plus the light's ``bias`` and
    ``slope_bias``. The slope term covers the filter's reach, pcf / 2 texels, and at least
    the one texel a single bilinear tap reaches (pcf 1 takes one tap, as pcf 2 does)."""
    return BASE_BIAS_TEXELS + settings.bias, 0.5 * max(settings.pcf, 2) + settings.slope_bias


def _texel_world_size(view) -> list:
    """World size of one shadow-map texel: (per unit distance, constant, 0, 0).

    Perspective views (spot, cube faces) grow with distance from the light; orthographic
    views (directional) have one size everywhere.
    """
    p = view.projection
    if p[3, 3] == 0.0:  # perspective: x_ndc = p00 * x / -z
        return [2.0 / (p[0, 0] * view.tile.size), 0.0, 0.0, 0.0]
    return [0.0, 2.0 / (p[0, 0] * view.tile.size), 0.0, 0.0]
