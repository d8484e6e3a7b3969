"""How long the steps of the environment's prefilter take (rendering.steps) and how soon a
render stops on SIGTERM, at the scene format's largest prefilter: prefilter_size 2048,
samples 4096, a 64x48 frame.

    python benchmarks/interruptible_work.py [--steps 12] [--signals 5] [--after 2] [--rounds 0 --at 128:512]

Steps: ``--steps`` steps of each roughness level, spread evenly over it (pole to pole),
drawn as the pass draws them, in one process, with its waits between them: the time
between two waits (what a signal may wait for), each level's median and longest, its
texture lookups a second, and the whole prefilter's time estimated from those.
Signals: ``--signals`` renders of the scene as the command line runs them, each sent
SIGTERM ``--after`` seconds after its "GL renderer" line (the renderer made, the
prefilter starting): the exit code and the seconds from the signal to the exit.
Against one draw: ``--rounds`` rounds of the prefilter at ``--at SIZE:SAMPLES`` (its
defaults: 128:512) in steps and in one draw (as before the steps), alternated.
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
from scenerender.rendering import steps as steps_module  # noqa: E402
from scenerender.rendering.pass_context import PassContext  # noqa: E402
from scenerender.rendering.passes import environment  # noqa: E402
from scenerender.rendering.renderer import GraphRenderer  # noqa: E402
from scenerender.rendering.steps import Step  # noqa: E402
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


def wait_groups(steps: list, every: int) -> list[list]:
    """``steps`` as the waits of rendering.steps.Waits split them: the steps drawn between
    two waits."""
    groups, sent = [[]], 0
    for step in steps:
        if 0 < sent and every < sent + step.work:
            groups.append([])
            sent = 0
        groups[-1].append(step)
        sent += step.work
    return groups


def step_times(scene: Path, per_level: int) -> None:
    layout_steps, chosen, strip = {}, {}, {}  # level -> all its steps; the ones drawn; a level's height
    original = environment.prefilter_steps

    def spread_steps(layout, samples):
        height = strip["height"] = layout[2]
        for step in original(layout, samples):
            layout_steps.setdefault(step.rect[1] // height, []).append(step)
        for level, steps in layout_steps.items():
            picks = sorted({round(k) for k in np.linspace(0, len(steps) - 1, min(per_level, len(steps)))})
            chosen[level] = [steps[k] for k in picks]
        return [step for level in sorted(chosen) for step in chosen[level]]

    waited = []
    wait = PassContext.checkpoint

    def timed_wait(ctx):
        wait(ctx)
        waited.append(time.perf_counter())

    environment.prefilter_steps = spread_steps
    PassContext.checkpoint = timed_wait
    gl = create_context()
    renderer = GraphRenderer(scenerender.load(scene).world, gl,
                             report_work=lambda what, fraction: fraction == 0.0 and waited.append(time.perf_counter()))
    renderer.render(0)
    groups = wait_groups([step for level in sorted(chosen) for step in chosen[level]], steps_module.STEP_LOOKUPS)
    height = strip["height"]
    by_level = {}
    for group, started, ended in zip(groups, waited, waited[1:]):  # the last group: waited for by the readback
        by_level.setdefault(group[-1].rect[1] // height, []).append((ended - started, sum(s.work for s in group)))
    print(f"GL renderer: {gl.info['GL_RENDERER']}; {steps_module.STEP_LOOKUPS:,} lookups between waits at most")
    print("| level | steps | step | timed waits | median s between waits | longest s | lookups/s | level's estimate s |")
    print("|---|---|---|---|---|---|---|---|")
    total = 0.0
    for level, timed in sorted(by_level.items()):
        first = chosen[level][0]
        seconds = [s for s, _ in timed]
        rate = sum(work for _, work in timed) / sum(seconds)
        estimate = sum(step.work for step in layout_steps[level]) / rate
        total += estimate
        print(f"| {level} | {len(layout_steps[level])} | {first.rect[2]}x{first.rect[3]} | {len(timed)} | "
              f"{statistics.median(seconds):.3f} | {max(seconds):.3f} | {rate / 1e6:.0f} M | {estimate:.0f} |")
    longest = max(s for timed in by_level.values() for s, _ in timed)
    print(f"longest time between waits: {longest:.3f} s (the first includes the shader's first use); "
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


def against_one_draw(folder: Path, rounds: int, size: int, samples: int) -> None:
    """The prefilter at ``size`` and ``samples`` in steps against one draw, as before the
    steps, alternated in one process: seconds of the pass, GPU-synchronised."""
    scene = folder / "against.yaml"
    scene.write_text(SCENE.replace("prefilter_size: 2048, samples: 4096", f"prefilter_size: {size}, samples: {samples}"),
                     encoding="utf-8")
    gl = create_context()
    stepped = environment.prefilter_steps

    def one_draw(layout, samples):
        return [Step((0, 0, layout[1], layout[2] * layout[0]), 1)]

    times = {"steps": [], "one draw": []}
    for _ in range(rounds):
        for name, steps in (("steps", stepped), ("one draw", one_draw)):
            environment.prefilter_steps = steps
            renderer = GraphRenderer(scenerender.load(scene).world, gl, profile=True)
            renderer.render(0)
            times[name].append(renderer.timings["environment_prefilter"][0])
            renderer.release()
    environment.prefilter_steps = stepped
    print(f"| prefilter at {size} px, {samples} samples | median s | each round's s |")
    print("|---|---|---|")
    for name, seconds in times.items():
        print(f"| {name} | {statistics.median(seconds):.3f} | {' '.join(f'{s:.2f}' for s in seconds)} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=12, help="steps drawn of each roughness level")
    parser.add_argument("--signals", type=int, default=5, help="renders stopped by SIGTERM")
    parser.add_argument("--after", type=float, default=2.0, help="seconds into the prefilter the signal comes")
    parser.add_argument("--rounds", type=int, default=0, help="rounds of the prefilter, steps against one draw")
    parser.add_argument("--at", default="128:512", help="SIZE:SAMPLES of the prefilter those rounds draw")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        scene = write_scene(Path(folder))
        if args.steps:
            step_times(scene, args.steps)
        if args.signals:
            signal_latency(scene, args.signals, args.after)
        if args.rounds:
            size, samples = map(int, args.at.split(":"))
            against_one_draw(Path(folder), args.rounds, size, samples)


if __name__ == "__main__":
    main()
