"""How long the diff rule takes on one 1920x1080 frame pair, in one process.

Renders the diff corpus's detail scene (tests/diff_corpus/) at 1920x1080 and again with the
camera turned by a quarter pixel (the corpus's hardest noise for the shift search), with
object ids, then times, alternated over several rounds: the whole verdict of one frame pair
(compare_images, a passing frame, so without SSIM and FLIP), its two views apart, the
object verdict the ids add, and an identical pair. Prints the median seconds of each.

With ``--command``, also the whole ``scenerender diff REF OUT`` command as a user runs it
(a fresh process: start-up, imports, reading the PNGs and the object ids, the verdict; no
--report), on folders rendered by ``scenerender render --object-ids`` at 1920x1080: an
identical pair, a quarter-pixel camera turn (passes) and a changed pair (the knobbly model
10% darker, fails), the three alternated over the rounds.

    python benchmarks/diff_speed.py [--rounds 7] [--command]
"""
from __future__ import annotations

import argparse
import dataclasses
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from scenerender.compare.diff import compare_images  # noqa: E402
from scenerender.compare.metrics import shift_residual, unexplained_difference  # noqa: E402
from scenerender.compare.objects import measure_objects  # noqa: E402
from scenerender.compare.rule import DEFAULT_RULE  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
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


def _render(case, out: Path, extra: list[str]) -> None:
    sets = [arg for key in case.base() + extra for arg in ("--set", key)]
    subprocess.run([sys.executable, "-m", "scenerender", "render", str(case.path), "-o", str(out), "--object-ids",
                    "-q", *sets], check=True, cwd=ROOT)


def command_times(rounds: int) -> dict:
    """Median seconds of the whole ``scenerender diff`` command per pair (see the notes)."""
    case = dataclasses.replace(next(c for c in perturbation.CASES if c.name == "detail"), size=(1920, 1080))
    with tempfile.TemporaryDirectory() as tmp:
        folders = {"reference": [], "identical pair (passes)": [], "quarter-pixel turn (passes)": case.jittered(0.25),
                   "changed pair, knobbly 10% darker (fails)": case.changes()["knobbly colour -10%"]}
        paths = {}
        for index, (name, extra) in enumerate(folders.items()):
            paths[name] = Path(tmp) / f"side{index}"
            _render(case, paths[name], extra)
        times = {name: [] for name in list(paths)[1:]}
        for _ in range(rounds):
            for name in times:
                start = time.perf_counter()
                subprocess.run([sys.executable, "-m", "scenerender", "diff", str(paths["reference"]),
                                str(paths[name])], cwd=ROOT, capture_output=True)
                times[name].append(time.perf_counter() - start)
    return {name: statistics.median(values) for name, values in times.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--command", action="store_true", help="also time the whole `scenerender diff` command")
    args = parser.parse_args()
    rounds = args.rounds
    if args.command:
        print(f"| whole `scenerender diff`, 1920x1080, object ids on both sides | median s ({rounds} rounds) |\n|---|---|")
        for name, seconds in command_times(rounds).items():
            print(f"| {name} | {seconds:.3f} |")
        print()
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
