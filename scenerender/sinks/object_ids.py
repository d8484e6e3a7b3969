"""Where a frame's object ids are kept, and how: ``render --object-ids`` writes them,
``scenerender diff`` reads them (scenerender.compare.objects).

The ids of the frame file ``OUT/frame_0003.png`` (or ``.jpg``, ``.exr``...) are the 16-bit
grayscale PNG ``OUT/.object_ids/frame_0003.png``: per pixel, top row first, the index of
the object it shows in the scene's ``objects`` + 1, 0 for none. ``OUT/.object_ids/objects.json``
names them: ``{"format": 1, "scene": "garden.yaml", "objects": {"1": "ground", ...}}``. The
folder starts with a dot, so nothing that lists frames sees it. A single image ``-o still.png``
keeps its ids the same way, in ``.object_ids/`` beside it.

The layer behind, ``OUT/.object_ids/behind/frame_0003.png`` (same encoding), names the
nearest opaque object at each pixel: where a transparent surface is nearest, the object
seen through it. Renders before it have none: their frames are judged by the first layer.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.json_input import OBJECT_NAMES_MAX_BYTES, parse_json
from scenerender.sinks.base import atomic_path, write_file

FOLDER = ".object_ids"
NAMES_FILE = "objects.json"
BEHIND = "behind"
FORMAT = 1
# ids are 16-bit: object index + 1 must fit, 0 being the background
MAX_OBJECT_IDS = 65535


def ids_path(frame: Path) -> Path:
    """Where the ids of the frame file ``frame`` are kept."""
    frame = Path(frame)
    return frame.parent / FOLDER / (frame.stem + ".png")


def behind_path(frame: Path) -> Path:
    """Where the ids of the nearest opaque surfaces of the frame file ``frame`` are kept."""
    frame = Path(frame)
    return frame.parent / FOLDER / BEHIND / (frame.stem + ".png")


def names_path(folder: Path) -> Path:
    """The objects.json of the frames in ``folder``."""
    return Path(folder) / FOLDER / NAMES_FILE


def read_ids(path: Path) -> np.ndarray | None:
    """The ids in ``path`` as (H, W) uint16, or None when there is no such file or it is
    not a 16-bit grayscale image (then the frame is compared by its colours alone)."""
    from PIL import Image

    try:
        with Image.open(path) as image:
            if image.mode not in ("I;16", "I;16B", "I"):
                return None
            values = np.asarray(image)
    except (OSError, ValueError, SyntaxError):
        return None
    if values.ndim != 2:
        return None
    if values.dtype == np.uint16:  # a 16-bit PNG as written: nothing to check or convert (1080p: 4 MB a map)
        return values
    if values.min(initial=0) < 0 or values.max(initial=0) > MAX_OBJECT_IDS:
        return None
    return values.astype(np.uint16)


def read_names(folder: Path) -> dict:
    """id -> object name from ``folder``'s objects.json; {} when absent or unreadable."""
    data = _read_names_file(names_path(folder))
    objects = data.get("objects") if isinstance(data, dict) else None
    if not isinstance(objects, dict):
        return {}
    try:
        return {int(key): str(value) for key, value in objects.items()}
    except ValueError:  # a key that is not a number
        return {}


def _read_names_file(path: Path):
    """The JSON value of an objects.json (read through the JSON guard), None where there is
    none or it cannot be read."""
    try:
        with open(path, "rb") as stream:
            data = stream.read(OBJECT_NAMES_MAX_BYTES + 1)
        return parse_json(data) if len(data) <= OBJECT_NAMES_MAX_BYTES else None
    except (OSError, ValueError):  # ValueError: json_input.JsonProblem
        return None


def write_names(folder: Path, scene: str, names: dict, option: str = "-o") -> None:
    """Write ``folder``'s objects.json (whole or not at all). Another scene's names there
    are a UserError: two scenes' ids in one folder could not both be named."""
    path = names_path(folder)
    old = _read_names_file(path)
    if isinstance(old, dict) and old.get("scene") not in (None, scene) and any(
            p.name != NAMES_FILE for p in path.parent.iterdir()):
        raise UserError(f"{display_path(path.parent)} holds the object ids of {old.get('scene')}; render "
                        f"{scene} with --object-ids into a folder of its own", SourceLocation(option))
    text = json.dumps({"format": FORMAT, "scene": scene, "objects": {str(k): v for k, v in sorted(names.items())}},
                      indent=1)
    with atomic_path(path, option) as temp:
        write_file(temp, (text + "\n").encode("utf-8"))
