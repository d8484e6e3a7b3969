"""Small asset files for tests, generated here: OBJ/MTL text, PNGs, and hostile images
(a PNG header claiming 100000x100000 pixels, truncated data)."""
from __future__ import annotations

import io
import struct
import zlib
from pathlib import Path

import numpy as np

TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n"


def write(path: Path, content) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    return path


def png_bytes(width: int = 4, height: int = 4, color=(200, 120, 40, 255)) -> bytes:
    from PIL import Image

    pixels = np.empty((height, width, 4), dtype=np.uint8)
    pixels[...] = color
    out = io.BytesIO()
    Image.fromarray(pixels, "RGBA").save(out, format="PNG")
    return out.getvalue()


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def png_header_only(width: int, height: int) -> bytes:
    """A valid-looking PNG (signature, IHDR with correct CRC, one tiny IDAT, IEND) whose
    header claims ``width`` x ``height`` RGBA pixels: a decompression bomb's header in
    a few dozen bytes."""
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    idat = zlib.compress(b"\x00" * 16)
    return b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", idat) + _chunk(b"IEND", b"")


def truncated_png(width: int = 32, height: int = 32) -> bytes:
    """A real PNG cut off inside its image data: the header reads, decoding fails."""
    noisy = np.random.default_rng(1).integers(0, 255, (height, width, 4), dtype=np.uint8)
    from PIL import Image

    out = io.BytesIO()  # noise does not compress, so half the file is half the rows
    Image.fromarray(noisy, "RGBA").save(out, format="PNG")
    whole = out.getvalue()
    return whole[: len(whole) // 2]


def model_with_two_vertex_faces(short_faces: int = 201) -> str:
    """An OBJ shaped like real exported models that carry stray edges as two-corner faces:
    a grid of quads with ``short_faces`` two-vertex 'faces' mixed between them, plus a
    couple of line and point elements."""
    lines = ["# exported model", "mtllib model.mtl", "o building"]
    size = 12
    for j in range(size + 1):
        for i in range(size + 1):
            lines.append(f"v {i} 0 {j}")
    lines.append("usemtl stone")
    index = lambda i, j: j * (size + 1) + i + 1  # noqa: E731
    written = 0
    for j in range(size):
        for i in range(size):
            lines.append(f"f {index(i, j)} {index(i, j + 1)} {index(i + 1, j + 1)} {index(i + 1, j)}")
            if written < short_faces:
                lines.append(f"f {index(i, j)} {index(i + 1, j)}")
                written += 1
    while written < short_faces:
        lines.append("f 1 2")
        written += 1
    lines += ["l 1 2 3", "p 4"]
    return "\n".join(lines) + "\n"
