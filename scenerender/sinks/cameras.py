"""cameras.json: every frame's camera, beside the frames, for data sets.

``OUT/cameras.json`` beside an image sequence; ``<parent>/<file name>.cameras.json`` beside
a video or a single image (``clip.mp4.cameras.json``). The run manifest holds each finished
frame's camera (run/manifest.py) and this file is written from it whole, so it lists
exactly the frames the output holds, each from the run that made it. One frame::

    {"file": "frame_0003.png", "scene": "walk.yaml", "index": 3, "time": 0.125,
     "width": 640, "height": 480, "projection": "perspective", "near": 0.1, "far": 80.0,
     "K": [[fx, 0, cx], [0, fy, cy], [0, 0, 1]],
     "world_to_camera": {"opencv": 4 x 4, "opengl": 4 x 4}}

An orthographic frame has ``orthographic_height`` (world units) instead of ``K``. The
conventions are written into the file too (``CONVENTIONS``).
"""
from __future__ import annotations

import json
from pathlib import Path

from scenerender.sinks.base import atomic_path, write_file

FORMAT = 1
FOLDER_FILE = "cameras.json"
FILE_SUFFIX = ".cameras.json"
FIELDS = ("file", "scene", "index", "time", "width", "height", "projection", "near", "far", "K",
          "orthographic_height", "world_to_camera")
CONVENTIONS = {
    "pixels": "u right, v down, from the top-left corner of the image; pixel (i, j) has its centre at "
              "(i + 0.5, j + 0.5); a point X in camera coordinates (opencv) lands at K @ X / X[2]",
    "opencv": "camera axes x right, y down, z forward (the direction the camera looks)",
    "opengl": "camera axes x right, y up, z backward (the camera looks down -z)",
    "world_to_camera": "4 x 4, rows first: camera point = M @ [world point, 1]",
    "near_far": "clipping distances along the view axis, in scene units",
}


def cameras_path(target: Path, is_folder: bool) -> Path:
    """Where the cameras of ``target`` (a frame folder, or a video or image file) go."""
    target = Path(target)
    return target / FOLDER_FILE if is_folder else target.parent / f"{target.name}{FILE_SUFFIX}"


def write_cameras(path: Path, frames: list[dict]) -> None:
    """Write ``frames`` (records in frame order) to ``path`` whole, unless it holds them
    already; with no frames, remove the file (an output with no frames has no cameras,
    and an old list would mislead)."""
    if not frames:
        Path(path).unlink(missing_ok=True)
        return
    head = json.dumps({"format": FORMAT, "conventions": CONVENTIONS}, indent=1)
    rows = ",\n".join("  " + json.dumps(_in_order(frame)) for frame in frames)  # one frame a line
    text = head[:-2] + ',\n "frames": [\n' + rows + "\n ]\n}\n"
    data = text.encode("utf-8")
    try:
        if Path(path).read_bytes() == data:  # a run with nothing to do touches no file
            return
    except OSError:
        pass
    with atomic_path(path) as temp:
        write_file(temp, data)


def _in_order(frame: dict) -> dict:
    """``frame``'s keys in FIELDS order (then any others, sorted): the same bytes whether the
    record comes fresh from the renderer or back from the run manifest."""
    known = {key: frame[key] for key in FIELDS if key in frame}
    return {**known, **{key: frame[key] for key in sorted(frame) if key not in known}}
