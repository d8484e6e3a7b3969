"""The camera at one instant: orientation, position and projection, all float64.

Rendering is camera-relative: geometry is uploaded relative to the camera position, so the
view matrix the GPU sees holds only the rotation. That keeps float32 precise however far
from the origin the scene is.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scenerender.world.camera_data import intrinsics_fov, intrinsics_projection, pose_placement
from scenerender.world.transforms import box_corners

# Looking closer than this to `up` (|cos| of the angle) counts as looking along it.
_PARALLEL = 1.0 - 1e-9

# The view direction when there is none to work out (an animated camera passing through
# its target): the default view direction, down -Z.
DEFAULT_FORWARD = np.array([0.0, 0.0, -1.0])


@dataclass(frozen=True)
class CameraState:
    """The camera for one frame.

    position:   (3,) float64 world position.
    rotation:   (3, 3) float64 world -> view rotation; rows are right, up, back (+Z).
    projection: (4, 4) float64 view -> clip (OpenGL conventions, depth -1..1).
    near, far:  clip distances used this frame.
    """

    position: np.ndarray
    rotation: np.ndarray
    projection: np.ndarray
    near: float
    far: float
    fov: float
    aspect: float
    orthographic: bool

    @property
    def forward(self) -> np.ndarray:
        return -self.rotation[2]

    @property
    def right(self) -> np.ndarray:
        return self.rotation[0]

    @property
    def up(self) -> np.ndarray:
        return self.rotation[1]

    def view_proj_relative(self) -> np.ndarray:
        """(4, 4) float64 camera-relative world -> clip: P * R (no translation)."""
        r = np.eye(4)
        r[:3, :3] = self.rotation
        return self.projection @ r


def look_rotation(forward, up) -> np.ndarray:
    """(3, 3) world -> view rotation looking along ``forward`` with ``up`` roughly up.

    When ``forward`` is (anti)parallel to ``up`` the image's up is taken from the direction
    a camera tilting there would face: looking down, the top of the image points to -Z
    (the default view direction); looking up, to +Z. No NaN, no sudden flip. A zero
    ``forward`` (no direction at all) looks along ``DEFAULT_FORWARD``.
    """
    f = unit_direction(forward, DEFAULT_FORWARD)
    u = unit_direction(up, np.array([0.0, 1.0, 0.0]))
    cos = float(np.dot(f, u))
    if abs(cos) > _PARALLEL:
        u = _fallback_up(u, cos)
    right = np.cross(f, u)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, f)
    return np.stack([right, true_up, -f])


def unit_direction(vector, fallback: np.ndarray) -> np.ndarray:
    """``vector`` scaled to length 1, or ``fallback`` where it has no direction (all zeros,
    or not finite). Where the squares in its length underflow to 0 (1e-200) or overflow
    (1e200), it is divided by its largest component first, so the result is never NaN;
    other vectors are divided by their length alone, the same bits as ever."""
    v = np.asarray(vector, dtype=np.float64)
    with np.errstate(over="ignore", under="ignore"):  # both handled below, not warned about
        length = float(np.linalg.norm(v))
    if 0.0 < length < math.inf:
        return v / length
    largest = float(np.max(np.abs(v)))
    if not (0.0 < largest < math.inf):
        return fallback.copy()
    v = v / largest
    return v / np.linalg.norm(v)


def _fallback_up(up: np.ndarray, cos: float) -> np.ndarray:
    """A screen-up direction perpendicular to ``up`` for a camera looking along +-up."""
    reference = np.array([0.0, 0.0, -1.0])
    if abs(np.dot(reference, up)) > 0.9:  # up is itself near Z: use X then
        reference = np.array([1.0, 0.0, 0.0])
    reference = reference - np.dot(reference, up) * up
    reference /= np.linalg.norm(reference)
    # looking down (cos < 0) the image top faces -Z; looking up it faces +Z
    return reference if cos < 0 else -reference


def yaw_pitch_forward(yaw_degrees: float, pitch_degrees: float) -> np.ndarray:
    """FPS-style angles -> unit forward; yaw -90 looks down -Z; pitch clamped to [-89, 89]."""
    pitch = math.radians(min(89.0, max(-89.0, pitch_degrees)))
    yaw = math.radians(yaw_degrees)
    return np.array([math.cos(yaw) * math.cos(pitch), math.sin(pitch), math.sin(yaw) * math.cos(pitch)])


def perspective(fov_degrees: float, aspect: float, near: float, far: float) -> np.ndarray:
    f = 1.0 / math.tan(math.radians(fov_degrees) / 2.0)
    m = np.zeros((4, 4))
    m[0, 0] = f / aspect
    m[1, 1] = f
    m[2, 2] = (far + near) / (near - far)
    m[2, 3] = 2.0 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def orthographic(height: float, aspect: float, near: float, far: float) -> np.ndarray:
    half_h = height / 2.0
    half_w = half_h * aspect
    m = np.eye(4)
    m[0, 0] = 1.0 / half_w
    m[1, 1] = 1.0 / half_h
    m[2, 2] = -2.0 / (far - near)
    m[2, 3] = -(far + near) / (far - near)
    return m


# With float reversed-Z depth near may be this small a fraction of far: it only matters
# when the camera is inside the scene's bounds (no nearest corner in front of it).
FLOAT_DEPTH_MIN_NEAR = 1e-7


def fit_near_far(bounds: np.ndarray | None, position: np.ndarray, rotation: np.ndarray,
                 orthographic_view: bool, max_ratio: float | None = None) -> tuple[float, float]:
    """Clip distances that enclose ``bounds`` (2, 3) seen from the camera.

    The far plane sits just behind the farthest corner; the near plane just before the
    nearest. ``max_ratio``: the largest far / near the depth buffer keeps precise (1e4
    for 24-bit fixed point); None for reversed-Z float depth, where near is bounded only
    by ``FLOAT_DEPTH_MIN_NEAR`` * far.
    """
    if bounds is None:
        return 0.1, 100.0
    corners = box_corners(bounds) - position
    depths = -(corners @ rotation[2])
    far = max(float(depths.max()) * 1.02, 1e-3)
    if orthographic_view:
        extent = max(float(np.linalg.norm(bounds[1] - bounds[0])), 1e-3)
        return min(float(depths.min()), 0.0) - 0.01 * extent, far + 0.01 * extent
    floor = far / max_ratio if max_ratio is not None else far * FLOAT_DEPTH_MIN_NEAR
    near = max(float(depths.min()) * 0.98, floor)
    return near, max(far, near * 1.001)


def framing_position(bounds: np.ndarray, fov_degrees: float, aspect: float,
                     direction=(0.0, 0.45, 1.0)) -> tuple[np.ndarray, np.ndarray]:
    """Where a camera looking at ``bounds``' centre from ``direction`` sees all of it.

    Returns (position, target). The bounding sphere fills the narrower of the two fields of
    view with a small margin.
    """
    center = (bounds[0] + bounds[1]) / 2.0
    radius = max(float(np.linalg.norm(bounds[1] - bounds[0])) / 2.0, 1e-6)
    half_v = math.radians(fov_degrees) / 2.0
    half_h = math.atan(math.tan(half_v) * aspect)
    distance = radius / math.sin(min(half_v, half_h)) * 1.05
    d = np.asarray(direction, dtype=np.float64)
    return center + d / np.linalg.norm(d) * distance, center


class CameraRig:
    """The scene's camera (its ``camera:`` spec, or None for the default that frames the
    scene) at any time, for one aspect ratio. ``first_bounds`` (2, 3), the scene's bounds
    at frame 0, place the default camera and size an orthographic view without ``height``:
    set once, before the first ``at``, so that every frame of a run is framed alike."""

    def __init__(self, spec, aspect: float, max_depth_ratio: float | None = None, size: tuple | None = None,
                 file_camera=None):
        """max_depth_ratio: the cap on far / near of `near/far: auto` (fit_near_far).
        size: the image (width, height) in pixels that `camera.intrinsics` are given in
        (render.size); an image of another size scales them with it. file_camera: the
        glTF file's camera of `camera.from` (world.file_nodes.FileCamera), which places
        the camera and gives its projection."""
        self.spec = spec
        self.file_camera = file_camera
        self.aspect = aspect
        self.size = tuple(size) if size is not None else None
        self.max_depth_ratio = max_depth_ratio
        self.first_bounds = None

    def at(self, t: float, bounds) -> CameraState:
        """The camera at time ``t`` seeing a scene that spans ``bounds`` (2, 3) now."""
        spec = self.spec
        intrinsics = spec.intrinsics if spec is not None else None
        fov = intrinsics_fov(intrinsics, self.size) if intrinsics is not None else spec.fov(t) if spec is not None else 60.0
        file_camera = self.file_camera
        if file_camera is not None:
            fov = file_camera.fov
            position, rotation = file_camera.place(t)
        else:
            position, rotation = self._place(t, fov)
        if file_camera is not None:
            ortho = file_camera.orthographic
        else:
            ortho = spec is not None and spec.projection == "orthographic"
        near, far = fit_near_far(bounds, position, rotation, ortho, self.max_depth_ratio)
        if spec is not None and spec.near != "auto":
            near = spec.near
        if spec is not None and spec.far != "auto":
            far = spec.far
        far = max(far, near * 1.001)
        height = self._ortho_height(t) if ortho else 0.0
        if ortho:
            projection = orthographic(height, self.aspect, near, far)
        elif intrinsics is not None:
            projection = intrinsics_projection(intrinsics, self.size, near, far)
        else:
            projection = perspective(fov, self.aspect, near, far)
        return CameraState(position, rotation, projection, near, far, fov, self.aspect, ortho)

    def _place(self, t: float, fov: float):
        """(position (3,), world -> view rotation (3, 3)) in float64: from `camera.pose`
        where given, else from the position and where it looks."""
        spec = self.spec
        if spec is not None and spec.pose is not None:
            return pose_placement(spec.pose, t)
        up = np.asarray(spec.up if spec is not None else (0.0, 1.0, 0.0), dtype=np.float64)
        position, forward = self._aim(t, fov)
        return position, look_rotation(forward, up)

    def _aim(self, t: float, fov: float):
        """(position (3,), forward (3,)) in float64."""
        spec = self.spec
        framed_position, center = framing_position(self.first_bounds, fov, self.aspect)
        if spec is None:
            return framed_position, center - framed_position
        position = np.asarray(spec.position(t), dtype=np.float64) if spec.position is not None else framed_position
        if spec.yaw is not None or spec.pitch is not None:
            yaw = spec.yaw(t) if spec.yaw is not None else -90.0
            pitch = spec.pitch(t) if spec.pitch is not None else 0.0
            return position, yaw_pitch_forward(yaw, pitch)
        target = np.asarray(spec.target(t), dtype=np.float64) if spec.target is not None else center
        return position, target - position  # zero where they meet: look_rotation has a fallback

    def focus_distance(self, t: float) -> float:
        """Where the lens focuses at ``t``: ``focus_distance``, else the distance to what the
        camera looks at (its target, or the centre the default camera frames)."""
        spec = self.spec
        if spec is not None and spec.focus_distance is not None:
            return float(spec.focus_distance(t))
        _, forward = self._aim(t, spec.fov(t) if spec is not None else 60.0)
        return max(float(np.linalg.norm(forward)), 1e-9)

    def _ortho_height(self, t: float) -> float:
        if self.file_camera is not None:
            return self.file_camera.height
        if self.spec.height is not None:
            return self.spec.height(t)
        lo, hi = self.first_bounds
        return float(np.linalg.norm(hi - lo)) * 1.05
