"""render.indirect against the path tracer on the Cornell box: error by region, whole-image
relative RMSE, the colour bleeding on the boxes' sides, and the bake's time, for a sweep
of the setting's knobs (scenerender/tools/bounce_regions.py defines the regions).

    python benchmarks/quality/cornell_indirect.py     # writes cornell_indirect.md, .json, .png

The PNG: direct light only (the truth's), the GPU at the defaults, the path tracer, side by
side, sRGB.

The truth is references/cornell_box_bounces16.npy (cornell_reference.py: 16 bounces, 1024
paths a pixel); the regions use cornell_box_objects.npy and cornell_box_direct.npy, and the
normals the GPU's `mode: normals` view gives. Each variant renders once on a fresh
renderer: the time is the first frame's, the bake with it (a static scene bakes once).
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))

import scenerender  # noqa: E402
from scenerender.colorspace import encode_output  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.tools.bounce_regions import (  # noqa: E402
    bounce_regions, red_over_green, region_errors, relative_rmse,
)

SCENE = HERE / "scenes" / "cornell_box.yaml"
KEPT = HERE / "references"
VARIANTS = {
    "direct only": [],
    "ambient 0.12 (a flat fill)": ["lights[1]={type: ambient, color: [0.12, 0.12, 0.12]}"],
    "bounces 2": ["render.indirect={bounces: 2}"],
    "bounces 4": ["render.indirect={bounces: 4}"],
    "default (bounces 8)": ["render.indirect={}"],
    "bounces 16": ["render.indirect={bounces: 16}"],
    "capture 8 px": ["render.indirect={capture_size: 8}"],
    "capture 32 px": ["render.indirect={capture_size: 32}"],
    "spacing 0.33 (6x6x6)": ["render.indirect={probe_spacing: 0.33}"],
    "spacing 0.17 (12x12x12)": ["render.indirect={probe_spacing: 0.17}"],
}


def load(overrides) -> scenerender.Scene:
    return scenerender.Scene.from_yaml(SCENE.read_text(), SCENE.parent, list(overrides), name="cornell_box")


def render(gl, overrides) -> tuple[np.ndarray, float]:
    """(H, W, 3) float64 linear radiance and the first frame's seconds (bake included)."""
    started = time.perf_counter()
    with scenerender.Renderer(load(overrides), gl=gl, want_linear=True) as renderer:
        image = renderer.render(0).linear[:, :, :3].astype(np.float64)
    return image, time.perf_counter() - started


def normals_view(gl) -> np.ndarray:
    """(H, W, 3) world-space unit normals from the GPU's `mode: normals` view."""
    with scenerender.Renderer(load(["render.mode=normals", "render.samples=1"]), gl=gl, want_linear=True) as renderer:
        encoded = renderer.render(0).linear[:, :, :3].astype(np.float64)
    normals = encoded * 2.0 - 1.0
    return normals / np.maximum(np.linalg.norm(normals, axis=2, keepdims=True), 1e-9)


def truth() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(the 16-bounce reference, the direct-only one, the object map), top row first."""
    return (np.load(KEPT / "cornell_box_bounces16.npy").astype(np.float64),
            np.load(KEPT / "cornell_box_direct.npy").astype(np.float64),
            np.load(KEPT / "cornell_box_objects.npy"))


def measure(image: np.ndarray, reference: np.ndarray, regions: dict) -> dict:
    """Every number of one variant's row."""
    return {"regions": region_errors(image, reference, regions), "rmse": relative_rmse(image, reference),
            "mean": float(image.mean() / reference.mean()),
            "bleeding": {face: red_over_green(image, regions[face]) / red_over_green(reference, regions[face])
                         for face in ("tall_box_front", "short_box_front")}}


def main() -> None:
    reference, direct, objects = truth()
    gl = create_context()
    regions = bounce_regions(objects, normals_view(gl), direct)
    rows = {}
    for name, overrides in VARIANTS.items():
        image, seconds = render(gl, overrides)
        rows[name] = {**measure(image, reference, regions), "seconds": seconds, "overrides": overrides}
        print(f"{name}: {seconds:.1f} s, RMSE {rows[name]['rmse']:.3f}", flush=True)
        if name == "default (bounces 8)":
            side_by_side(direct, image, reference).save(HERE / "cornell_indirect.png")
    (HERE / "cornell_indirect.json").write_text(json.dumps(rows, indent=1) + "\n")
    (HERE / "cornell_indirect.md").write_text(table(rows, gl.info["GL_RENDERER"]) + "\n")


def side_by_side(*images: np.ndarray) -> Image.Image:
    """Linear (H, W, 3) images side by side, sRGB-encoded, 8-bit."""
    return Image.fromarray(encode_output(np.concatenate(images, axis=1), "srgb", 2.2))


def table(rows: dict, renderer: str) -> str:
    names = list(next(iter(rows.values()))["regions"])
    lines = [f"Cornell box, 128x128, against the path tracer (16 bounces, 1024 paths a pixel); GPU: {renderer}, "
             "2 shared CPU cores. Region error: GPU mean / truth mean - 1 (%). Bleeding: a face's red/green over "
             "the truth's. Seconds: the first frame, bake included.", "",
             "| variant | s | whole RMSE % | mean | " + " | ".join(names) + " | bleed tall front | bleed short front |",
             "|---" * (len(names) + 6) + "|"]
    for name, row in rows.items():
        cells = [f"{100 * row['regions'][r]:+.1f}" for r in names]
        bleed = [f"{row['bleeding'][f]:.3f}" for f in ("tall_box_front", "short_box_front")]
        lines.append(f"| {name} | {row['seconds']:.1f} | {100 * row['rmse']:.1f} | {row['mean']:.3f} | "
                     + " | ".join(cells) + " | " + " | ".join(bleed) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
