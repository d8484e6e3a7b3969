"""The two sides of a comparison: one image, a folder of frames, or a video, and the
provenance sidecar written beside each render output.

Frames come out as (H, W, 3) uint8 sRGB. EXR frames hold linear light; they are encoded
with the exact sRGB transfer function (values clipped to 0..1) so that they are judged by
the same rule as every other format, at the 8-bit precision a person sees.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator

import numpy as np

from scenerender.colorspace import srgb_encode
from scenerender.compare.ignore import FILES as IGNORE_FILES
from scenerender.compare.objects import IdMap
from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.json_input import MANIFEST_MAX_BYTES
from scenerender.scene.files import read_json_file
from scenerender.sinks.object_ids import behind_path, ids_path, read_ids, read_names

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tga", ".exr")
VIDEO_SUFFIXES = (".mp4", ".gif")
UNKNOWN = "unknown"


def _bad(path: Path, message: str) -> UserError:
    return UserError(message, SourceLocation(display_path(path)))


@dataclass(frozen=True)
class Provenance:
    """What made one side, from its sidecar; "unknown" where there is none."""

    scenerender: str = UNKNOWN
    gl_renderer: str = UNKNOWN
    gl_version: str = UNKNOWN
    sidecar: str | None = None   # the file it was read from

    def to_json(self) -> dict:
        return {"scenerender": self.scenerender, "gl": {"renderer": self.gl_renderer, "version": self.gl_version},
                "sidecar": self.sidecar}

    def line(self) -> str:
        return f"scenerender {self.scenerender}, GL {self.gl_renderer} ({self.gl_version})"


def sidecar_candidates(path: Path) -> list[Path]:
    """Where the provenance of ``path`` may be written: a folder's own
    ``.scenerender.json``, else that of a video in it (``.<video>.scenerender.json``); for a
    file ``.<name>.scenerender.json`` beside it, else the folder's sidecar (a frame inside a
    rendered folder)."""
    if path.is_dir():
        return [path / ".scenerender.json", *sorted(path.glob(".*.scenerender.json"))]
    return [path.parent / f".{path.name}.scenerender.json", path.parent / ".scenerender.json"]


def read_provenance(path: Path) -> Provenance:
    """The provenance of a render output; a missing or unreadable sidecar gives unknowns
    (a reference made by hand has none, and that must not stop a comparison)."""
    for candidate in sidecar_candidates(path):
        if not candidate.is_file():
            continue
        try:
            data = read_json_file(candidate, "run manifest", MANIFEST_MAX_BYTES)
        except UserError:  # unreadable: as good as absent, like the run that would reuse it
            continue
        if not isinstance(data, dict):
            continue
        gl = data.get("gl") if isinstance(data.get("gl"), dict) else {}
        return Provenance(str(data.get("scenerender", UNKNOWN)), str(gl.get("renderer", UNKNOWN)),
                          str(gl.get("version", UNKNOWN)), str(candidate))
    return Provenance()


# -- reading frames ----------------------------------------------------------------------

def srgb_bytes(linear: np.ndarray) -> np.ndarray:
    """(H, W, 3) float linear light -> (H, W, 3) uint8 with the exact sRGB curve."""
    return np.round(srgb_encode(np.nan_to_num(linear.astype(np.float64))) * 255.0).astype(np.uint8)


def _read_exr(path: Path) -> np.ndarray:
    # the scene layer (pydantic models) costs a quarter second to import: only for EXR frames
    from scenerender.scene.image_files import DEFAULT_MAX_PIXELS
    from scenerender.world.environment_files import read_exr

    return srgb_bytes(read_exr(path, DEFAULT_MAX_PIXELS))


def read_image(path: Path) -> np.ndarray:
    """One image file -> (H, W, 3) uint8 sRGB. Unreadable files are a UserError."""
    try:
        if path.suffix.lower() == ".exr":
            return _read_exr(path)
        from PIL import Image

        with Image.open(path) as image:
            return np.asarray(image.convert("RGB"))
    except UserError:
        raise
    except Exception as exc:  # Pillow and OpenEXR raise many kinds for a broken file
        raise _bad(path, f"cannot read image ({exc})") from None


def video_frames(path: Path) -> Iterator[np.ndarray]:
    """Decode a MP4 or GIF frame by frame -> (H, W, 3) uint8, never the whole video in memory."""
    try:
        if path.suffix.lower() == ".gif":
            from PIL import Image, ImageSequence

            with Image.open(path) as image:
                for frame in ImageSequence.Iterator(image):
                    yield np.asarray(frame.convert("RGB"))
            return
        import imageio_ffmpeg

        reader = imageio_ffmpeg.read_frames(str(path), pix_fmt="rgb24")
        meta = next(reader)
        width, height = meta["size"]
        for raw in reader:
            yield np.frombuffer(raw, np.uint8).reshape(height, width, 3)
    except UserError:
        raise
    except Exception as exc:
        raise _bad(path, f"cannot decode video: {decoder_reason(exc, path)}") from None


# ffmpeg names the cause of a failure to open or decode in a line of its own: "Error opening
# input: <cause>", "Decoding error: <cause>", or in older versions "<file>: <cause>"; lines
# are prefixed by the component speaking ("[in#0 @ 0x55d1...] ").
_FFMPEG_CAUSE = re.compile(r"^(?:Error opening input|Decoding error)[^:]*: (?P<cause>.+)$")
_FFMPEG_SPEAKER = re.compile(r"^(?:\[[^\]]* @ 0x[0-9a-fA-F]+\] )+")


def decoder_reason(exc: Exception, path: Path) -> str:
    """Why ``path`` could not be decoded, in one line. imageio-ffmpeg's errors carry ffmpeg's
    whole stderr (banner, build configuration, stream details) after "=== stderr ===":
    the cause is the one line of it that names one; else imageio-ffmpeg's (or Pillow's) own words."""
    summary, _, log = str(exc).partition("=== stderr ===")
    old_style = f"{path}: "
    for line in log.splitlines():
        line = _FFMPEG_SPEAKER.sub("", line.strip())
        match = _FFMPEG_CAUSE.match(line)
        if match:
            return match["cause"]
        if line.startswith(old_style):
            return line[len(old_style):]
    return " ".join(summary.split()).rstrip(":") or type(exc).__name__


# -- the sides -----------------------------------------------------------------------------

@dataclass
class Side:
    """One side of a comparison. ``kind`` is "image", "folder" or "video"; ``names`` lists
    a folder's frame and video files (sorted) or a single image's name; videos name frames
    by index as they are decoded."""

    path: Path
    kind: str
    names: list[str] = field(default_factory=list)
    provenance: Provenance = field(default_factory=Provenance)
    _object_names: dict | None = field(default=None, repr=False)

    def load(self, name: str) -> np.ndarray:
        return read_image(self.frame_path(name))

    def frame_path(self, name: str) -> Path:
        return self.path / name if self.kind == "folder" else self.path

    def object_ids(self, name: str) -> IdMap | None:
        """Frame ``name``'s object ids (sinks/object_ids.py) with the objects' names, or None
        where the render kept none (videos never do)."""
        if self.kind == "video":
            return None
        ids = read_ids(ids_path(self.frame_path(name)))
        if ids is None:
            return None
        if self._object_names is None:
            self._object_names = read_names(self.frame_path(name).parent)
        behind = read_ids(behind_path(self.frame_path(name)))
        return IdMap(ids, self._object_names, behind if behind is not None and behind.shape == ids.shape else None)

    def to_json(self) -> dict:
        return {"path": str(self.path), "kind": self.kind, "provenance": self.provenance.to_json()}


def is_video_name(name: str) -> bool:
    return Path(name).suffix.lower() in VIDEO_SUFFIXES


def is_frame_file(path: Path) -> bool:
    """An image or video in a folder, not hidden (sidecars and the temporary files of
    unfinished writes start with a dot) and not a reference folder's ignore mask."""
    return (path.is_file() and not path.name.startswith(".") and path.name not in IGNORE_FILES
            and path.suffix.lower() in IMAGE_SUFFIXES + VIDEO_SUFFIXES)


def open_side(path: Path) -> Side:
    """Classify ``path`` as an image, a folder of frames or a video; bad paths are a UserError."""
    path = Path(path)
    if path.is_dir():
        names = sorted(p.name for p in path.iterdir() if is_frame_file(p))
        return Side(path, "folder", names, read_provenance(path))
    if not path.exists():
        raise _bad(path, "no such file or folder")
    suffix = path.suffix.lower()
    if suffix in VIDEO_SUFFIXES:
        return Side(path, "video", [], read_provenance(path))
    if suffix in IMAGE_SUFFIXES:
        return Side(path, "image", [path.name], read_provenance(path))
    raise _bad(path, f"not an image, folder or video (expected {', '.join(IMAGE_SUFFIXES + VIDEO_SUFFIXES)})")
