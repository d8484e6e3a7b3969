"""Image files opened safely, up to their header: what validation and decoding share.

An image is an untrusted input: its header can claim any size, its data can be truncated or
malformed in ways each Pillow plugin reports with a different exception, and Pillow picks
the decoder from the content, not the name. So:

- only the formats in ``IMAGE_FORMATS`` are opened (never EPS, which runs Ghostscript);
- the header's width x height is checked against the pixel limit before any pixel is
  decoded (Pillow's own decompression-bomb check and its multi-line warning are replaced by
  this one limit, which ``--limit texture_pixels=N`` raises);
- every exception the decoder raises on bad data becomes an ``ImageError``, a ``UserError``
  naming the file.

The scene's file checks read sizes here (``image_size``); decoding pixels is the world's
(``scenerender.world.images``), through ``opened_image`` and ``decoder_failure``.
"""
from __future__ import annotations

import contextlib
import io
import threading
import warnings as _pywarnings
from pathlib import Path

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
# Pillow's bomb limit and the warnings filters are process-wide: one decode at a time
# changes them, so that concurrent callers cannot leave them changed.
_PILLOW_SETTINGS = threading.Lock()


def pillow():
    """Pillow's ``Image`` module, imported by the first image opened, deliberately late: a
    scene without images and its PNG frames never need it, and its import (with its tables
    of EXIF and TIFF tags) is a tenth of the start-up of a one-frame render."""
    from PIL import Image

    return Image


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
    with opened_image(path, max_pixels) as image:
        return image.size


@contextlib.contextmanager
def opened_image(path: Path, max_pixels: int):
    """The Pillow image for ``path``, header read and size checked, pixels not decoded;
    Pillow's own bomb check and warnings stay off until the block ends (decode inside it)."""
    with open_regular_file(path, "image") as stream, _opened(stream, path, max_pixels) as image:
        yield image


@contextlib.contextmanager
def opened_image_bytes(data: bytes, label: Path, max_pixels: int):
    """``opened_image`` for an image held in memory (one a mesh file holds); ``label``
    names it in messages."""
    with _opened(io.BytesIO(data), label, max_pixels) as image:
        yield image


@contextlib.contextmanager
def _opened(stream, path: Path, max_pixels: int):
    with _pillow_quiet():
        try:
            image = pillow().open(stream, formats=IMAGE_FORMATS)
        except MemoryError:
            raise ImageError("the image header claims more data than fits in memory", path) from None
        except Exception as exc:  # noqa: BLE001 - see decoder_failure
            raise decoder_failure(exc, path) from None
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
    Image = pillow()
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


def decoder_failure(exc: Exception, path: Path) -> ImageError:
    """The ImageError for an exception out of Pillow.

    Pillow reports bad data with whatever its plugin happens to raise: OSError (truncated,
    broken stream, UnidentifiedImageError), ValueError, SyntaxError, struct.error, EOFError,
    IndexError, KeyError, TypeError, ZeroDivisionError, OverflowError... None of them is a
    bug of this program when the input is a file from outside, so every one is mapped here;
    the call sites keep their try blocks around Pillow calls only.
    """
    if isinstance(exc, pillow().UnidentifiedImageError):
        accepted = ", ".join(f for f in IMAGE_FORMATS if f != "DIB")
        return ImageError(f"not an image this renderer reads ({accepted})", path)
    text = " ".join(str(exc).split())
    if len(text) > 160:
        text = text[:157] + "..."
    detail = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
    if isinstance(exc, OSError) and text:
        detail = text
    return ImageError(f"cannot decode image ({detail})", path)
