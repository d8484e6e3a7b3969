"""How long the diff rule takes on one 1920x1080 frame pair, in one process.

Renders the diff corpus's detail scene (tests/diff_corpus/) at 1920x1080 and again with the
camera turned by a quarter pixel (the corpus's hardest noise for the shift search), with
object ids, then times, alternated over several rounds: the whole verdict of one frame pair
(compare_images, a passing frame, so without SSIM and FLIP), its two views apart, the
object verdict the ids add, and an identical pair. Prints the median seconds of each.

    python benchmarks/diff_speed.py [--rounds 7]
"""
from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from scenerender.compare.diff import compare_images  # noqa: E402
from scenerender.compare.metrics import shift_residual, unexplained_difference  # noqa: E402
from scenerender.compare.objects import measure_objects  # noqa: E402
from scenerender.compare.rule import DEFAULT_RULE  # noqa: E402
from scenerender.gpu.context import create_context  # noqa: E402
from scenerender.tools import perturbation  # noqa: E402


def frame_pair():
    case = dataclasses.replace(next(c for c in perturbation.CASES if c.name == "detail"), size=(1920, 1080))
    gl = create_context()
    try:
        render = perturbation.api_render_fn(gl)
        base = render(case.path, case.base(), case.frame)
        jittered = render(case.path, case.base() + case.jittered(0.25), case.frame)
    finally:
        gl.release()
    return base, jittered


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=7)
    rounds = parser.parse_args().rounds
    base_shot, jittered_shot = frame_pair()
    base, jittered = base_shot.pixels, jittered_shot.pixels
    ids = (base_shot.ids, jittered_shot.ids)
    tolerance = DEFAULT_RULE.aa_tolerance
    work = {
        "verdict, quarter-pixel jitter (passes)": lambda: compare_images("f", base, jittered, keep_images=False),
        "  of which: outside the ranges": lambda: unexplained_difference(base, jittered, tolerance),
        "  of which: left after the shift": lambda: shift_residual(base, jittered, tolerance),
        "verdict with object ids, quarter-pixel jitter (passes)": lambda: compare_images(
            "f", base, jittered, keep_images=False, object_ids=ids),
        "  of which: by object": lambda: measure_objects(base, jittered, *ids, tolerance=tolerance),
        "verdict, identical frames": lambda: compare_images("f", base, base.copy(), keep_images=False),
        "verdict with object ids, identical frames": lambda: compare_images(
            "f", base, base.copy(), keep_images=False, object_ids=(ids[0], ids[0])),
    }
    times = {name: [] for name in work}
    for _ in range(rounds):
        for name, run in work.items():
            start = time.perf_counter()
            run()
            times[name].append(time.perf_counter() - start)
    print(f"| 1920x1080 frame pair | median s ({rounds} rounds) |\n|---|---|")
    for name, values in times.items():
        print(f"| {name} | {statistics.median(values):.3f} |")


if __name__ == "__main__":
    main()
