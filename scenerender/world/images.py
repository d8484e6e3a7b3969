"""Image files decoded on the CPU (Pillow), with the checks an untrusted file needs. No GL.

An image is an untrusted input: its header can claim any size, its data can be truncated or
malformed in ways each Pillow plugin reports with a different exception, and Pillow picks
the decoder from the content, not the name. So:

- only the formats in ``IMAGE_FORMATS`` are opened (never EPS, which runs Ghostscript);
- the header's width x height is checked against the pixel limit before any pixel is
  decoded (Pillow's own decompression-bomb check and its multi-line warning are replaced by
  this one limit, which ``--limit texture_pixels=N`` raises);
- every exception the decoder raises on bad data becomes an ``ImageError``, a ``UserError``
  naming the file.
"""
from __future__ import annotations

import contextlib
import threading
import warnings as _pywarnings
from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.limits import exceeded_message
from scenerender.scene.files import open_regular_file

# Pillow format names that may be decoded: the common texture formats. Everything else
# Pillow knows (EPS, PDF-adjacent, scientific formats...) is refused.
IMAGE_FORMATS = ("PNG", "JPEG", "BMP", "DIB", "TGA", "GIF", "TIFF", "DDS", "PPM", "WEBP")
DEFAULT_MAX_PIXELS = 16384 * 16384
# The largest texture side every OpenGL 4.3 device must accept (GL_MAX_TEXTURE_SIZE); a
# longer side would fail at upload, after validation said the scene was fine.
MAX_SIDE = 16384
PLACEHOLDER_SIZE = 64
# Pillow's bomb limit and the warnings filters are process-wide: one decode at a time
# changes them, so that concurrent callers cannot leave them changed.
_PILLOW_SETTINGS = threading.Lock()


class ImageError(UserError):
    """An image file that cannot be used: unreadable, malformed, or over the pixel limit.

    ``reason`` is the problem without the file name, for messages that name the file
    differently (an MTL line, a scene key).
    """

    def __init__(self, reason: str, path: Path):
        super().__init__(reason, SourceLocation(display_path(path)))
        self.reason = reason
        self.path = path


def image_size(path: Path, max_pixels: int = DEFAULT_MAX_PIXELS) -> tuple[int, int]:
    """(width, height) from the image's header, without decoding the pixels.

    Raises ImageError when the file is not a readable image of an accepted format, or when
    its header claims more than ``max_pixels`` pixels.
    """
    with _opened(path, max_pixels) as image:
        return image.size


def decode_image(path: Path, max_pixels: int = DEFAULT_MAX_PIXELS) -> np.ndarray:
    """(H, W, 4) uint8 RGBA, rows top to bottom; the first frame of animated files.

    Raises ImageError (never anything else) for files that cannot be decoded, and
    UserError when the machine has not the memory to decode it.
    """
    with _opened(path, max_pixels) as image:
        try:
            image.load()
            pixels = _rgba(image)
        except MemoryError:  # not the file's fault, so not a placeholder's case: the run stops
            raise UserError(f"not enough memory to decode this {image.width}x{image.height} image "
                            f"({image.width * image.height * 4 / 2**20:,.0f} MiB as RGBA); use a smaller image, or "
                            "lower --limit texture_pixels=N to refuse such images early",
                            SourceLocation(display_path(path))) from None
        except Exception as exc:  # noqa: BLE001 - see _decoder_failure
            raise _decoder_failure(exc, path) from None
    if pixels.ndim != 3 or pixels.shape[2] != 4 or pixels.shape[0] == 0 or pixels.shape[1] == 0:
        raise ImageError("the image has no pixels", path)
    return pixels


# Rows converted at a time: converting a whole image to RGBA, then to an array, held three
# copies of it at once (a 12,000 x 12,000 texture peaked at 2.3 GB to decode, now 1.1 GB).
_CONVERT_ROWS = 1024


def _rgba(image) -> np.ndarray:
    """(H, W, 4) uint8 of a loaded Pillow image, converted a band of rows at a time (every
    mode's conversion to RGBA is per pixel, so the bands join seamlessly)."""
    width, height = image.size
    if image.mode == "RGBA":
        return np.asarray(image, dtype=np.uint8)
    pixels = np.empty((height, width, 4), dtype=np.uint8)
    for top in range(0, height, _CONVERT_ROWS):
        bottom = min(height, top + _CONVERT_ROWS)
        pixels[top:bottom] = np.asarray(image.crop((0, top, width, bottom)).convert("RGBA"), dtype=np.uint8)
    return pixels


def placeholder_pixels() -> np.ndarray:
    """(64, 64, 4) uint8: a magenta and black checkerboard, impossible to mistake for a
    real texture; drawn where an MTL names a texture that is missing or unreadable."""
    cells = (np.indices((PLACEHOLDER_SIZE, PLACEHOLDER_SIZE)) // 8).sum(axis=0) % 2
    pixels = np.zeros((PLACEHOLDER_SIZE, PLACEHOLDER_SIZE, 4), dtype=np.uint8)
    pixels[cells == 0] = (255, 0, 255, 255)
    pixels[cells == 1] = (0, 0, 0, 255)
    return pixels


class ImageStore:
    """Decoded images by file for one run: each file decoded once, every one checked
    against ``max_pixels`` (``Limits.texture_pixels``). The world builds one while checking
    textures, and the GPU upload reuses the pixels instead of decoding again."""

    def __init__(self, max_pixels: int = DEFAULT_MAX_PIXELS):
        self.max_pixels = max_pixels
        self._pixels: dict[Path, np.ndarray] = {}

    def size(self, path: Path) -> tuple[int, int]:
        """(height, width) of ``path``: of its decoded pixels, else from its header."""
        key = Path(path)
        if key in self._pixels:
            return self._pixels[key].shape[:2]
        width, height = image_size(key, self.max_pixels)
        return height, width

    def pixels(self, path: Path) -> np.ndarray:
        """(H, W, 4) uint8 RGBA of ``path``; raises ImageError."""
        key = Path(path)
        if key not in self._pixels:
            self._pixels[key] = decode_image(key, self.max_pixels)
        return self._pixels[key]


# ---------------------------------------------------------------------------------------


@contextlib.contextmanager
def _opened(path: Path, max_pixels: int):
    """The Pillow image for ``path``, header read and size checked, pixels not decoded."""
    from PIL import Image

    with open_regular_file(path, "image") as stream, _pillow_quiet():
        try:
            image = Image.open(stream, formats=IMAGE_FORMATS)
        except MemoryError:
            raise ImageError("the image header claims more data than fits in memory", path) from None
        except Exception as exc:  # noqa: BLE001 - see _decoder_failure
            raise _decoder_failure(exc, path) from None
        with image:
            width, height = image.size
            if width <= 0 or height <= 0:
                raise ImageError(f"the image header gives an empty size {width}x{height}", path)
            if width * height > max_pixels:
                raise ImageError(exceeded_message("texture_pixels", width * height, max_pixels,
                                                  f"the image's size {width}x{height} in pixels"), path)
            if max(width, height) > MAX_SIDE:
                raise ImageError(f"the image is {width}x{height}; textures can be at most {MAX_SIDE} pixels "
                                 "on a side", path)
            yield image


@contextlib.contextmanager
def _pillow_quiet():
    """Pillow's decompression-bomb check off (the pixel limit above replaces it) and its
    warnings about the file silenced (the bomb warning is a RuntimeWarning, odd palettes and
    truncated chunks UserWarnings), for the duration of one open and decode. A
    DeprecationWarning still shows: it is about this code, not the file."""
    from PIL import Image

    with _PILLOW_SETTINGS:
        saved = Image.MAX_IMAGE_PIXELS
        Image.MAX_IMAGE_PIXELS = None
        try:
            with _pywarnings.catch_warnings():
                _pywarnings.simplefilter("ignore", RuntimeWarning)
                _pywarnings.simplefilter("ignore", UserWarning)
                yield
        finally:
            Image.MAX_IMAGE_PIXELS = saved


def _decoder_failure(exc: Exception, path: Path) -> ImageError:
    """The ImageError for an exception out of Pillow.

    Pillow reports bad data with whatever its plugin happens to raise: OSError (truncated,
    broken stream, UnidentifiedImageError), ValueError, SyntaxError, struct.error, EOFError,
    IndexError, KeyError, TypeError, ZeroDivisionError, OverflowError... None of them is a
    bug of this program when the input is a file from outside, so every one is mapped here;
    the call sites keep their try blocks around Pillow calls only.
    """
    from PIL import UnidentifiedImageError

    if isinstance(exc, UnidentifiedImageError):
        accepted = ", ".join(f for f in IMAGE_FORMATS if f != "DIB")
        return ImageError(f"not an image this renderer reads ({accepted})", path)
    text = " ".join(str(exc).split())
    if len(text) > 160:
        text = text[:157] + "..."
    detail = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
    if isinstance(exc, OSError) and text:
        detail = text
    return ImageError(f"cannot decode image ({detail})", path)
