"""Parts of a frame a user knows are not deterministic (a clock, a noisy sky), kept with the
references and left out of the verdict.

A reference folder may hold ``ignore.json``::

    {"rectangles": [{"x": 280, "y": 0, "w": 40, "h": 16, "frames": "frame_00*", "why": "clock"}]}

(``frames``, a shell pattern of frame names, defaults to every frame; ``why`` is shown in
the summary, characters a terminal cannot show escaped), and ``ignore.png``, a mask of the
frames' size whose non-black pixels are ignored in every frame. Neither is a frame. Ignored
pixels of the output are taken from the reference (colours and object ids) before the
comparison, so nothing there can fail, and every verdict says how many pixels it ignored
and why. ignore.json is read through the JSON guard and validated into ``RectanglesFile``:
anything else in it is bad input naming the file and the key.
"""
from __future__ import annotations

import fnmatch
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict, PositiveInt, ValidationError, field_validator

from scenerender.errors import SourceLocation, UserError, display_path, printable
from scenerender.json_input import IGNORE_MAX_BYTES
from scenerender.scene.files import read_json_file
from scenerender.scene.messages import json_file_error

RECTANGLES_FILE = "ignore.json"
MASK_FILE = "ignore.png"
FILES = (RECTANGLES_FILE, MASK_FILE)


class Rectangle(BaseModel):
    """One ignored rectangle, in pixels from the top left; strict: 1.5 or true is no pixel."""

    model_config = ConfigDict(strict=True, frozen=True)

    x: int
    y: int
    w: PositiveInt
    h: PositiveInt
    frames: str = "*"
    why: str = ""

    @field_validator("why")
    @classmethod
    def _printable(cls, why: str) -> str:
        return printable(why)  # the verdict prints it


class RectanglesFile(BaseModel):
    """The contents of ignore.json."""

    model_config = ConfigDict(strict=True)

    rectangles: list[Rectangle]


@dataclass
class IgnoreRegions:
    """What a reference folder ignores: rectangles (per frame pattern) and a mask."""

    folder: Path | None = None
    rectangles: list = field(default_factory=list)
    mask: np.ndarray | None = None    # (H, W) bool

    def __bool__(self) -> bool:
        return bool(self.rectangles) or self.mask is not None

    def mask_for(self, name: str, shape: tuple[int, int]) -> np.ndarray | None:
        """(H, W) bool: the pixels of frame ``name`` to ignore, or None for none."""
        mask = np.zeros(shape, bool)
        if self.mask is not None and self.mask.shape == shape:
            mask |= self.mask
        for r in self.rectangles:
            if fnmatch.fnmatch(name, r.frames):
                mask[max(r.y, 0):max(r.y + r.h, 0), max(r.x, 0):max(r.x + r.w, 0)] = True
        return mask if mask.any() else None

    def describe(self) -> str:
        parts = [f"{RECTANGLES_FILE}: " + ", ".join(r.why or f"x {r.x} y {r.y} {r.w}x{r.h}" for r in self.rectangles)
                 ] if self.rectangles else []
        if self.mask is not None:
            parts.append(MASK_FILE)
        return "; ".join(parts)


def read_ignore(folder: Path) -> IgnoreRegions:
    """The ignore regions of the reference folder ``folder`` (none where it holds neither
    file). A malformed ignore.json is a UserError naming the file and the entry."""
    folder = Path(folder)
    found = IgnoreRegions(folder)
    path = folder / RECTANGLES_FILE
    if path.is_file():
        found.rectangles = _rectangles(path)
    mask_path = folder / MASK_FILE
    if mask_path.is_file():
        from PIL import Image

        try:
            with Image.open(mask_path) as image:
                found.mask = np.asarray(image.convert("L")) > 0
        except Exception as exc:  # Pillow raises many kinds for a broken file
            raise UserError(f"cannot read the ignore mask ({exc})", SourceLocation(display_path(mask_path))) from None
    return found


def _rectangles(path: Path) -> list[Rectangle]:
    data = read_json_file(path, "ignore regions file", IGNORE_MAX_BYTES)
    try:
        return RectanglesFile.model_validate(data).rectangles
    except ValidationError as exc:
        raise json_file_error(exc, data, display_path(path)) from None
