"""The comparison scene rendered by pyrender 0.1.45 over EGL (optional extra [bench]).

Meshes are loaded with trimesh from the same OBJ files; directional shadows as pyrender
does them (RenderFlags.SHADOWS_DIRECTIONAL); pyrender's offscreen target is always 4x
MSAA. Frames go to the same level-1 PNG writer thread as the hand-written loop.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import parse_args, run_frames  # noqa: E402

import numpy as np  # noqa: E402
import scene_def as S  # noqa: E402

if not hasattr(np, "infty"):  # pyrender 0.1.45 still uses this alias, removed in NumPy 2.0
    np.infty = np.inf


def light_pose(direction) -> np.ndarray:
    """A pose whose -Z axis points along ``direction`` (how pyrender aims lights)."""
    d = np.asarray(direction, dtype=np.float64)
    eye = -d / np.linalg.norm(d)
    up = (0.0, 0.0, 1.0) if abs(eye[1]) > 0.99 else (0.0, 1.0, 0.0)
    return np.linalg.inv(S.look_at(eye, (0.0, 0.0, 0.0), up))


def build_scene():
    import pyrender
    import trimesh

    scene = pyrender.Scene(bg_color=(*S.BACKGROUND, 1.0), ambient_light=S.AMBIENT)
    for name in S.MESHES:
        mesh = trimesh.load(S.mesh_path(name), force="mesh")
        pose = np.eye(4)
        pose[:3, 3] = S.MESHES[name][1]
        scene.add(pyrender.Mesh.from_trimesh(mesh), pose=pose)
    scene.add(pyrender.DirectionalLight(color=S.SUN_COLOR, intensity=3.0), pose=light_pose(S.SUN_DIRECTION))
    point = np.eye(4)
    point[:3, 3] = S.POINT_POSITION
    scene.add(pyrender.PointLight(color=S.POINT_COLOR, intensity=8.0), pose=point)
    return scene


def main() -> None:
    import pyrender

    args = parse_args(__doc__)
    scene = build_scene()
    camera = pyrender.PerspectiveCamera(yfov=np.radians(S.FOV_Y), aspectRatio=args.width / args.height,
                                        znear=0.1, zfar=50.0)
    camera_node = scene.add(camera, pose=np.eye(4))
    renderer = pyrender.OffscreenRenderer(args.width, args.height)
    flags = pyrender.RenderFlags.SHADOWS_DIRECTIONAL

    def render_frame(i):
        scene.set_pose(camera_node, np.linalg.inv(S.look_at(S.camera_position(i))))
        color, _ = renderer.render(scene, flags=flags)
        return color

    run_frames(args, render_frame)
    renderer.delete()


if __name__ == "__main__":
    main()
