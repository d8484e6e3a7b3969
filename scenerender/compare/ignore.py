"""Parts of a frame a user knows are not deterministic (a clock, a noisy sky), kept with the
references and left out of the verdict.

A reference folder may hold ``ignore.json``::

    {"rectangles": [{"x": 280, "y": 0, "w": 40, "h": 16, "frames": "frame_00*", "why": "clock"}]}

(``frames``, a shell pattern of frame names, defaults to every frame; ``why`` is shown in
the summary), and ``ignore.png``, a mask of the frames' size whose non-black pixels are
ignored in every frame. Neither is a frame. Ignored pixels of the output are taken from the
reference (colours and object ids) before the comparison, so nothing there can fail, and
every verdict says how many pixels it ignored and why.
"""
from __future__ import annotations

import fnmatch
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, display_path

RECTANGLES_FILE = "ignore.json"
MASK_FILE = "ignore.png"
FILES = (RECTANGLES_FILE, MASK_FILE)


@dataclass(frozen=True)
class Rectangle:
    x: int
    y: int
    w: int
    h: int
    frames: str = "*"
    why: str = ""


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
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise UserError(f"cannot read the ignore regions ({exc})", SourceLocation(display_path(path))) from None
    entries = data.get("rectangles") if isinstance(data, dict) else None
    if not isinstance(entries, list):
        raise UserError('rectangles: expected {"rectangles": [{"x": .., "y": .., "w": .., "h": ..}, ...]}',
                        SourceLocation(display_path(path)))
    out = []
    for index, entry in enumerate(entries):
        key = f"rectangles[{index}]"
        if not isinstance(entry, dict) or not all(isinstance(entry.get(k), int) and not isinstance(entry.get(k), bool)
                                                  for k in ("x", "y", "w", "h")):
            raise UserError(f"{key}: each rectangle needs whole numbers x, y, w and h (pixels from the top left)",
                            SourceLocation(display_path(path)))
        if entry["w"] <= 0 or entry["h"] <= 0:
            raise UserError(f"{key}: w and h must be positive", SourceLocation(display_path(path)))
        out.append(Rectangle(entry["x"], entry["y"], entry["w"], entry["h"], str(entry.get("frames", "*")),
                             str(entry.get("why", ""))))
    return out
