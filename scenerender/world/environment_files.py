"""Environment images read as linear light: Radiance ``.hdr`` (RGBE), OpenEXR ``.exr``
(OpenEXR), or an 8-bit image decoded as sRGB. No GL.

Every failure to read is an ``ImageError`` naming the file, as for textures.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from scenerender.colorspace import srgb_decode
from scenerender.limits import exceeded_message
from scenerender.scene.files import open_regular_file
from scenerender.scene.image_files import ImageError
from scenerender.world.images import ImageStore

_HDR_SIZE = re.compile(rb"^([-+])Y (\d+) ([-+])X (\d+)$")


def read_linear_image(path: Path, images: ImageStore) -> np.ndarray:
    """(H, W, 3) float32 linear RGB of ``path``, rows top to bottom; 8-bit images go
    through ``images`` (decoded once, the pixel limit applied) and the sRGB curve."""
    suffix = path.suffix.lower()
    if suffix == ".hdr":
        return read_hdr(path, images.max_pixels)
    if suffix == ".exr":
        return read_exr(path, images.max_pixels)
    return srgb_decode(images.pixels(path)[..., :3].astype(np.float32) / 255.0).astype(np.float32)


def read_exr(path: Path, max_pixels: int) -> np.ndarray:
    """(H, W, 3) float32 of an OpenEXR file's R, G, B channels."""
    import OpenEXR

    try:
        with OpenEXR.File(str(path)) as exr:
            channels = exr.channels()
            if "RGB" in channels:
                linear = np.asarray(channels["RGB"].pixels, dtype=np.float32)[..., :3]
            elif all(c in channels for c in "RGB"):
                linear = np.stack([np.asarray(channels[c].pixels, dtype=np.float32) for c in "RGB"], axis=2)
            else:
                raise ImageError(f"EXR without R, G, B channels (has {', '.join(sorted(channels))})", path)
    except ImageError:
        raise
    except Exception as exc:  # noqa: BLE001 - OpenEXR raises many kinds for a broken file
        raise ImageError(f"cannot read this EXR file ({exc})", path) from None
    _check_size(linear.shape[1], linear.shape[0], max_pixels, path)
    return linear


def read_hdr(path: Path, max_pixels: int) -> np.ndarray:
    """(H, W, 3) float32 of a Radiance RGBE file (flat or run-length encoded scanlines,
    rows top to bottom as ``-Y H +X W`` stores them)."""
    with open_regular_file(path, "image") as stream:
        data = stream.read()
    try:
        header_end = data.index(b"\n\n")
        size_end = data.index(b"\n", header_end + 2)
    except ValueError:
        raise ImageError("not a Radiance HDR file (no header end)", path) from None
    header = data[:header_end]
    if not (header.startswith(b"#?RADIANCE") or header.startswith(b"#?RGBE")):
        raise ImageError("not a Radiance HDR file (it does not start with #?RADIANCE)", path)
    if b"FORMAT=32-bit_rle_xyze" in header:
        raise ImageError("Radiance HDR in XYZ colours is not read; save it as RGB (32-bit_rle_rgbe)", path)
    found = _HDR_SIZE.match(data[header_end + 2:size_end].strip())
    if found is None or found.group(1) != b"-" or found.group(3) != b"+":
        raise ImageError("Radiance HDR with an orientation other than -Y H +X W is not read", path)
    height, width = int(found.group(2)), int(found.group(4))
    if width < 1 or height < 1:
        raise ImageError("the image has no pixels", path)
    _check_size(width, height, max_pixels, path)
    rgbe = _rgbe_scanlines(memoryview(data)[size_end + 1:], width, height, path)
    exponent = rgbe[..., 3].astype(np.int32)
    scale = np.where(exponent > 0, np.ldexp(1.0, exponent - 136), 0.0).astype(np.float32)
    return rgbe[..., :3].astype(np.float32) * scale[..., None]


def _rgbe_scanlines(body: memoryview, width: int, height: int, path: Path) -> np.ndarray:
    """(H, W, 4) uint8 RGBE from the pixel data: run-length encoded rows where each starts
    with 2 2 W (8 <= W < 32768), flat RGBE quadruples otherwise."""
    raw = np.frombuffer(body, dtype=np.uint8)
    if not (8 <= width < 32768) or len(raw) < 4 or raw[0] != 2 or raw[1] != 2 or raw[2] & 0x80:
        if len(raw) < width * height * 4:
            raise ImageError("the HDR file ends before its last pixel", path)
        return raw[:width * height * 4].reshape(height, width, 4)
    out = np.empty((height, 4, width), dtype=np.uint8)
    at = 0
    for row in range(height):
        if at + 4 > len(raw) or raw[at] != 2 or raw[at + 1] != 2 or (int(raw[at + 2]) << 8 | raw[at + 3]) != width:
            raise ImageError(f"bad run-length scanline {row} in the HDR file", path)
        at += 4
        for channel in range(4):
            at = _decode_run_channel(raw, at, out[row, channel], path)
    return out.transpose(0, 2, 1)


def _decode_run_channel(raw: np.ndarray, at: int, target: np.ndarray, path: Path) -> int:
    """Fill one channel of one row from Radiance's run-length code; returns the new offset."""
    filled, width = 0, len(target)
    while filled < width:
        if at >= len(raw):
            raise ImageError("the HDR file ends before its last pixel", path)
        count = int(raw[at])
        at += 1
        if count > 128:  # a run: one value, count - 128 times
            count -= 128
            if filled + count > width or at >= len(raw):
                raise ImageError("a run-length code in the HDR file runs past its row", path)
            target[filled:filled + count] = raw[at]
            at += 1
        else:  # count literal values
            if count == 0 or filled + count > width or at + count > len(raw):
                raise ImageError("a run-length code in the HDR file runs past its row", path)
            target[filled:filled + count] = raw[at:at + count]
            at += count
        filled += count
    return at


def write_hdr(path: Path, linear: np.ndarray) -> None:
    """Write (H, W, 3) linear RGB as a flat (not run-length encoded) Radiance file: for
    generated environments and tests."""
    linear = np.maximum(np.asarray(linear, dtype=np.float64), 0.0)
    brightest = linear.max(axis=2)
    mantissa, exponent = np.frexp(brightest)
    scale = np.where(brightest > 1e-32, mantissa * 256.0 / np.maximum(brightest, 1e-32), 0.0)
    rgbe = np.zeros(linear.shape[:2] + (4,), dtype=np.uint8)
    rgbe[..., :3] = np.clip(linear * scale[..., None], 0, 255).astype(np.uint8)
    rgbe[..., 3] = np.where(brightest > 1e-32, exponent + 128, 0).astype(np.uint8)
    height, width = linear.shape[:2]
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n".encode()
    Path(path).write_bytes(header + rgbe.tobytes())


def _check_size(width: int, height: int, max_pixels: int, path: Path) -> None:
    if width * height > max_pixels:
        raise ImageError(exceeded_message("texture_pixels", width * height, max_pixels,
                                          f"the image's size {width}x{height} in pixels"), path)
