"""Image files decoded on the CPU (Pillow) into RGBA arrays, once per file and run. No GL.

Opening goes through ``scenerender.scene.image_files``, which checks the format, the
header's size against the pixel limit and maps every decoder failure to an ``ImageError``
(see there); this module decodes the pixels and keeps them for the GPU upload.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.scene.image_files import (
    DEFAULT_MAX_PIXELS, ImageError, decoder_failure, image_size, opened_image, opened_image_bytes,
)

PLACEHOLDER_SIZE = 64


def decode_image(path: Path, max_pixels: int = DEFAULT_MAX_PIXELS, data: bytes | None = None) -> np.ndarray:
    """(H, W, 4) uint8 RGBA, rows top to bottom; the first frame of animated files. With
    ``data``, the image is those encoded bytes (one a mesh file holds), ``path`` its name.

    Raises ImageError (never anything else) for files that cannot be decoded, and
    UserError when the machine has not the memory to decode it.
    """
    opened = opened_image(path, max_pixels) if data is None else opened_image_bytes(data, path, max_pixels)
    with opened as image:
        try:
            image.load()
            pixels = _rgba(image)
        except MemoryError:  # not the file's fault, so not a placeholder's case: the run stops
            raise UserError(f"not enough memory to decode this {image.width}x{image.height} image "
                            f"({image.width * image.height * 4 / 2**20:,.0f} MiB as RGBA); use a smaller image, or "
                            "lower --limit texture_pixels=N to refuse such images early",
                            SourceLocation(display_path(path))) from None
        except Exception as exc:  # noqa: BLE001 - see decoder_failure
            raise decoder_failure(exc, path) from None
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
        self._encoded: dict[Path, bytes] = {}

    def add_encoded(self, key: Path, data: bytes) -> None:
        """An image held by a mesh file (encoded bytes), known as ``key`` from now on."""
        self._encoded[Path(key)] = data

    def size(self, path: Path) -> tuple[int, int]:
        """(height, width) of ``path``: of its decoded pixels, else from its header."""
        key = Path(path)
        if key in self._pixels or key in self._encoded:
            return self.pixels(key).shape[:2]
        width, height = image_size(key, self.max_pixels)
        return height, width

    def pixels(self, path: Path) -> np.ndarray:
        """(H, W, 4) uint8 RGBA of ``path``; raises ImageError."""
        key = Path(path)
        if key not in self._pixels:
            self._pixels[key] = decode_image(key, self.max_pixels, self._encoded.get(key))
        return self._pixels[key]
