"""What the filmed camera costs and how near it comes to the reference: the same scene
with each variant (bloom, a shutter, a lens, at several render.film_samples) in one
process and one GL context, the variants taking turns frame by frame (A B C A B C ...),
so that a busy spell of a shared machine slows them alike. Prints the median ms per
frame (whole frame: evaluation, uploads, every sub-frame's passes, readback), its ratio
to the first variant, the spread (IQR), and, with --reference-frame, each variant's error
on that frame against `scenerender reference` of the same settings (RMSE of the linear
image clipped to [0, 1], and of the 8-bit image, in % of white).

    python benchmarks/film_cost.py scenes/showcase.yaml --set "render.size=[320,240]" \\
        --variant "plain=" --variant "bloom=render.bloom={strength: 0.05, radius: 0.02}" \\
        --variant "shutter 8=camera.shutter=0.5;render.film_samples=8"

A variant is NAME=OVERRIDE;OVERRIDE... (the first is the one the others are compared with).
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import scenerender  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.raytrace import render_reference  # noqa: E402
from scenerender.rendering.renderer import GraphRenderer  # noqa: E402


# settings of how the GPU films the camera, which the reference does not read
FILMING_KEYS = ("render.film_samples", "render.depth_of_field", "render.motion_blur")


def rmse_percent(a: np.ndarray, b: np.ndarray, scale: float = 1.0) -> float:
    return 100.0 * float(np.sqrt(np.mean(((a.astype(np.float64) - b.astype(np.float64)) / scale) ** 2)))


def variant(text: str) -> tuple[str, list[str]]:
    name, _, rest = text.partition("=")
    return name, [item for item in rest.split(";") if item]


def timings(scene: str, sets: list, variants: list, frames: int, rounds: int, gl) -> dict:
    """name -> ms of each timed frame (frames 1..frames, after frame 0 warmed up)."""
    renderers = []
    for _, overrides in variants:
        renderer = GraphRenderer(scenerender.load(scene, sets + overrides).world, gl)
        renderer.render(0)  # programs compiled, static passes drawn
        renderers.append(renderer)
    frame_count = scenerender.load(scene, sets).frame_count
    totals = {name: [] for name, _ in variants}
    for round_index in range(rounds):
        order = list(range(len(variants)))
        order = order[round_index % len(order):] + order[:round_index % len(order)]
        for index in range(1, frames + 1):
            for k in order:
                started = time.perf_counter()
                renderers[k].render(index % max(frame_count, 1))
                totals[variants[k][0]].append(1000.0 * (time.perf_counter() - started))
    for renderer in renderers:
        renderer.release()
    return totals


def errors(scene: str, sets: list, variants: list, frame: int, spp: int, shutter_samples: int, gl,
           reference_sets: list | None = None) -> dict:
    """name -> (linear RMSE %, 8-bit RMSE %) of ``frame`` against the reference of the
    variant's settings (one reference per distinct setting besides how the renderer films
    them: render.film_samples, render.depth_of_field, render.motion_blur), or, given
    ``reference_sets``, against the one reference of those settings (an instant against the
    shutter's reference, say)."""
    references, found = {}, {}
    for name, overrides in variants:
        key = (tuple(o for o in overrides if not o.startswith(FILMING_KEYS)) if reference_sets is None
               else tuple(reference_sets))
        loaded = scenerender.load(scene, sets + overrides)
        if key not in references:
            started = time.perf_counter()
            filmed = loaded if reference_sets is None else scenerender.load(scene, sets + reference_sets)
            references[key] = render_reference(filmed, frame, spp=spp, shutter_samples=shutter_samples)
            print(f"reference for {name}: {time.perf_counter() - started:.0f} s", file=sys.stderr)
        reference = references[key]
        renderer = GraphRenderer(loaded.world, gl, want_linear=True)
        result = renderer.render(frame)
        renderer.release()
        linear = rmse_percent(np.clip(reference.linear, 0, 1), np.clip(result.linear, 0, 1))
        found[name] = (linear, rmse_percent(reference.pixels, result.pixels, scale=255.0))
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--set", dest="sets", action="append", default=[], help="override for every variant")
    parser.add_argument("--variant", dest="variants", action="append", default=[], help="NAME=OVERRIDE;OVERRIDE...")
    parser.add_argument("--frames", type=int, default=10, help="timed frames per variant and round (default 10)")
    parser.add_argument("--rounds", type=int, default=2, help="rounds, each in a rotated order (default 2)")
    parser.add_argument("--reference-frame", type=int, default=None, help="measure the error on this frame")
    parser.add_argument("--spp", type=int, default=4, help="the reference's samples a pixel along each axis")
    parser.add_argument("--shutter-samples", type=int, default=32, help="the reference's instants over the shutter")
    parser.add_argument("--reference-set", dest="reference_sets", action="append", default=None,
                        help="every variant against the one reference of these overrides (repeatable; "
                             "--reference-set '' for the scene as --set leaves it)")
    args = parser.parse_args()
    variants = [variant(text) for text in args.variants or ["plain="]]
    gl = create_context()
    totals = timings(args.scene, args.sets, variants, args.frames, args.rounds, gl) if args.frames else {}
    reference_sets = [item for item in args.reference_sets if item] if args.reference_sets is not None else None
    found = (errors(args.scene, args.sets, variants, args.reference_frame, args.spp, args.shutter_samples, gl,
                    reference_sets) if args.reference_frame is not None else {})
    print(f"{args.scene} {' '.join(args.sets)}: {args.rounds} rounds x {args.frames} frames a variant, alternated")
    print("| variant | ms/frame | IQR | ratio | RMSE linear % | RMSE 8-bit % |")
    print("|---|---|---|---|---|---|")
    first = statistics.median(totals[variants[0][0]]) if totals else None
    for name, _ in variants:
        ms = statistics.median(totals[name]) if totals else None
        q = statistics.quantiles(totals[name], n=4) if totals and len(totals[name]) > 1 else None
        error = found.get(name)
        print(f"| {name} | {ms:.1f} | {q[0]:.1f}-{q[2]:.1f} | {ms / first:.2f} | " if ms is not None else f"| {name} | | | | ",
              end="")
        print(f"{error[0]:.3f} | {error[1]:.3f} |" if error else " | |")


if __name__ == "__main__":
    main()
