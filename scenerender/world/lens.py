"""The filmed camera: when the shutter is open and where on the lens each sub-frame of a
frame looks from (docs/scene-notes.md#a-filmed-camera-bloom-motion-blur-depth-of-field).

A frame with ``camera.shutter`` or ``camera.aperture`` is the mean, in linear light, of
sub-frames: each evaluates the scene at a time inside the shutter interval and, with an
aperture, moves the eye to a point on the lens disc and shears the view so the focus
plane stays where it was. Everything here is float64 and needs no GL.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from scenerender.world.camera import CameraState
from scenerender.world.settings import DATA_MODES

MILLIMETRE = 1e-3  # the lens takes scene units as metres


@dataclass(frozen=True)
class FilmSample:
    """One sub-frame: ``time_offset`` seconds from the frame's time; ``lens``: a point
    (x, y) on the unit disc, or None for a pinhole."""

    time_offset: float
    lens: tuple | None


@dataclass(frozen=True)
class Film:
    """What a run's camera films with. shutter: the open fraction of the frame interval;
    aperture: the f-number or None; sensor_width: millimetres; samples: sub-frames a frame."""

    shutter: float
    aperture: float | None
    sensor_width: float
    samples: int

    @classmethod
    def of(cls, camera_spec, samples: int, lens_by_sub_frames: bool = True,
           shutter_by_sub_frames: bool = True) -> "Film | None":
        """The film of a ``camera:`` spec (None: no spec); None where neither a shutter nor
        a lens filmed by sub-frames (``lens_by_sub_frames``: not the gather blur;
        ``shutter_by_sub_frames``: not the velocity blur) is set, so such a scene renders
        as it always did."""
        aperture = camera_spec.aperture if camera_spec is not None and lens_by_sub_frames else None
        shutter = camera_spec.shutter if camera_spec is not None and shutter_by_sub_frames else 0.0
        if camera_spec is None or (shutter == 0.0 and aperture is None):
            return None
        return cls(shutter, aperture, camera_spec.sensor_width, samples)

    def describe(self) -> str:
        """As "12 sub-frames a frame (shutter 0.5, f/0.95)"."""
        parts = ([f"shutter {self.shutter:g}"] if self.shutter > 0 else []) + (
            [f"f/{self.aperture:g}"] if self.aperture is not None else [])
        return f"{self.samples} sub-frames a frame ({', '.join(parts)})"

    @classmethod
    def of_world(cls, world) -> "Film | None":
        """The film a render of ``world`` uses: none in the data modes (a mean depth is no depth)."""
        if world.settings.mode in DATA_MODES:
            return None
        settings = world.settings
        return cls.of(world.spec.camera, settings.film_samples, settings.depth_of_field == "sub_frames",
                      settings.motion_blur == "sub_frames")

    def samples_over(self, frame_interval: float) -> list[FilmSample]:
        """The sub-frames of one frame (``frame_interval`` = 1 / fps seconds)."""
        return film_samples(self.samples, self.shutter * frame_interval, self.aperture is not None)


GOLDEN_ANGLE = math.pi * (3.0 - math.sqrt(5.0))


def radical_inverse(index: int, base: int) -> float:
    """``index``'s digits in ``base`` mirrored about the point: the van der Corput sequence."""
    result, scale = 0.0, 1.0 / base
    while index > 0:
        index, digit = divmod(index, base)
        result += digit * scale
        scale /= base
    return result


def shutter_times(count: int) -> np.ndarray:
    """(count,) float64 offsets in units of the open interval, centred on 0: one in each of
    ``count`` equal slices, spread so that their mean (0) and variance (1/12) are a uniform
    interval's exactly (the slices' middles alone have (1 - 1/count^2) / 12, which blurs a
    moving edge over sqrt(1 - 1/count^2) of its path); every offset stays inside
    (-1/2, 1/2). One time is the instant at the centre."""
    middles = (np.arange(count) + 0.5) / count - 0.5
    return middles if count == 1 else middles * (count / math.sqrt(count * count - 1.0))


def lens_points(count: int) -> np.ndarray:
    """(count, 2) float64 points of the unit disc whose mean (0, 0) and second moments
    (E[x^2] = E[y^2] = 1/4, E[xy] = 0) are the uniform disc's exactly, so that the blur of
    ``count`` sub-frames has the thin lens's width and centre at every count.

    A Vogel spiral (radius sqrt((k + 1/2) / count), k golden angles round) has the disc's
    mean squared radius but is neither centred nor isotropic; moved onto its centroid and
    stretched by (4 C)^(-1/2) (C its covariance) it is both, and stays inside the disc
    (largest radius 0.9993 up to 1024 points). One point is the lens's centre; two cannot
    be isotropic, so they are a centred pair with the disc's mean squared radius."""
    k = np.arange(count)
    radius, angle = np.sqrt((k + 0.5) / count), k * GOLDEN_ANGLE
    points = np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=1)
    points -= points.mean(axis=0)
    if count < 3:
        squared = float(np.mean(np.sum(points * points, axis=1)))
        return points * math.sqrt(0.5 / squared) if squared > 0.0 else points
    values, vectors = np.linalg.eigh(points.T @ points / count)
    return points @ (vectors @ np.diag(0.5 / np.sqrt(values)) @ vectors.T)


def film_samples(count: int, open_seconds: float, lens: bool) -> list[FilmSample]:
    """``count`` sub-frames: times over the open shutter centred on the frame time
    (shutter_times), in the order of the van der Corput sequence so that the times do not
    follow the lens points (lens_points, which run outwards along their spiral)."""
    slices = np.argsort([radical_inverse(k, 2) for k in range(count)], kind="stable")
    order = np.empty(count, dtype=int)
    order[slices] = np.arange(count)
    times = shutter_times(count) * open_seconds
    points = lens_points(count) if lens else None
    return [FilmSample(float(times[order[k]]), None if points is None else (float(points[k, 0]), float(points[k, 1])))
            for k in range(count)]


def lens_radius(camera: CameraState, aperture: float, focus_distance: float, sensor_width_mm: float) -> float:
    """The aperture's radius in scene units (metres) for a thin lens focused at
    ``focus_distance`` whose image of the sensor spans the camera's field of view.

    The sensor sits at the image distance v = w / (2 tan(horizontal fov / 2)) behind the
    lens (w its width), and focusing there on a plane at S makes the focal length
    f = v S / (v + S) (1/f = 1/v + 1/S); the aperture's diameter is f / N."""
    half_width = math.tan(math.radians(camera.fov) / 2.0) * camera.aspect
    image_distance = sensor_width_mm * MILLIMETRE / (2.0 * half_width)
    focal_length = image_distance * focus_distance / (image_distance + focus_distance)
    return focal_length / aperture / 2.0


def through_lens(camera: CameraState, point: tuple, radius: float, focus_distance: float) -> CameraState:
    """``camera`` looking from ``point`` (on the unit disc) of a lens of ``radius``: the eye
    moved in the view plane by radius * point, and the projection sheared so that the
    plane at ``focus_distance`` in front projects where it did (an off-axis frustum).
    A point at distance z then lands radius * |point| * (1/focus - 1/z) * P[0,0] away in
    normalised device units: averaged over the disc, the thin lens's circle of confusion."""
    shift = np.array([point[0], point[1]]) * radius
    eye = camera.position + shift[0] * camera.right + shift[1] * camera.up
    shear = np.eye(4)
    shear[0, 2] = -shift[0] / focus_distance  # x + dx (-z) / S: the focus plane keeps its place
    shear[1, 2] = -shift[1] / focus_distance
    return replace(camera, position=eye, projection=camera.projection @ shear)
