"""Directional shadow maps that stay put for the whole run.

A directional light's view normally follows the camera: it covers the casters' footprint
only where the camera sees receivers (world.shadows), so its texels are as small as the
visible region allows, and the map is redrawn whenever the camera moves. Where nothing
but the camera moves, one view over the casters' whole footprint serves every frame: its
map is drawn once, and its shadows do not crawl as the camera moves. It is chosen when a
map of at most ``MAX_GROWTH`` times the light's size (and ``MAX_FIXED_SIZE``), over the
whole footprint, has texels no larger than the camera-following map's in any frame of the
animation (judged on up to ``SAMPLED_FRAMES`` frames spread over it); the map gets that
size.

The showcase's sun: its camera-following view spans 22-29 m across the orbit, the whole
footprint 42 m, so a 3904 px map drawn once replaces a 2048 px map redrawn every frame
(6.5-9 ms of each 640x480 frame on llvmpipe).

With render.indirect every directional light that does not move with the camera stays
put over the whole footprint, whatever the sizes: the probes see all of the scene, also
what the camera does not, and their direct light must be shadowed there too (and the bake
reads the views: a view that followed the camera would bake again every frame). The map
keeps the size the comparison gives it within MAX_GROWTH times the light's, or that. A
directional light that moves, or whose casters move, has its view fitted every frame to
the casters' whole footprint too (whole_footprint), never to the camera's: fitted to the
camera, the probes saw unshadowed sunlight wherever the camera did not look (the interior
example with its sun turning: 57 % brighter than with it still, in its first frame).
"""
from __future__ import annotations

import math

import numpy as np

from scenerender.world.camera import CameraRig
from scenerender.world.frame_inputs import camera_fitted_inputs, whole_footprint
from scenerender.world.shadows import directional_half_width, directional_rotation, visible_region
from scenerender.world.transforms import union_bounds

# A fixed map may be at most this many times the light's map size per side (4x the texels
# and memory); beyond that, following the camera gives finer shadows for less.
MAX_GROWTH = 2.0
# Frames the comparison looks at, evenly spread over the animation (on the showcase's and
# the foggy road's orbits, 24 give the sizes all their frames give).
SAMPLED_FRAMES = 24
# Fixed map sizes are rounded up to a multiple of this many texels.
SIZE_STEP = 64
# and are at most this: a page then stays within the 16384 texels every GL 4.3 device
# offers, with room for another map beside it (beyond it the atlas would halve every map).
MAX_FIXED_SIZE = 8192


def fixed_view_sizes(world, aspect: float) -> dict:
    """{index in world.lights: map size} of the directional lights whose view stays put
    for the run (see the module's docstring); ``aspect`` is the image's width / height."""
    whole_scene = whole_footprint(world)
    if world.output.frame_count < 2 and not whole_scene:
        return {}  # one frame draws every map once: the camera-fitted view is the finer
    # directional views that change only because the camera moves: not the light, not the
    # objects (a light attached to the camera turns with it); for the probes also those
    # that stay where a still camera puts them
    kept = (("follows camera",), ()) if whole_scene else (("follows camera",),)
    candidates = []
    for index, views in camera_fitted_inputs(world).shadow_views.items():
        light = world.lights[index]
        if light.kind == "directional" and not light.attach_camera and views.because in kept:
            candidates.append(index)
    if not candidates:
        return {}
    everything, casters = _still_bounds(world)
    if everything is None or casters is None:
        return {}
    # what the camera sees of the scene in each sampled frame (frames seeing none of it
    # shadow nothing)
    regions = [region for region in (visible_region(camera, everything)
                                     for camera in _sampled_cameras(world, aspect, everything)) if region is not None]
    sizes = {}
    for index in candidates:
        light = world.lights[index]
        rotation = directional_rotation(np.asarray(light.direction(0.0), dtype=np.float64))
        whole = directional_half_width(rotation, casters, None)
        halves = (directional_half_width(rotation, casters, region) for region in regions)
        followed = [half for half in halves if half is not None]
        if not followed:
            if whole_scene:
                sizes[index] = light.shadow.size
            continue
        size = SIZE_STEP * math.ceil(light.shadow.size * whole / min(followed) / SIZE_STEP)
        largest = min(MAX_GROWTH * light.shadow.size, MAX_FIXED_SIZE)
        if size <= largest:
            sizes[index] = max(size, light.shadow.size)
        elif whole_scene:
            sizes[index] = max(int(largest), light.shadow.size)
    return sizes


def _still_bounds(world) -> tuple:
    """(2, 3) bounds of every visible object and of the visible shadow casters, or None."""
    placed = [(obj, obj.world_bounds(obj.matrices(0.0))) for obj in world.objects if obj.visible(0.0)]
    return (union_bounds([bounds for _, bounds in placed]),
            union_bounds([bounds for obj, bounds in placed if obj.cast_shadows]))


def _sampled_cameras(world, aspect: float, bounds: np.ndarray) -> list:
    """The camera at up to SAMPLED_FRAMES frames spread over the animation."""
    count = max(world.output.frame_count, 1)
    sampled = min(count, SAMPLED_FRAMES)
    indices = sorted({round(k * (count - 1) / max(sampled - 1, 1)) for k in range(sampled)})
    rig = CameraRig(world.spec.camera, aspect, size=world.settings.size, file_camera=world.file_camera)
    rig.first_bounds = bounds
    return [rig.at(index / float(world.output.fps), bounds) for index in indices]
