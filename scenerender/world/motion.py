"""Where each surface point is when the shutter opens and when it closes: the screen-space
motion a velocity-buffer blur smears along (``render.motion_blur: velocity``;
docs/scene-notes.md, "Motion blur along a velocity buffer").

For every object, two matrices take a camera-relative world point as the frame shows it to
clip space at the shutter's opening and at its closing: the point is carried back to the
object's own space by the inverse of its transform at the frame's time, out again by its
transform at that instant, and projected by that instant's camera. Composed in float64
from the world's tracks; only the products are rounded for the GPU. No GL here.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenerender.world.settings import DATA_MODES


@dataclass(frozen=True)
class ShutterMotion:
    """open, close: (N, 4, 4) float64, one per object of ``World.objects``: a camera-relative
    world point at the frame's time -> clip space at the shutter's opening, at its closing.
    sky_open, sky_close: (4, 4) a direction (w = 0) -> clip space then: the skybox, infinitely
    far, moves only as the camera turns."""

    open: np.ndarray
    close: np.ndarray
    sky_open: np.ndarray
    sky_close: np.ndarray

    def same_as(self, other) -> bool:
        return isinstance(other, ShutterMotion) and all(
            np.array_equal(getattr(self, name), getattr(other, name))
            for name in ("open", "close", "sky_open", "sky_close"))


def blurs_by_velocity(world) -> bool:
    """Whether ``world`` films its shutter by the velocity blur: a shutter is open, the
    setting asks for it, and the output is a colour (a blurred depth is no depth)."""
    camera = world.spec.camera
    return (camera is not None and camera.shutter > 0.0 and world.settings.motion_blur == "velocity"
            and world.settings.mode not in DATA_MODES)


def world_to_clip(camera) -> np.ndarray:
    """(4, 4) float64 world -> clip of ``camera`` (world.camera.CameraState)."""
    view = np.eye(4)
    view[:3, :3] = camera.rotation
    view[:3, 3] = -camera.rotation @ camera.position
    return camera.projection @ view


def translation(offset: np.ndarray) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, 3] = offset
    return matrix


def carried(object_matrix_then: np.ndarray, object_matrix_now: np.ndarray) -> np.ndarray:
    """The world motion of an object's points from now to then: M_then M_now^-1 (the
    identity where its transform is singular now: a point of a zero-scaled object is
    nowhere to move from)."""
    try:
        return object_matrix_then @ np.linalg.inv(object_matrix_now)
    except np.linalg.LinAlgError:
        return np.eye(4)


def placement(obj, t: float) -> np.ndarray:
    """The world matrix of ``obj``'s first instance at ``t`` (the identity where it has none)."""
    matrices = obj.matrices(t)
    return matrices[0] if len(matrices) else np.eye(4)


def shutter_motion(objects, time: float, open_seconds: float, origin: np.ndarray, camera_at) -> ShutterMotion:
    """The motion of ``objects`` (world RenderObjects) over a shutter open ``open_seconds``
    centred on ``time``, for points given relative to ``origin`` (the frame camera's
    position); ``camera_at(t)``: the camera at ``t``. The first instance's motion (the
    object's transform, and a glTF part's node motion) stands for every instance's:
    instances that move apart by their own tracks blur as the first does."""
    opening, closing = time - open_seconds / 2.0, time + open_seconds / 2.0
    to_world = translation(origin)
    camera_open, camera_close = camera_at(opening), camera_at(closing)
    clip_open, clip_close = world_to_clip(camera_open), world_to_clip(camera_close)
    opens, closes = [], []
    for obj in objects:
        now = placement(obj, time)
        opens.append(clip_open @ carried(placement(obj, opening), now) @ to_world)
        closes.append(clip_close @ carried(placement(obj, closing), now) @ to_world)
    empty = np.zeros((0, 4, 4))
    return ShutterMotion(np.array(opens) if opens else empty, np.array(closes) if closes else empty,
                         camera_open.view_proj_relative(), camera_close.view_proj_relative())
