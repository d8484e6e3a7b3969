"""scenerender benchmarks: start-up, throughput, static-pass caching and memory over a long
run. Prints Markdown tables (docs/performance.md quotes them). Speed against error is measured by
`scenerender bench` against the CPU reference (benchmarks/quality/), and the comparison
with other renderers by benchmarks/compare/.

    python benchmarks/run.py                  # everything but the long memory run
    python benchmarks/run.py --memory 10000   # also RSS over 10,000 frames
    python benchmarks/run.py --only caching   # one section: startup throughput caching

Machines are shared and noisy: every comparison alternates its variants in one process
and reports medians and ratios, not single timings.
"""
from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "scenes"
BENCH = Path(__file__).resolve().parent


def machine_line(gl) -> str:
    from scenerender.gpu.gl_context import gl_info

    info = gl_info(gl)
    return (f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
            f"{info['GL_RENDERER']}; OpenGL {info['GL_VERSION']}")


def make_renderer(gl, scene, overrides=(), **options):
    import scenerender

    return scenerender.Renderer(scenerender.load(scene, list(overrides)), gl=gl, **options)


# -- start-up ------------------------------------------------------------------------------

def startup(runs: int = 5) -> list[str]:
    """Whole-process time of `scenerender render` for one frame (a fresh Python each time)."""
    rows = ["| one-frame render, whole process | median | min | max |", "|---|---|---|---|"]
    cases = {
        "minimal scene (1 box, default camera and lights), 640x480": BENCH / "scenes" / "minimal.yaml",
        "showcase frame 0, 640x480": SCENES / "showcase.yaml",
    }
    with tempfile.TemporaryDirectory() as out:
        for label, scene in cases.items():
            times = []
            for _ in range(runs + 1):
                started = time.perf_counter()
                subprocess.run([sys.executable, "-m", "scenerender", "render", str(scene), "-o", out,
                                "--frames", "0:1", "--format", "png", "--overwrite", "-q"], check=True)
                times.append(time.perf_counter() - started)
            times = times[1:]  # the first run warms the file cache
            rows.append(f"| {label} | {statistics.median(times):.2f} s | {min(times):.2f} s | {max(times):.2f} s |")
    return rows


# -- throughput ------------------------------------------------------------------------------

def throughput(frames: int = 120) -> list[str]:
    """Frames per second for a 120-frame 640x480 animation, as PNG sequence and as MP4."""
    rows = ["| 120 frames at 640x480 | format | seconds | frames/s |", "|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as out:
        for scene in ("showcase.yaml", "primitives.yaml"):
            for fmt in ("png", "mp4"):
                started = time.perf_counter()
                subprocess.run([sys.executable, "-m", "scenerender", "render", str(SCENES / scene), "-o",
                                str(Path(out) / fmt), "--format", fmt, "--size", "640x480", "--frames",
                                f"0:{frames}", "--set", "output.duration=null", "--set", f"output.frames={frames}",
                                "--overwrite", "-q"],
                               check=True)
                seconds = time.perf_counter() - started
                rows.append(f"| {scene} | {fmt} | {seconds:.1f} | {frames / seconds:.2f} |")
    return rows


# -- static-pass caching ---------------------------------------------------------------------

def caching(gl, frames: int = 24) -> list[str]:
    """Per-frame time with static passes cached (default) and re-run every frame,
    alternating frame by frame in one process."""
    rows = ["| scene (640x480) | cached ms/frame | uncached ms/frame | saved |", "|---|---|---|---|"]
    for scene, overrides in (("showcase.yaml", []), ("foggy_road.yaml", ["render.size=[640, 480]"]),
                             ("island.yaml", ["render.size=[640, 480]"])):
        cached = make_renderer(gl, SCENES / scene, overrides)
        uncached = make_renderer(gl, SCENES / scene, overrides, cache_static_passes=False)
        cached.render(0), uncached.render(0)
        times = {"cached": [], "uncached": []}
        for i in range(1, frames + 1):
            for name, renderer in (("cached", cached), ("uncached", uncached)):
                started = time.perf_counter()
                renderer.render(i)
                gl.finish()
                times[name].append(time.perf_counter() - started)
        cached.close(), uncached.close()
        a, b = statistics.median(times["cached"]), statistics.median(times["uncached"])
        rows.append(f"| {scene} | {a * 1000:.0f} | {b * 1000:.0f} | {100 * (1 - a / b):.0f}% |")
    return rows


# -- memory --------------------------------------------------------------------------------

def rss_mb() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def memory(gl, frames: int) -> list[str]:
    """Resident memory while one renderer draws ``frames`` frames of an animated scene
    (camera, objects, lights and a material all change every frame)."""
    renderer = make_renderer(gl, BENCH / "scenes" / "memory.yaml")
    rows = ["| frames rendered | RSS MB |", "|---|---|"]
    step = max(frames // 10, 1)
    started = time.perf_counter()
    for i in range(frames):
        renderer.render(i)
        if i % step == 0 or i == frames - 1:
            rows.append(f"| {i + 1} | {rss_mb():.1f} |")
    rows.append(f"| ({frames / (time.perf_counter() - started):.0f} frames/s at 160x120) | |")
    renderer.close()
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--only", nargs="*", default=["startup", "throughput", "caching"])
    parser.add_argument("--memory", type=int, default=0, help="also run N frames and report RSS")
    args = parser.parse_args()
    from scenerender.gpu.gl_context import create_context

    gl = create_context()
    print(f"machine: {machine_line(gl)}\n")
    sections = {"startup": lambda: startup(), "throughput": lambda: throughput(),
                "caching": lambda: caching(gl)}
    for name in args.only:
        print(f"## {name}\n")
        print("\n".join(sections[name]()) + "\n", flush=True)
    if args.memory:
        print("## memory\n")
        print("\n".join(memory(gl, args.memory)) + "\n")


if __name__ == "__main__":
    main()
