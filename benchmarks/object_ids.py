"""What ``render --object-ids`` costs: ms per frame with and without the object-id pass.

Renders scenes/showcase.yaml at 640x480 with two renderers on one GL context, one with the
object-id pass and one without, alternating frame by frame (the same frame index for both,
so both see the same animation and the machine's load falls on both alike). The time is
``Renderer.render`` (evaluation, every pass and the readback), the first frames of each left
out as warm-up; the cost is also the median of the per-frame differences, which a
machine's changing load disturbs less. Also times encoding one frame's ids as a 16-bit PNG
(done on the encoder threads beside the renderer) and the object verdict of one frame pair
(``diff`` on frames with ids: a frame against the camera turned by a quarter pixel).

    python benchmarks/object_ids.py [--frames 60] [--size 640x480]
"""
from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from scenerender.compare.objects import measure_objects  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.run.session import Renderer, load  # noqa: E402
from scenerender.sinks.images import encode_grey16_png  # noqa: E402
from scenerender.tools import perturbation  # noqa: E402

WARM_UP = 3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--size", default="640x480")
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes" / "showcase.yaml")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    scene = load(args.scene, [f"render.size=[{width}, {height}]"])
    gl = create_context()
    renderer_name = gl.info["GL_RENDERER"]
    times = {False: [], True: []}
    last = None
    with Renderer(scene, gl=gl) as plain, Renderer(scene, gl=gl, object_ids=True) as with_ids:
        for index in range(args.frames + WARM_UP):
            order = (plain, with_ids) if index % 2 == 0 else (with_ids, plain)  # who goes first alternates too
            for renderer in order:
                started = time.perf_counter()
                frame = renderer.render(index)
                elapsed = time.perf_counter() - started
                if index >= WARM_UP:
                    times[renderer is with_ids].append(elapsed)
                if renderer is with_ids:
                    last = frame
        encode = []
        for _ in range(20):
            started = time.perf_counter()
            encode_grey16_png(last.object_ids)
            encode.append(time.perf_counter() - started)
        jitter = _jittered_pair(args.scene, width, height, gl)
    gl.release()
    verdict = []
    for _ in range(7):
        started = time.perf_counter()
        measure_objects(*jitter)
        verdict.append(time.perf_counter() - started)

    plain_ms, ids_ms = (1000 * statistics.median(times[k]) for k in (False, True))
    paired = 1000 * statistics.median(b - a for a, b in zip(times[False], times[True]))
    print(f"{args.scene.name} at {width}x{height}, {args.frames} frames each, alternated on {renderer_name}")
    print("| | median ms/frame |\n|---|---|")
    print(f"| without --object-ids | {plain_ms:.1f} |")
    print(f"| with --object-ids | {ids_ms:.1f} ({ids_ms - plain_ms:+.1f}, {100 * (ids_ms / plain_ms - 1):+.1f} %) |")
    print(f"| median of the per-frame differences (same frame, with - without) | {paired:+.1f} "
          f"({100 * paired / plain_ms:+.1f} %) |")
    print(f"| encoding one frame's ids (16-bit PNG, encoder thread) | {1000 * statistics.median(encode):.1f} |")
    print(f"| object verdict of one frame pair (quarter-pixel jitter) | {1000 * statistics.median(verdict):.1f} |")


def _jittered_pair(path: Path, width: int, height: int, gl):
    """The showcase case of the diff corpus at ``width`` x ``height`` (a still camera) and
    the same with the camera turned a quarter pixel, with ids: (reference, output, their ids)."""
    case = next(c for c in perturbation.CASES if c.scene == path.relative_to(ROOT).as_posix())
    case = dataclasses.replace(case, size=(width, height))
    render = perturbation.api_render_fn(gl)
    base = render(case.path, case.base(), case.frame)
    jittered = render(case.path, case.base() + case.jittered(0.25), case.frame)
    return base.pixels, jittered.pixels, base.ids, jittered.ids


if __name__ == "__main__":
    main()
