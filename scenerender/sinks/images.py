"""Image sequences: PNG, JPG, TGA (Pillow) and EXR (OpenEXR, linear float)."""
from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from scenerender.sinks.base import FrameSink, atomic_path, write_file
from scenerender.sinks.names import name_template_problem

SUFFIXES = {"png": ".png", "jpg": ".jpg", "tga": ".tga", "exr": ".exr"}
# the suffixes an `-o` file name may end in, and the format each means
IMAGE_SUFFIX_FORMATS = {".png": "png", ".jpg": "jpg", ".jpeg": "jpg", ".tga": "tga", ".exr": "exr"}
# zlib level, chosen by measurement (showcase frame 30, 640x480, Pillow, one core):
#   level 0: 15.5 ms, 901 KB   level 1: 21.7 ms, 251 KB   level 2: 23.9 ms, 242 KB
#   level 6 (Pillow's default): 75.8 ms, 212 KB            level 9: 795 ms, 201 KB
# Level 1 keeps nearly all of the size gain (3.6x smaller than level 0) for 6 ms more;
# each step beyond costs more time than it saves bytes. Frame sequences are
# throughput-bound, so they use level 1.
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
        problem = name_template_problem(pattern)
        if problem is not None:  # scenes are validated earlier; this guards callers in code
            raise ValueError(f"bad frame name pattern {pattern!r}: {problem}")
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

    def encode_frame(self, frame) -> bytes:
        """The file bytes for ``frame``. Touches no state, so encoder threads may call
        it for several frames at once (see ``sinks.threaded``)."""
        if self.fmt == "exr":
            return encode_exr(frame.linear)
        return encode_image(frame.pixels, self.fmt, self.quality)

    def write(self, frame) -> None:
        """Write ``frame`` whole or not at all; its ``encoded`` bytes, when it carries
        them (a ``ThreadedSink`` encodes ahead), are used as they are."""
        data = getattr(frame, "encoded", None)
        if data is None:
            data = self.encode_frame(frame)
        with atomic_path(self.path_for(frame.index)) as temp:
            write_file(temp, data)
        self.written += 1

    def describe(self) -> str:
        return str(self.folder)


class SingleImageSink(ImageSequenceSink):
    """Exactly one file, ``path`` (``-o still.png`` with a one-frame render), whatever the
    frame's index."""

    def __init__(self, path: Path, fmt: str, quality: int = 90):
        super().__init__(Path(path).parent, fmt, "frame", quality)
        self.path = Path(path)

    def path_for(self, index: int) -> Path:
        return self.path

    def describe(self) -> str:
        return str(self.path)


# Encoders write into memory and the bytes go to disk through write_file: OpenEXR writing
# a file by itself reports no error on a full disk (the EXR is silently cut short).


def write_image(path: Path, pixels: np.ndarray, fmt: str, quality: int = 90) -> None:
    """(H, W, 3) uint8 -> an image file of ``fmt`` ("png", "jpg", "tga")."""
    write_file(path, encode_image(pixels, fmt, quality))


def encode_image(pixels: np.ndarray, fmt: str, quality: int = 90) -> bytes:
    """(H, W, 3) uint8 -> the bytes of an image file of ``fmt`` ("png", "jpg", "tga")."""
    from PIL import Image

    image = Image.fromarray(np.ascontiguousarray(pixels, dtype=np.uint8), "RGB")
    buffer = io.BytesIO()
    if fmt == "png":
        image.save(buffer, format="PNG", compress_level=PNG_COMPRESS_LEVEL)
    elif fmt == "jpg":
        image.save(buffer, format="JPEG", quality=int(quality), subsampling=0 if quality >= 90 else 2)
    elif fmt == "tga":
        image.save(buffer, format="TGA", compression="tga_rle")
    else:
        raise ValueError(f"not an image format: {fmt}")
    return buffer.getvalue()


def write_exr(path: Path, linear: np.ndarray) -> None:
    """(H, W, 3) float32 linear RGB -> a ZIP-compressed 32-bit float EXR file."""
    write_file(path, encode_exr(linear))


def encode_exr(linear: np.ndarray) -> bytes:
    """(H, W, 3) float32 linear RGB -> the bytes of a ZIP-compressed 32-bit float EXR."""
    import OpenEXR

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    buffer = io.BytesIO()
    with OpenEXR.File(header, {"RGB": np.ascontiguousarray(linear, dtype=np.float32)}) as exr:
        exr.write(buffer)
    return buffer.getvalue()


def _exr_readable(path: Path) -> bool:
    import OpenEXR

    try:
        with OpenEXR.File(str(path)) as exr:
            return "RGB" in exr.channels() or "R" in exr.channels()
    except Exception:
        return False
