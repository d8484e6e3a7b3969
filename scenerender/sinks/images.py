"""Image sequences: PNG, JPG, TGA (Pillow) and EXR (OpenEXR, linear float)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from scenerender.sinks.base import FrameSink, atomic_path

SUFFIXES = {"png": ".png", "jpg": ".jpg", "tga": ".tga", "exr": ".exr"}
# zlib level 6 is Pillow's default; level 1 is about twice as fast to write for frames
# a few percent larger. Frame sequences are throughput-bound, so they use the fast level.
PNG_COMPRESS_LEVEL = 1


def frame_name_pattern(pattern: str | None, frame_count: int) -> str:
    """The stem pattern for frame files. The default pads the number to at least four
    digits and to the digits of the last frame, so names always sort in frame order."""
    if pattern is not None:
        return pattern
    digits = max(4, len(str(max(frame_count - 1, 0))))
    return "frame_{frame:0" + str(digits) + "d}"


class ImageSequenceSink(FrameSink):
    """One file per frame in ``folder``, named by ``pattern`` (``{frame}`` is the index)."""

    def __init__(self, folder: Path, fmt: str, pattern: str, quality: int = 90):
        self.folder = Path(folder)
        self.fmt = fmt
        self.pattern = pattern
        self.quality = quality
        self.needs_linear = fmt == "exr"
        self.written = 0

    def path_for(self, index: int) -> Path:
        return self.folder / (self.pattern.format(frame=index) + SUFFIXES[self.fmt])

    def is_complete(self, index: int) -> bool:
        """True when the frame's file exists and reads back as a whole image."""
        path = self.path_for(index)
        if not path.is_file() or path.stat().st_size == 0:
            return False
        if self.fmt == "exr":
            return _exr_readable(path)
        from PIL import Image

        try:  # decode it all: a header-only check accepts a JPEG or TGA cut in half
            with Image.open(path) as image:
                image.load()
        except Exception:  # any decoding failure means "not complete"
            return False
        return True

    def write(self, frame) -> None:
        target = self.path_for(frame.index)
        with atomic_path(target) as temp:
            if self.fmt == "exr":
                write_exr(temp, frame.linear)
            else:
                write_image(temp, frame.pixels, self.fmt, self.quality)
        self.written += 1

    def describe(self) -> str:
        return str(self.folder)


def write_image(path: Path, pixels: np.ndarray, fmt: str, quality: int = 90) -> None:
    """(H, W, 3) uint8 -> an image file of ``fmt`` ("png", "jpg", "tga")."""
    from PIL import Image

    image = Image.fromarray(np.ascontiguousarray(pixels, dtype=np.uint8), "RGB")
    if fmt == "png":
        image.save(path, format="PNG", compress_level=PNG_COMPRESS_LEVEL)
    elif fmt == "jpg":
        image.save(path, format="JPEG", quality=int(quality), subsampling=0 if quality >= 90 else 2)
    elif fmt == "tga":
        image.save(path, format="TGA", compression="tga_rle")
    else:
        raise ValueError(f"not an image format: {fmt}")


def write_exr(path: Path, linear: np.ndarray) -> None:
    """(H, W, 3) float32 linear RGB -> a ZIP-compressed 32-bit float EXR."""
    import OpenEXR

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": np.ascontiguousarray(linear, dtype=np.float32)}) as exr:
        exr.write(str(path))


def _exr_readable(path: Path) -> bool:
    import OpenEXR

    try:
        with OpenEXR.File(str(path)) as exr:
            return "RGB" in exr.channels() or "R" in exr.channels()
    except Exception:
        return False
