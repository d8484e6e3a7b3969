"""What the page asks to see, and what it is told about the camera.

A ``View`` is one frame of the scene seen in one render mode, from the scene's own camera
or from a camera the page placed; ``overrides`` turns it into ``--set`` strings, so the
preview changes a scene exactly as the command line does.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# The settings the preview lowers unless the command line gives its own: the image size
# (the scene's shape, made to fit 320x240) and MSAA (one sample). Everything else renders
# as the scene says.
PREVIEW_FIT = (320, 240)
PREVIEW_SAMPLES = 1

# A placed camera replaces the scene's aim: these keys would fight position/target.
AIM_KEYS_CLEARED = ("yaw", "pitch", "intrinsics", "pose")


@dataclass(frozen=True)
class PlacedCamera:
    """A camera the page placed: ``position`` and ``target`` (3 floats each, world units)
    and ``fov`` (vertical, degrees)."""

    position: tuple[float, float, float]
    target: tuple[float, float, float]
    fov: float

    @classmethod
    def parse(cls, text: str) -> "PlacedCamera":
        """'px,py,pz,tx,ty,tz,fov' (the page's query value) -> PlacedCamera; ValueError
        for anything else (wrong count, not finite, fov outside the scene's 0.1..179)."""
        values = [float(part) for part in text.split(",")]
        if len(values) != 7 or not all(math.isfinite(v) for v in values):
            raise ValueError(f"expected 7 finite numbers, got {text!r}")
        fov = values[6]
        if not 0.1 <= fov <= 179:
            raise ValueError(f"fov must be within 0.1..179, got {fov:g}")
        return cls(tuple(values[0:3]), tuple(values[3:6]), fov)

    def overrides(self) -> list[str]:
        return [f"camera.position={_vector(self.position)}", f"camera.target={_vector(self.target)}",
                f"camera.fov={_number(self.fov)}"] + [f"camera.{key}=null" for key in AIM_KEYS_CLEARED]


@dataclass(frozen=True)
class View:
    """One frame (``frame`` >= 0) in render mode ``mode`` (None: the scene's own), from
    ``camera`` (None: the scene's own camera)."""

    frame: int = 0
    mode: str | None = None
    camera: PlacedCamera | None = None

    def scene_key(self) -> tuple:
        """Views with the same key share one loaded scene and renderer (only the frame differs)."""
        return (self.mode, self.camera)

    def overrides(self) -> list[str]:
        out = [] if self.mode is None else [f"render.mode={self.mode}"]
        return out + ([] if self.camera is None else self.camera.overrides())


@dataclass(frozen=True)
class PreviewQuality:
    """How preview frames are lowered: ``fit`` (width, height) the frame is shrunk into,
    keeping the scene's shape (None: the scene's own size); ``samples`` MSAA samples (None:
    the scene's own)."""

    fit: tuple[int, int] | None = PREVIEW_FIT
    samples: int | None = PREVIEW_SAMPLES

    @classmethod
    def for_options(cls, size_given: bool, samples_given: bool) -> "PreviewQuality":
        """The command line's own --size or --samples (or --set of either) stands."""
        return cls(None if size_given else PREVIEW_FIT, None if samples_given else PREVIEW_SAMPLES)

    def size_for(self, scene_size: tuple[int, int]) -> tuple[int, int] | None:
        """The preview frame's (width, height) for a scene of ``scene_size``; None where
        it is the scene's own (a scene smaller than ``fit`` is not enlarged)."""
        if self.fit is None:
            return None
        width, height = scene_size
        scale = min(self.fit[0] / width, self.fit[1] / height, 1.0)
        return max(1, round(width * scale)), max(1, round(height * scale))


def camera_from_record(record: dict, target_hint=None) -> dict:
    """The page's camera from a cameras.json record (``Renderer.camera_record``):
    ``{"position": [3], "target": [3], "fov": degrees or None}``, floats.

    ``target_hint``: (3,) the scene's own target at that time, or None; a camera aimed by
    yaw/pitch or a pose gets a target one scene-centre distance (at least 1) ahead."""
    world_to_camera = np.asarray(record["world_to_camera"]["opengl"], dtype=np.float64)
    rotation, translation = world_to_camera[:3, :3], world_to_camera[:3, 3]
    position = -rotation.T @ translation
    forward = -rotation[2]  # OpenGL cameras look down their -Z
    if target_hint is not None:
        target = np.asarray(target_hint, dtype=np.float64)
    else:
        target = position + forward * max(1.0, float(np.linalg.norm(position)))
    fov = None
    if "K" in record:
        focal_y = float(record["K"][1][1])
        fov = math.degrees(2.0 * math.atan(record["height"] / (2.0 * focal_y)))
    return {"position": _rounded(position), "target": _rounded(target), "fov": None if fov is None else round(fov, 3)}


def camera_yaml(camera: dict) -> str:
    """``camera: {position: [...], target: [...], fov: N}`` to paste into a scene file."""
    fov = "" if camera.get("fov") is None else f", fov: {_number(camera['fov'])}"
    return f"camera: {{position: {_vector(camera['position'])}, target: {_vector(camera['target'])}{fov}}}"


def _rounded(values) -> list[float]:
    return [round(float(v), 4) + 0.0 for v in values]  # + 0.0: no "-0.0" in the YAML


def _number(value: float) -> str:
    return f"{round(float(value), 3) + 0.0:g}"  # millimetres are close enough to place a camera


def _vector(values) -> str:
    return "[" + ", ".join(_number(v) for v in values) + "]"
