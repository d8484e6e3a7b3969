"""scenerender against pyrender and a hand-written moderngl loop (the floor), on the same
scene, camera path and sizes. Prints a Markdown table.

    python benchmarks/compare/run_compare.py            # 640x480 and 1280x720, 120 frames (a few minutes)
    python benchmarks/compare/run_compare.py --quick    # 640x480 only, 30 frames

pyrender is optional: ``pip install -e '.[bench]'`` (it runs over EGL). Every measurement
is a whole process, and the three renderers are alternated (A B C A B C ...) so that a
busy shared machine slows them alike. Per process:

- frames/s with writes: PNG per frame; (N - 1) over the time between the first and the last
  file's modification times. scenerender runs as ``scenerender render``.
- frames/s render-only: frames rendered and read back, nothing encoded (steady state,
  frames 1..N-1, timed inside the process).
- first frame: from just before the process starts to the first PNG's modification time.
- whole command: the with-writes process from start to exit, start-up included.
- peak RSS: the process's maximum resident set (wait4).

``--tree PATH`` (repeatable) adds the scenerender of another checkout, such as a commit
before a change (``git worktree add /tmp/base COMMIT``), as a row of its own alternated with
the others: its ``scenerender render`` and its own ``run_scenerender.py``, with PATH first
on ``PYTHONPATH``.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import scene_def as S  # noqa: E402

RENDERERS = ("scenerender", "pyrender", "floor")
# scenerender's runner is each checkout's own benchmarks/compare/run_scenerender.py (tree_of)
RUNNERS = {"pyrender": HERE / "run_pyrender.py", "floor": HERE / "run_floor.py"}


def run_process(command: list[str], env: dict | None = None) -> tuple[float, float, str]:
    """(start time as time.time(), peak RSS in MB, stdout) of one whole process."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        started = time.time()
        process = subprocess.Popen(command, stdout=out, stderr=err, text=True, env=env)
        _, status, usage = os.wait4(process.pid, 0)  # reaps it: its own rusage, not the sum of all children
        process.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0), err.seek(0)
        if process.returncode != 0:
            raise RuntimeError(f"{' '.join(command)} failed:\n{err.read()[-2000:]}")
        return started, usage.ru_maxrss / 1024.0, out.read()


def tree_of(renderer: str) -> Path | None:
    """The checkout a scenerender row runs: this one, or PATH for "scenerender@PATH" (see
    --tree); None for the other renderers."""
    if renderer == "scenerender":
        return HERE.parent.parent
    return Path(renderer.split("@", 1)[1]) if renderer.startswith("scenerender@") else None


def environment(renderer: str) -> dict | None:
    tree = tree_of(renderer)
    if tree is None:
        return None
    return dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(tree), os.environ.get("PYTHONPATH")])))


def with_writes(renderer: str, size: str, samples: int, frames: int, folder: Path) -> dict:
    """One process writing PNGs: frames/s between first and last file, first-frame latency,
    the whole command's seconds."""
    if tree_of(renderer) is not None:
        command = [sys.executable, "-m", "scenerender", "render", str(S.SCENE_YAML), "-o", str(folder),
                   "--size", size, "--samples", str(samples), "--frames", f"0:{frames}", "--overwrite", "-q"]
    else:
        command = [sys.executable, str(RUNNERS[renderer]), "--size", size, "--samples", str(samples),
                   "--frames", str(frames), "--out", str(folder)]
    started, rss, _ = run_process(command, environment(renderer))
    whole = time.time() - started
    files = sorted(folder.glob("*.png"))
    if len(files) != frames:
        raise RuntimeError(f"{renderer} wrote {len(files)} frames, expected {frames}")
    first, last = files[0].stat().st_mtime, files[-1].stat().st_mtime
    for f in files:
        f.unlink()
    return {"fps_writes": (frames - 1) / max(last - first, 1e-9), "first_frame_s": first - started,
            "whole_s": whole, "rss_mb": rss}


def render_only(renderer: str, size: str, samples: int, frames: int) -> dict:
    tree = tree_of(renderer)
    runner = RUNNERS[renderer] if tree is None else tree / "benchmarks" / "compare" / "run_scenerender.py"
    command = [sys.executable, str(runner), "--size", size, "--samples", str(samples), "--frames", str(frames)]
    _, rss, out = run_process(command, environment(renderer))
    return {"fps_render": json.loads(out.strip().splitlines()[-1])["fps"], "rss_mb": rss}


def machine_line() -> str:
    from scenerender.gpu.gl_context import create_context, gl_info

    cpu = platform.processor() or platform.machine()
    try:
        cpu = next(line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    info = gl_info(create_context())
    return f"{cpu}, {os.cpu_count()} cores; {info['GL_RENDERER']}; OpenGL {info['GL_VERSION']}"


def measure(sizes, frames: int, rounds: int, renderers=RENDERERS, log=print) -> dict:
    """results[(renderer, size, samples)] -> lists of each figure over the rounds."""
    results: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        for size in sizes:
            for round_index in range(rounds):
                plan = [("writes", 4), ("render", 4), ("render", 1)]
                for kind, samples in plan:
                    for renderer in renderers:
                        if renderer == "pyrender" and samples != 4:
                            continue  # pyrender's offscreen target is always 4x MSAA
                        if kind == "writes":
                            folder = Path(tmp) / f"frames{renderers.index(renderer)}"
                            figures = with_writes(renderer, size, samples, frames, folder)
                        else:
                            figures = render_only(renderer, size, samples, frames)
                        log(f"  {size} round {round_index + 1} {kind:6s} {samples}x {renderer:11s} "
                            + " ".join(f"{k}={v:.2f}" for k, v in figures.items()), file=sys.stderr)
                        entry = results.setdefault((renderer, size, samples), {})
                        for key, value in figures.items():
                            entry.setdefault(key, []).append(value)
    return results


def table(results: dict, sizes, renderers=RENDERERS) -> str:
    def med(renderer, size, samples, key):
        values = results.get((renderer, size, samples), {}).get(key)
        return statistics.median(values) if values else None

    lines = ["| renderer | size | MSAA | frames/s with PNG writes | vs pyrender | vs floor | frames/s render-only "
             "| vs floor | render-only, no MSAA | vs floor | first frame | whole command | peak RSS |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for size in sizes:
        for renderer in renderers:
            fw = med(renderer, size, 4, "fps_writes")
            fr = med(renderer, size, 4, "fps_render")
            f1 = med(renderer, size, 1, "fps_render")
            ratio = lambda a, other, key, samples=4: (  # noqa: E731
                f"{a / med(other, size, samples, key):.2f}x" if a and med(other, size, samples, key) else "")
            rss = max(results[(renderer, size, 4)]["rss_mb"])
            ttff = med(renderer, size, 4, "first_frame_s")
            whole = med(renderer, size, 4, "whole_s")
            lines.append(
                f"| {renderer} | {size} | 4x | {fw:.1f} | {ratio(fw, 'pyrender', 'fps_writes')} | "
                f"{ratio(fw, 'floor', 'fps_writes')} | {fr:.1f} | {ratio(fr, 'floor', 'fps_render')} | "
                + (f"{f1:.1f} | {ratio(f1, 'floor', 'fps_render', 1)} | " if f1 else "n/a | | ")
                + f"{ttff:.2f} s | {whole:.2f} s | {rss:.0f} MB |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="640x480 only, 30 frames")
    parser.add_argument("--frames", type=int, help="frames per process (default 120; 30 with --quick)")
    parser.add_argument("--rounds", type=int, default=1, help="A B C rounds per size (medians over rounds)")
    parser.add_argument("--sizes", help="comma-separated WxH list (default 640x480,1280x720)")
    parser.add_argument("--tree", action="append", default=[], metavar="PATH",
                        help="another checkout's scenerender as a row of its own (repeatable)")
    args = parser.parse_args()
    for tree in args.tree:
        if not (Path(tree) / "scenerender" / "__init__.py").is_file():
            sys.exit(f"--tree {tree}: no scenerender package there (a checkout's root is expected)")
    renderers = ("scenerender", *(f"scenerender@{Path(tree).resolve()}" for tree in args.tree), "pyrender", "floor")
    sizes = (args.sizes.split(",") if args.sizes else ["640x480"] if args.quick else ["640x480", "1280x720"])
    frames = args.frames or (30 if args.quick else S.FRAMES)
    if not S.SCENE_YAML.exists():
        sys.exit("run benchmarks/compare/make_assets.py first")
    print(f"machine: {machine_line()}")
    command = " ".join(["python", "benchmarks/compare/run_compare.py", *sys.argv[1:]])
    print(f"command: `{command}`; {frames} frames per process, {args.rounds} round(s), whole processes "
          "alternated\n")
    results = measure(sizes, frames, args.rounds, renderers)
    print(table(results, sizes, renderers))


if __name__ == "__main__":
    main()
