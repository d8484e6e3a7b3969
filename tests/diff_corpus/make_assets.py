"""Writes the diff corpus's assets (deterministic: a fixed seed), all made here:

- ``knobbly.obj``: a unit icosphere (4 subdivisions) pushed in and out along its normals by
  smooth random bumps, so a small copy of it has detailed, high-frequency shading;
- ``speckle.png``: 64x64 random speckle, a texture with detail at every pixel;
- ``speckle_dark.png``: the same 15% darker (a texture change the verdict must see);
- ``checker.png``: an 8x8 checker of 8-pixel cells, tiled on the ground for sharp texture edges.

    python tests/diff_corpus/make_assets.py
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh
from PIL import Image

HERE = Path(__file__).resolve().parent


def knobbly_obj(seed: int = 7) -> str:
    sphere = trimesh.creation.icosphere(subdivisions=4)
    rng = np.random.default_rng(seed)
    centres = rng.normal(size=(160, 3))
    centres /= np.linalg.norm(centres, axis=1, keepdims=True)
    heights = rng.uniform(-0.09, 0.09, size=160)
    # a bump of each centre's height, falling off with the angle to it
    cosines = sphere.vertices @ centres.T
    radius = 1.0 + (heights * np.exp(-(1 - cosines) * 80)).sum(axis=1)
    vertices = sphere.vertices * radius[:, None]
    lines = ["# knobbly sphere: made by make_assets.py"]
    lines += [f"v {x:.5f} {y:.5f} {z:.5f}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in sphere.faces]
    return "\n".join(lines) + "\n"


def speckle(seed: int = 11) -> Image.Image:
    rng = np.random.default_rng(seed)
    return Image.fromarray(rng.integers(40, 230, size=(64, 64, 3), dtype=np.uint8))


def checker() -> Image.Image:
    cells = (np.indices((64, 64)) // 8).sum(axis=0) % 2
    return Image.fromarray(np.where(cells, 200, 60).astype(np.uint8)).convert("RGB")


def main() -> None:
    (HERE / "knobbly.obj").write_text(knobbly_obj(), encoding="utf-8")
    speckle().save(HERE / "speckle.png")
    Image.fromarray(np.round(np.asarray(speckle(), float) * 0.85).astype(np.uint8)).save(HERE / "speckle_dark.png")
    checker().save(HERE / "checker.png")


if __name__ == "__main__":
    main()
