"""Image sequences: PNG, JPG, TGA (Pillow) and EXR (OpenEXR, linear float)."""
from __future__ import annotations

import io
import struct
from pathlib import Path

import numpy as np
from zlib_ng import zlib_ng

from scenerender.sinks.base import FrameSink, atomic_path, make_folders, write_file
from scenerender.sinks.names import name_template_problem
from scenerender.sinks.object_ids import behind_path, ids_path, write_names

SUFFIXES = {"png": ".png", "jpg": ".jpg", "tga": ".tga", "exr": ".exr"}
# the suffixes an `-o` file name may end in, and the format each means
IMAGE_SUFFIX_FORMATS = {".png": "png", ".jpg": "jpg", ".jpeg": "jpg", ".tga": "tga", ".exr": "exr"}
# PNG: every row filtered with "Sub" (each byte less the one a pixel to its left), then
# deflated at level 1 with run-length matching (Z_RLE). Chosen by measurement on
# 640x480 frames, one core, time to encode / file size (with zlib's deflate, before zlib-ng):
#   benchmark scene:  Pillow level 1 (adaptive filters) 13.1 ms / 88 KB;  this 5.4 ms / 74 KB
#   showcase frame:   Pillow level 1                    19.3 ms / 255 KB; this 11.6 ms / 240 KB
# Pillow's level 0 is 5.4 / 9.9 ms but 901 KB; its default level 6 is 75.8 ms / 212 KB on
# the showcase. The "Up" filter is as fast but larger on textured frames (338 KB), and
# "Average" slower. The deflate is zlib-ng's: the same bytes as zlib's with Z_RLE, 2.3x
# sooner (benchmark frames: 1.21 against 2.82 ms; docs/performance.md). The rows are
# filtered in NumPy and the deflate lets go of the GIL, so encoder threads run beside the
# renderer. Frame sequences are throughput-bound: this is their encoder.
PNG_COMPRESS_LEVEL = 1
PNG_STRATEGY = zlib_ng.Z_RLE


def frame_name_pattern(pattern: str | None, frame_count: int) -> str:
    """The stem pattern for frame files. The default pads the number to at least four
    digits and to the digits of the last frame, so names always sort in frame order."""
    if pattern is not None:
        return pattern
    digits = max(4, len(str(max(frame_count - 1, 0))))
    return "frame_{frame:0" + str(digits) + "d}"


class ImageSequenceSink(FrameSink):
    """One file per frame in ``folder``, named by ``pattern`` (``{frame}`` is the index).

    ``object_names`` (id -> name) asks for each frame's object ids too: written beside the
    frame (sinks/object_ids.py) from ``frame.object_ids``, named in objects.json for
    ``scene``. Without it a frame written over one that had ids loses them, so ids never
    describe another render than their frame."""

    is_sequence = True

    def __init__(self, folder: Path, fmt: str, pattern: str, quality: int = 90, object_names: dict | None = None,
                 scene: str = ""):
        problem = name_template_problem(pattern)
        if problem is not None:  # scenes are validated earlier; this guards callers in code
            raise ValueError(f"bad frame name pattern {pattern!r}: {problem}")
        self.folder = self.target = Path(folder)
        self.fmt = fmt
        self.pattern = pattern
        self.quality = quality
        self.needs_linear = fmt == "exr"
        self.object_names = object_names
        self.scene = scene
        self.written = 0

    @property
    def object_ids(self) -> bool:
        """Whether each frame's object ids are written too."""
        return self.object_names is not None

    def path_for(self, index: int) -> Path:
        return self.folder / (self.pattern.format(frame=index) + SUFFIXES[self.fmt])

    def ids_path_for(self, index: int) -> Path | None:
        """Where frame ``index``'s object ids go, when they are written."""
        return ids_path(self.path_for(index)) if self.object_ids else None

    def is_complete(self, index: int) -> bool:
        """True when the frame's file exists and reads back as a whole image."""
        path = self.path_for(index)
        if not path.is_file() or path.stat().st_size == 0:
            return False
        if self.fmt == "exr":
            return _exr_readable(path)
        try:  # decode it all: a header-only check accepts a JPEG or TGA cut in half
            with pillow().open(path) as image:
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
        path = self.path_for(frame.index)
        if self.object_ids:
            if frame.object_ids is None:
                raise ValueError("the sink writes object ids, but the frame has none: render with object_ids=True")
            if self.written == 0:
                write_names(path.parent, self.scene, self.object_names)
            with atomic_path(ids_path(path)) as temp:
                write_file(temp, encode_grey16_png(frame.object_ids))
            self._write_behind(path, getattr(frame, "object_ids_behind", None))
        else:
            ids_path(path).unlink(missing_ok=True)  # another render's ids would misname this frame
            behind_path(path).unlink(missing_ok=True)
        with atomic_path(path) as temp:
            write_file(temp, data)
        self.written += 1

    @staticmethod
    def _write_behind(path: Path, ids) -> None:
        """The layer behind transparent surfaces (sinks/object_ids.py), or none."""
        where = behind_path(path)
        if ids is None:
            where.unlink(missing_ok=True)
            return
        make_folders(where.parent)
        with atomic_path(where) as temp:
            write_file(temp, encode_grey16_png(ids))

    def describe(self) -> str:
        return str(self.folder)


class SingleImageSink(ImageSequenceSink):
    """Exactly one file, ``path`` (``-o still.png`` with a one-frame render), whatever the
    frame's index."""

    is_sequence = False
    keeps_cameras = False  # -o still.png writes exactly that file

    def __init__(self, path: Path, fmt: str, quality: int = 90, object_names: dict | None = None, scene: str = ""):
        super().__init__(Path(path).parent, fmt, "frame", quality, object_names, scene)
        self.path = self.target = Path(path)

    def path_for(self, index: int) -> Path:
        return self.path

    def describe(self) -> str:
        return str(self.path)


# Encoders write into memory and the bytes go to disk through write_file: OpenEXR writing
# a file by itself reports no error on a full disk (the EXR is silently cut short).


def pillow():
    """Pillow's ``Image`` module, imported deliberately late: PNG frames are encoded here
    without it (``encode_png``), and a one-frame render should not pay for its import."""
    from PIL import Image

    return Image


def write_image(path: Path, pixels: np.ndarray, fmt: str, quality: int = 90) -> None:
    """(H, W, 3) uint8 -> an image file of ``fmt`` ("png", "jpg", "tga")."""
    write_file(path, encode_image(pixels, fmt, quality))


def encode_image(pixels: np.ndarray, fmt: str, quality: int = 90) -> bytes:
    """(H, W, 3) uint8 -> the bytes of an image file of ``fmt`` ("png", "jpg", "tga")."""
    pixels = np.ascontiguousarray(pixels, dtype=np.uint8)
    if fmt == "png":
        return encode_png(pixels)
    image = pillow().fromarray(pixels, "RGB")
    buffer = io.BytesIO()
    if fmt == "jpg":
        image.save(buffer, format="JPEG", quality=int(quality), subsampling=0 if quality >= 90 else 2)
    elif fmt == "tga":
        image.save(buffer, format="TGA", compression="tga_rle")
    else:
        raise ValueError(f"not an image format: {fmt}")
    return buffer.getvalue()


def encode_png(pixels: np.ndarray) -> bytes:
    """(H, W, C) uint8, C = 3 (RGB) or 4 (RGBA) -> the bytes of an 8-bit PNG file: one
    IDAT chunk of "Sub"-filtered rows (see PNG_STRATEGY)."""
    height, width, channels = pixels.shape
    deflate = zlib_ng.compressobj(PNG_COMPRESS_LEVEL, zlib_ng.DEFLATED, 15, 9, PNG_STRATEGY)
    return _png_file(pixels.reshape(height, width * channels), width, channels, 8, {3: 2, 4: 6}[channels], deflate)


def encode_grey16_png(values: np.ndarray) -> bytes:
    """(H, W) uint16 -> the bytes of a 16-bit greyscale PNG (object ids: large flat areas,
    so a fast deflate suffices: zlib-ng's level 2, a showcase frame's ids in 0.18 ms and
    9.0 KB, where zlib's level 1 took 0.78 ms and 9.7 KB and zlib-ng's level 1 gives 13 KB)."""
    height, width = values.shape
    rows = np.ascontiguousarray(values, dtype=">u2").view(np.uint8).reshape(height, width * 2)
    return _png_file(rows, width, 2, 16, 0, zlib_ng.compressobj(2))


def _png_file(rows: np.ndarray, width: int, pixel_bytes: int, bit_depth: int, color_type: int, deflate) -> bytes:
    """A PNG of one IDAT chunk from ``rows`` ((H, W * pixel_bytes) uint8, big-endian
    samples), each row "Sub"-filtered: every byte less the one a pixel to its left."""
    height = rows.shape[0]
    filtered = np.empty((height, rows.shape[1] + 1), dtype=np.uint8)
    filtered[:, 0] = 1  # filter type Sub
    filtered[:, 1:pixel_bytes + 1] = rows[:, :pixel_bytes]
    np.subtract(rows[:, pixel_bytes:], rows[:, :-pixel_bytes], out=filtered[:, pixel_bytes + 1:])
    data = deflate.compress(filtered) + deflate.flush()
    header = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, 0)
    return b"".join((b"\x89PNG\r\n\x1a\n", _png_chunk(b"IHDR", header), _png_chunk(b"IDAT", data),
                     _png_chunk(b"IEND", b"")))


def _png_chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib_ng.crc32(data, zlib_ng.crc32(kind)))


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
