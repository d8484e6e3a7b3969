"""How long the steps of the environment's prefilter take (rendering.steps) and how soon a
render stops on SIGTERM, at the scene format's largest prefilter: prefilter_size 2048,
samples 4096, a 64x48 frame.

    python benchmarks/interruptible_work.py [--steps 12] [--signals 5] [--after 2]

Steps: ``--steps`` steps of each roughness level, spread evenly over it (pole to pole),
drawn (and waited for) one by one as the pass draws them, in one process: the longest, each level's median and its
texture lookups a second, and the whole prefilter's time estimated from those (each
level's median step time x its step count). Signals: ``--signals`` renders of the scene
as the command line runs them, each sent SIGTERM ``--after`` seconds after its
"GL renderer" line (the renderer made, the prefilter starting): the exit code and the
seconds from the signal to the exit.
"""
from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import scenerender  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.rendering.passes import environment  # noqa: E402
from scenerender.rendering.renderer import GraphRenderer  # noqa: E402
from scenerender.world.environment_files import write_hdr  # noqa: E402

SCENE = """render: {size: [64, 48], shading: pbr}
lights:
  - {type: environment, image: sky.hdr, prefilter_size: 2048, samples: 4096, visibility: false}
objects:
  - mesh: {primitive: sphere}
    material: {metallic: 1, roughness: 0.4}
"""


def write_scene(folder: Path) -> Path:
    """The scene and its sky (a gradient with a bright patch, 256x128) in ``folder``."""
    rows = np.linspace(0.0, 1.0, 128)[:, None, None]
    sky = np.broadcast_to(0.2 + 0.8 * rows * np.array([0.4, 0.6, 1.0]), (128, 256, 3)).copy()
    sky[20:36, 150:170] = (40.0, 36.0, 30.0)
    write_hdr(folder / "sky.hdr", sky.astype(np.float32))
    (folder / "scene.yaml").write_text(SCENE, encoding="utf-8")
    return folder / "scene.yaml"


def step_times(scene: Path, per_level: int) -> None:
    layout_steps, chosen = {}, {}  # level -> all its steps; the ones drawn
    original = environment.prefilter_steps

    def spread_steps(layout, samples):
        height = layout[2]
        for step in original(layout, samples):
            layout_steps.setdefault(step.rect[1] // height, []).append(step)
        for level, steps in layout_steps.items():
            picks = sorted({round(k) for k in np.linspace(0, len(steps) - 1, min(per_level, len(steps)))})
            chosen[level] = [steps[k] for k in picks]
        return [step for level in sorted(chosen) for step in chosen[level]]

    times = []

    def report(_what, fraction):
        times.append((time.perf_counter(), fraction))

    environment.prefilter_steps = spread_steps
    gl = create_context()
    renderer = GraphRenderer(scenerender.load(scene).world, gl, report_work=report)
    renderer.render(0)
    seconds = iter(later[0] - earlier[0] for earlier, later in zip(times, times[1:]))
    timed_by_level = {level: [next(seconds) for _ in chosen[level]] for level in sorted(chosen)}
    total = 0.0
    print(f"GL renderer: {gl.info['GL_RENDERER']}")
    print("| level | steps | step size | median s | longest s | lookups/s | level's estimate s |")
    print("|---|---|---|---|---|---|---|")
    for level, timed in timed_by_level.items():
        first = chosen[level][0]
        median = statistics.median(timed)
        estimate = median * len(layout_steps[level])
        total += estimate
        print(f"| {level} | {len(layout_steps[level])} | {first.rect[2]}x{first.rect[3]} | {median:.3f} | "
              f"{max(timed):.3f} | {first.work / median / 1e6:.0f} M | {estimate:.0f} |")
    longest = max(s for timed in timed_by_level.values() for s in timed)
    print(f"longest step: {longest:.3f} s (the mirror level's one step includes the shader's first use); "
          f"whole prefilter estimated at {total:.0f} s")


def signal_latency(scene: Path, runs: int, after: float) -> None:
    print("| run | exit code | s from SIGTERM to exit | last stderr line |")
    print("|---|---|---|---|")
    for run in range(runs):
        out = scene.parent / f"out{run}"
        process = subprocess.Popen([sys.executable, "-m", "scenerender", "render", str(scene), "-o", str(out)],
                                   stderr=subprocess.PIPE, text=True, cwd=Path(__file__).resolve().parent.parent,
                                   env={**os.environ, "PYTHONUNBUFFERED": "1"})
        lines = []
        for line in process.stderr:
            lines.append(line.rstrip())
            if line.startswith("GL renderer"):
                break
        time.sleep(after)
        sent = time.perf_counter()
        process.send_signal(signal.SIGTERM)
        rest = process.stderr.read()
        code = process.wait()
        took = time.perf_counter() - sent
        lines += rest.splitlines()
        left = sorted(p.name for p in out.iterdir() if p.name != ".scenerender.json") if out.exists() else []
        print(f"| {run} | {code} | {took:.2f} | {lines[-1]} | files left: {left or 'none'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=12, help="steps drawn of each roughness level")
    parser.add_argument("--signals", type=int, default=5, help="renders stopped by SIGTERM")
    parser.add_argument("--after", type=float, default=2.0, help="seconds into the prefilter the signal comes")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        scene = write_scene(Path(folder))
        if args.steps:
            step_times(scene, args.steps)
        if args.signals:
            signal_latency(scene, args.signals, args.after)


if __name__ == "__main__":
    main()
