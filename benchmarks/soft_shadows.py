"""What a light's size costs: ms per frame of a sphere light's soft shadow against the point
light's hard one, and of the soft shadow's blocker and filter reads.

Renders benchmarks/quality/scenes/sized_lights.yaml (a 1 m box beside a sphere light of
radius 0.3) with the light held still and the camera drifting, so the shadow map is drawn
once and every timed frame shades the floor again. The variants share one GL context and
take turns frame by frame (the order turning each frame), so a machine's changing load
falls on all of them alike; the time is ``Renderer.render`` (evaluation, every pass and the
readback), the first frames left out as warm-up.

    python benchmarks/soft_shadows.py [--frames 40] [--size 320x240]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.run.session import Renderer, load  # noqa: E402

WARM_UP = 3
SCENE = ROOT / "benchmarks" / "quality" / "scenes" / "sized_lights.yaml"
STILL_LIGHT = ["lights[0].position=[0.9, 2.5, 0]", "output.frames=1000",
               "camera.position={keys: [[0, [0, 4.5, 4.5]], [30, [0.3, 4.5, 4.5]]]}"]
VARIANTS = {
    "point light (radius 0), map 1024": ["lights[0].radius=0", "render.shadows.size=1024"],
    "radius 0.3: blocker 16, filter 32 (default)": [],
    "radius 0.3: blocker 8, filter 16": ["render.shadows.blocker_samples=8", "render.shadows.filter_samples=16"],
    "radius 0.3: blocker 16, filter 16": ["render.shadows.filter_samples=16"],
    "radius 0.3: blocker 32, filter 64": ["render.shadows.blocker_samples=32", "render.shadows.filter_samples=64"],
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("--size", default="320x240")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    gl = create_context()
    renderer_name = gl.info["GL_RENDERER"]
    renderers = {name: Renderer(load(SCENE, STILL_LIGHT + extra + [f"render.size=[{width}, {height}]"]), gl=gl)
                 for name, extra in VARIANTS.items()}
    times = {name: [] for name in renderers}
    try:
        for renderer in renderers.values():
            renderer.__enter__()
        names = list(renderers)
        for index in range(args.frames + WARM_UP):
            turn = index % len(names)
            for name in names[turn:] + names[:turn]:
                started = time.perf_counter()
                renderers[name].render(index)
                if index >= WARM_UP:
                    times[name].append(1000 * (time.perf_counter() - started))
    finally:
        for renderer in renderers.values():
            renderer.__exit__(None, None, None)
        gl.release()
    point = statistics.median(times[names[0]])
    print(f"{SCENE.name} at {width}x{height}, {args.frames} frames each, alternated on {renderer_name}")
    print("| variant | median ms/frame | IQR | against the point light |\n|---|---|---|---|")
    for name, values in times.items():
        quartiles = statistics.quantiles(values, n=4)
        median = statistics.median(values)
        print(f"| {name} | {median:.1f} | {quartiles[2] - quartiles[0]:.1f} | {median / point:.2f}x |")


if __name__ == "__main__":
    main()
