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
10% darker, fails), the three alternated over the rounds. Each command runs with
PYTHONDONTWRITEBYTECODE unset (after a warm-up run), so its modules load from .pyc files as
a user's do; wall seconds and the CPU seconds of the process (user + system) are printed.
``--baseline DIR`` (a checkout of another version, e.g. ``git worktree add /tmp/base main``)
times the same command from there too, alternated with this checkout pair by pair.

    python benchmarks/diff_speed.py [--rounds 7] [--command [--baseline DIR]]
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import resource
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


def _timed_diff(checkout: Path, reference: Path, output: Path) -> tuple[float, float]:
    """Wall and CPU seconds (user + system) of one ``scenerender diff`` run from ``checkout``."""
    env = {key: value for key, value in os.environ.items() if key != "PYTHONDONTWRITEBYTECODE"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "scenerender", "diff", str(reference), str(output)], cwd=checkout,
                   env=env, capture_output=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime


def command_times(rounds: int, baseline: Path | None = None) -> dict:
    """(pair, checkout) -> (median wall s, median CPU s) of the whole ``scenerender diff``
    command (see the notes); the checkouts alternate within each pair and round."""
    case = dataclasses.replace(next(c for c in perturbation.CASES if c.name == "detail"), size=(1920, 1080))
    checkouts = {"this checkout": ROOT} if baseline is None else {"baseline": baseline, "this checkout": ROOT}
    with tempfile.TemporaryDirectory() as tmp:
        folders = {"reference": [], "identical pair (passes)": [], "quarter-pixel turn (passes)": case.jittered(0.25),
                   "changed pair, knobbly 10% darker (fails)": case.changes()["knobbly colour -10%"]}
        paths = {}
        for index, (name, extra) in enumerate(folders.items()):
            paths[name] = Path(tmp) / f"side{index}"
            _render(case, paths[name], extra)
        for checkout in checkouts.values():  # writes the .pyc files a user's install has
            _timed_diff(checkout, paths["reference"], paths["reference"])
        times = {(name, label): [] for name in list(paths)[1:] for label in checkouts}
        for _ in range(rounds):
            for name in list(paths)[1:]:
                for label, checkout in checkouts.items():
                    times[name, label].append(_timed_diff(checkout, paths["reference"], paths[name]))
    return {key: (statistics.median(w for w, _ in values), statistics.median(c for _, c in values))
            for key, values in times.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--command", action="store_true", help="also time the whole `scenerender diff` command")
    parser.add_argument("--baseline", type=Path, help="with --command: a checkout of another version to time too")
    parser.add_argument("--command-only", action="store_true", help="with --command: skip the in-process timings")
    args = parser.parse_args()
    rounds = args.rounds
    if args.command:
        print(f"| whole `scenerender diff`, 1920x1080, object ids on both sides | checkout | "
              f"median wall s ({rounds} rounds) | median CPU s |\n|---|---|---|---|")
        for (name, label), (wall, cpu) in command_times(rounds, args.baseline).items():
            print(f"| {name} | {label} | {wall:.3f} | {cpu:.3f} |")
        print()
        if args.command_only:
            return
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
