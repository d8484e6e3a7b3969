"""The comparison benchmark's scene, defined once for all three renderers.

A textured 4,096-triangle torus knot, a 900-triangle vase, a ground plane, one shadowed
directional light, one point light without shadows, and a camera orbiting once in 120
frames. ``make_assets.py`` writes the OBJ/MTL/PNG files and scenerender's YAML from this;
the pyrender and hand-written moderngl runners load the same OBJ files with trimesh and
follow the same camera path.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

SCENE_DIR = Path(__file__).resolve().parent.parent / "scenes" / "bench"
SCENE_YAML = SCENE_DIR / "bench.yaml"
MESHES = {  # name -> (OBJ file, world position)
    "knot": ("knot.obj", (0.0, 1.1, 0.0)),
    "vase": ("vase.obj", (1.6, 0.0, 0.9)),
    "ground": ("ground.obj", (0.0, 0.0, 0.0)),
}
FRAMES = 120
FPS = 30
FOV_Y = 50.0  # degrees
ORBIT_RADIUS = 6.0
ORBIT_HEIGHT = 2.6
TARGET = (0.0, 0.8, 0.0)
SUN_DIRECTION = (-0.45, -0.8, -0.35)  # the way the light travels
SUN_COLOR = (1.0, 0.96, 0.9)
SUN_SHADOW_SIZE = 2048
POINT_POSITION = (-1.8, 1.6, 1.4)
POINT_COLOR = (1.0, 0.7, 0.4)
AMBIENT = (0.2, 0.22, 0.26)
BACKGROUND = (0.5, 0.6, 0.75)


def camera_position(frame: int) -> np.ndarray:
    """(3,) float64: the orbit, one turn over FRAMES frames."""
    angle = 2.0 * math.pi * frame / FRAMES
    return np.array([ORBIT_RADIUS * math.sin(angle), ORBIT_HEIGHT, ORBIT_RADIUS * math.cos(angle)])


def look_at(eye, target=TARGET, up=(0.0, 1.0, 0.0)) -> np.ndarray:
    """(4, 4) float64 world -> view matrix (camera looks down -Z)."""
    eye, target, up = (np.asarray(v, dtype=np.float64) for v in (eye, target, up))
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = right, true_up, -forward
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def perspective(fov_y: float, aspect: float, near: float, far: float) -> np.ndarray:
    """(4, 4) float64 OpenGL projection."""
    f = 1.0 / math.tan(math.radians(fov_y) / 2.0)
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = f / aspect, f
    m[2, 2], m[2, 3] = (far + near) / (near - far), 2.0 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def mesh_path(name: str) -> Path:
    return SCENE_DIR / MESHES[name][0]
