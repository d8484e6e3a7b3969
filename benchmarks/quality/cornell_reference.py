"""The path-traced references of scenes/cornell_box.yaml, kept in references/ so that the
GPU's indirect light can be measured against them without rendering them again.

    python benchmarks/quality/cornell_reference.py [SPP] [BOUNCES]   # 32 16: about 6 minutes on 2 cores

Writes, each (128, 128, 3) float32 linear radiance (before exposure and tone curve):

- references/cornell_box_bounces16.npy: `scenerender reference --bounces 16 --spp 32`
  (32 x 32 = 1024 paths a pixel);
- references/cornell_box_direct.npy: the same with `--bounces 0` (direct light only);
- references/cornell_box_objects.npy: (128, 128) int32, the scene object each pixel's
  middle sample sees (the order of the scene's `objects`);

and prints the noise of the path-traced one: frame 1 of the (still) scene draws other
random numbers, so the difference of the two frames over sqrt(2) is one frame's noise,
per pixel and over each object's pixels (relative to the object's mean).
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))

import scenerender  # noqa: E402
from scenerender.raytrace import render_reference  # noqa: E402

SCENE = HERE / "scenes" / "cornell_box.yaml"
KEPT = HERE / "references"


def main() -> None:
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 32
    bounces = int(sys.argv[2]) if len(sys.argv) > 2 else 16
    scene = scenerender.load(SCENE)
    names = [obj.name for obj in scene.world.spec.objects]
    KEPT.mkdir(exist_ok=True)
    started = time.perf_counter()
    direct = render_reference(scene, 0, spp=spp)
    print(f"direct only: {time.perf_counter() - started:.1f} s")
    started = time.perf_counter()
    full = render_reference(scene, 0, spp=spp, bounces=bounces)
    seconds = time.perf_counter() - started
    print(f"{bounces} bounces, {spp}x{spp} samples a pixel: {seconds:.1f} s, "
          f"{seconds / (spp * spp):.3f} s per sample a pixel at {full.linear.shape[1]}x{full.linear.shape[0]}")
    np.save(KEPT / "cornell_box_direct.npy", direct.linear.astype(np.float32))
    np.save(KEPT / f"cornell_box_bounces{bounces}.npy", full.linear.astype(np.float32))
    np.save(KEPT / "cornell_box_objects.npy", full.object.astype(np.int32))
    other = render_reference(scene, 1, spp=spp, bounces=bounces)
    print_noise(full.linear, other.linear, direct.linear, full.object, names)


def print_noise(first: np.ndarray, second: np.ndarray, direct: np.ndarray, objects: np.ndarray, names) -> None:
    """One frame's noise from two frames of independent samples (H, W, 3): per pixel
    (median over the image of |difference| / sqrt(2) over the pair's mean, channel means),
    and over each object's pixels."""
    luminance = lambda image: image.mean(axis=2)  # noqa: E731
    a, b = luminance(first), luminance(second)
    mean = 0.5 * (a + b)
    per_pixel = np.abs(a - b) / np.sqrt(2.0) / np.maximum(mean, 1e-6)
    print(f"per-pixel noise: median {100 * np.median(per_pixel):.1f} %, "
          f"90th percentile {100 * np.percentile(per_pixel, 90):.1f} %")
    print("| object | pixels | mean (bounces) | mean (direct) | direct / bounces | noise of the mean |")
    print("|---|---|---|---|---|---|")
    for index, name in enumerate(names):
        mask = objects == index
        if not mask.any():
            continue
        region = a[mask].mean()
        noise = abs(a[mask].mean() - b[mask].mean()) / np.sqrt(2.0) / max(region, 1e-9)
        print(f"| {name} | {int(mask.sum())} | {region:.4f} | {luminance(direct)[mask].mean():.4f} | "
              f"{luminance(direct)[mask].mean() / region:.3f} | {100 * noise:.2f} % |")


if __name__ == "__main__":
    main()
