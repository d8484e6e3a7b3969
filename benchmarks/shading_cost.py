"""What a shading model costs: the same scene rendered with each ``render.shading`` in one
process, one GL context, the models taking turns frame by frame (A B A B ...), so that a
busy spell of a shared machine slows them alike. Prints the median ms per frame (whole
frame: evaluation, upload, passes, readback) and of the opaque pass (GPU-synchronised, the
--profile timing), each model's ratio to the first, and the spread (IQR).

    python benchmarks/shading_cost.py scenes/showcase.yaml --set "render.size=[640,480]"
    python benchmarks/shading_cost.py benchmarks/quality/scenes/pbr_point.yaml --frames 40 --rounds 3

Materials that name their own ``shading`` keep it whatever the variant says. A variant
may carry more overrides than the model, as NAME=SHADING:OVERRIDE;OVERRIDE... (the first
variant is the one the others are compared with):

    python benchmarks/shading_cost.py scenes/showcase.yaml --set "render.size=[640,480]" \
        --model blinn_phong --model "pbr+environment=pbr:lights[2]={type: environment}"
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import scenerender  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.rendering.renderer import GraphRenderer  # noqa: E402


def quartiles(values: list) -> tuple[float, float]:
    q = statistics.quantiles(values, n=4)
    return q[0], q[2]


def variant(text: str) -> tuple[str, list[str]]:
    """(name, overrides) of a --model value: SHADING, or NAME=SHADING:OVERRIDE;OVERRIDE..."""
    name, _, rest = text.partition("=") if "=" in text else (text, "", text)
    shading, _, extra = rest.partition(":")
    return name, [f"render.shading={shading}"] + [item for item in extra.split(";") if item]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--set", dest="sets", action="append", default=[], help="override for every model")
    parser.add_argument("--model", dest="models", action="append", default=[],
                        help="a render.shading value (repeatable; default blinn_phong and pbr)")
    parser.add_argument("--frames", type=int, default=20, help="timed frames per model and round (default 20)")
    parser.add_argument("--rounds", type=int, default=3, help="rounds, each in a rotated order (default 3)")
    args = parser.parse_args()
    variants = [variant(text) for text in args.models or ["blinn_phong", "pbr"]]
    models = [name for name, _ in variants]
    gl = create_context()
    renderers = []
    for _, sets in variants:
        scene = scenerender.load(args.scene, args.sets + sets)
        renderer = GraphRenderer(scene.world, gl, profile=True)
        renderer.render(0)  # programs compiled, static passes drawn
        renderer.timings.clear()
        renderers.append(renderer)
    frame_count = scenerender.load(args.scene, args.sets).frame_count
    totals = {model: [] for model in models}
    for round_index in range(args.rounds):
        order = list(range(len(models)))
        order = order[round_index % len(order):] + order[:round_index % len(order)]
        for index in range(1, args.frames + 1):
            for k in order:
                started = time.perf_counter()
                renderers[k].render(index % max(frame_count, 1))
                totals[models[k]].append(1000.0 * (time.perf_counter() - started))
    first = statistics.median(totals[models[0]])
    first_opaque = statistics.median(renderers[0].timings["opaque"]) * 1000
    print(f"{args.scene} {' '.join(args.sets)}: {args.rounds} rounds x {args.frames} frames a model")
    print("| model | ms/frame | IQR | ratio | opaque pass ms | ratio |")
    print("|---|---|---|---|---|---|")
    for model, renderer in zip(models, renderers):
        total = statistics.median(totals[model])
        low, high = quartiles(totals[model])
        opaque = statistics.median(renderer.timings["opaque"]) * 1000
        print(f"| {model} | {total:.1f} | {low:.1f}-{high:.1f} | {total / first:.2f} | {opaque:.1f} | "
              f"{opaque / first_opaque:.2f} |")


if __name__ == "__main__":
    main()
