"""The path-traced references of the scenes of light that bounces, kept in references/ so
that the GPU's indirect light can be measured against them without rendering them again.

    python benchmarks/quality/kept_references.py NAME [SPP] [BOUNCES]   # NAME: cornell_box or outdoor_boxes

renders scenes/NAME.yaml and writes, each at the scene's size:

- references/NAME_bouncesBOUNCES.npy: (H, W, 3) float32 linear radiance (before exposure
  and tone curve), `scenerender reference --bounces BOUNCES --spp SPP` (SPP x SPP paths a
  pixel; default 32 and 16);
- references/NAME_direct.npy: the same with `--bounces 0` (direct light only);
- references/NAME_objects.npy: (H, W) int32, the scene object each pixel's middle sample
  sees (the order of the scene's `objects`; -1 for none);

and prints the time taken and the path-traced one's noise: frame 1 of the (still) scene
draws other random numbers, so the difference of the two frames over sqrt(2) is one
frame's noise, per pixel and over each object's pixels (relative to the object's mean).
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

KEPT = HERE / "references"


def main() -> None:
    name = sys.argv[1]
    spp = int(sys.argv[2]) if len(sys.argv) > 2 else 32
    bounces = int(sys.argv[3]) if len(sys.argv) > 3 else 16
    scene = scenerender.load(HERE / "scenes" / f"{name}.yaml")
    names = [obj.name for obj in scene.world.spec.objects]
    KEPT.mkdir(exist_ok=True)
    started = time.perf_counter()
    direct = render_reference(scene, 0, spp=spp)
    print(f"direct only: {time.perf_counter() - started:.1f} s")
    started, cpu = time.perf_counter(), time.process_time()
    full = render_reference(scene, 0, spp=spp, bounces=bounces)
    seconds, cpu = time.perf_counter() - started, time.process_time() - cpu
    height, width = full.linear.shape[:2]
    print(f"{bounces} bounces, {spp}x{spp} samples a pixel: {seconds:.1f} s ({cpu:.1f} s CPU), "
          f"{seconds / (spp * spp):.3f} s ({cpu / (spp * spp):.3f} s CPU) per sample a pixel at {width}x{height}")
    np.save(KEPT / f"{name}_direct.npy", direct.linear.astype(np.float32))
    np.save(KEPT / f"{name}_bounces{bounces}.npy", full.linear.astype(np.float32))
    np.save(KEPT / f"{name}_objects.npy", full.object.astype(np.int32))
    other = render_reference(scene, 1, spp=spp, bounces=bounces)
    print_noise(full.linear, other.linear, direct.linear, full.object, names)


def print_noise(first: np.ndarray, second: np.ndarray, direct: np.ndarray, objects: np.ndarray, names) -> None:
    """One frame's noise from two frames of independent samples (H, W, 3): per pixel
    (median over the image of |difference| / sqrt(2) over the pair's mean, channel means),
    and over each object's pixels."""
    luminance = lambda image: image.mean(axis=2)  # noqa: E731
    a, b = luminance(first), luminance(second)
    seen = objects >= 0
    per_pixel = (np.abs(a - b) / np.sqrt(2.0) / np.maximum(0.5 * (a + b), 1e-6))[seen]
    print(f"per-pixel noise: median {100 * np.median(per_pixel):.1f} %, "
          f"90th percentile {100 * np.percentile(per_pixel, 90):.1f} %")
    print(f"direct light has {luminance(direct)[seen].mean() / a[seen].mean():.3f} of the light")
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
