"""render.indirect outdoors against the path tracer: scenes/outdoor_bounce.yaml (a ground
and three white boxes under a sky and a sun), by region (outdoor_regions in
scenerender/tools/bounce_regions.py: the boxes' vertical faces, those in the sun's shadow,
the ground in the boxes' shadows and beside them).

    python benchmarks/quality/outdoor_indirect.py [SPP]   # prints the table; about 5 minutes

Errors: a region's mean luminance over the truth's, less 1. Seconds: the frame, the bake
included. The truth: `scenerender reference --bounces 8` at SPP x SPP paths a pixel
(default 8), rendered here, not kept.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))

import scenerender  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.raytrace import render_reference  # noqa: E402
from scenerender.tools.bounce_regions import outdoor_regions, region_errors, relative_rmse  # noqa: E402

SCENE = HERE / "scenes" / "outdoor_bounce.yaml"
BOXES = (1, 2, 3)  # the scene's objects after the ground
VARIANTS = {
    "direct only": [],
    "probe_spacing 2 (the first default: the ground's 16 m over 8)": ["render.indirect={probe_spacing: 2}"],
    "render.indirect defaults (18x2x18 probes, 0.92 m apart)": ["render.indirect={}"],
    "probe_spacing 0.5": ["render.indirect={probe_spacing: 0.5}"],
}


def load(overrides=()) -> scenerender.Scene:
    return scenerender.Scene.from_yaml(SCENE.read_text(), SCENE.parent, list(overrides), name="outdoor_bounce")


def gpu(gl, overrides) -> np.ndarray:
    with scenerender.Renderer(load(overrides), gl=gl, want_linear=True) as renderer:
        return renderer.render(0).linear[:, :, :3].astype(np.float64)


def main() -> None:
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 8
    scene = load()
    started = time.perf_counter()
    truth = render_reference(scene, 0, spp=spp, bounces=8)
    direct = render_reference(scene, 0, spp=spp)
    print(f"references: {time.perf_counter() - started:.0f} s")
    gl = create_context()
    encoded = gpu(gl, ["render.mode=normals", "render.samples=1"])
    normals = (encoded * 2.0 - 1.0) / np.maximum(np.linalg.norm(encoded * 2.0 - 1.0, axis=2, keepdims=True), 1e-9)
    found = outdoor_regions(truth.object, normals, direct.linear, BOXES)
    reference = truth.linear.astype(np.float64)
    print("| variant | s | whole RMSE % | " + " | ".join(found) + " |")
    print("|---" * (len(found) + 3) + "|")
    for name, overrides in VARIANTS.items():
        started = time.perf_counter()
        image = gpu(gl, overrides)
        seconds = time.perf_counter() - started
        errors = region_errors(image, reference, found)
        print(f"| {name} | {seconds:.1f} | {100 * relative_rmse(image, reference):.1f} | "
              + " | ".join(f"{100 * errors[r]:+.1f}" for r in found) + " |")
    print("pixels: " + ", ".join(f"{name} {int(mask.sum())}" for name, mask in found.items()))


if __name__ == "__main__":
    main()
