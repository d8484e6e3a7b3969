"""Writing texture and skybox images."""
from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image


def save_image(pixels: np.ndarray, path: Path) -> None:
    """Write a float image in [0, 1] ((h, w) grey or (h, w, 3) RGB, top row first); the
    container comes from the suffix. Pillow writes no timestamps, so output is repeatable."""
    data = np.clip(np.round(np.asarray(pixels) * 255.0), 0, 255).astype(np.uint8)
    image = Image.fromarray(data, "L" if data.ndim == 2 else "RGB")
    path.parent.mkdir(parents=True, exist_ok=True)
    suffix = path.suffix.lower()
    if suffix == ".png":
        image.save(path, "PNG", optimize=True)
    elif suffix == ".jpg":
        image.save(path, "JPEG", quality=88, optimize=True)
    elif suffix == ".tga":
        image.save(path, "TGA", compression="tga_rle")
    elif suffix == ".bmp":
        image.save(path, "BMP")
    else:
        raise ValueError(f"no writer for {path.name}")
