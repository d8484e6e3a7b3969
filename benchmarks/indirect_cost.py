"""What render.indirect costs: scenes/interior.yaml still (the bake once; every frame is
then the graph's cached result), with its camera moving (the bake once, every frame
shades with the probes), with its ball rolling and with its sun moving: each bakes in
full in its first frame, then draws again only the probes the change touches, at most
render.indirect.probe_budget a frame (world/probe_updates.py), or, as before partial
updates, bakes every probe every frame ("full rebake"). Each against the same scene
without the key, renderer by renderer in one run, alternated.

    python benchmarks/indirect_cost.py [FRAMES] [ROUNDS] [ERROR_FRAMES] [BUDGETS]
    # default 6 frames, 3 rounds, 16 error frames, budget 32 (BUDGETS: e.g. 16,32,64)

Prints, per scene and setting, the first frame's time (the bake with it) and the median
of the frames after it, at 320x200, 4x MSAA (the scene's own); then, for the ball and
the sun, each frame's error of the partial updates against a full bake of that frame
(mean |difference| over the full bake's mean, linear light) and the probes drawn.
"""
from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import scenerender  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.rendering.renderer import GraphRenderer  # noqa: E402

SCENE = ROOT / "scenes" / "interior.yaml"
SIZE = "render.size=[320, 200]"
OFF = "render.indirect=null"
# the ball rolls 1.2 m over a second (24 frames); the sun turns 25 degrees over one
ROLLING = "objects[13].position={keys: [[0, [0.6, 0.3, 0.6]], [1, [-0.4, 0.3, 1.2]]]}"
SUN = "lights[0].direction={keys: [[0, [0.8, -0.5, -0.2]], [1, [0.75, -0.45, 0.2]]]}"
WALKING = "camera.position={keys: [[0, [2.2, 1.5, 2.2]], [1, [1.6, 1.5, 2.4]]]}"
FULL = {"indirect_updates": False}


def cases(budgets: list) -> dict:
    """name -> (scene overrides, renderer tuning)."""
    found = {
        "still, indirect off": ([SIZE, OFF], {}),
        "still, indirect on": ([SIZE], {}),
        "camera moving, indirect off": ([SIZE, OFF, WALKING], {}),
        "camera moving, indirect on": ([SIZE, WALKING], {}),
    }
    for name, motion in (("ball rolling", ROLLING), ("sun moving", SUN)):
        found[f"{name}, indirect off"] = ([SIZE, OFF, motion], {})
        found[f"{name}, full rebake"] = ([SIZE, motion], FULL)
        for budget in budgets:
            found[f"{name}, partial, budget {budget}"] = ([SIZE, motion, f"render.indirect.probe_budget={budget}"], {})
    return found


def load(overrides: list):
    return scenerender.Scene.from_yaml(SCENE.read_text(), SCENE.parent, overrides, name="interior")


def frame_times(gl, overrides: list, tuning: dict, frames: int) -> list[float]:
    renderer = GraphRenderer(load(overrides).world, gl, tuning=tuning)
    times = []
    try:
        for index in range(frames):
            started = time.perf_counter()
            renderer.render(index)
            renderer.gl.finish()
            times.append(time.perf_counter() - started)
    finally:
        renderer.release()
    return times


def partial_errors(gl, overrides: list, frames: int) -> list[tuple]:
    """(error against a full bake, probes drawn) of each frame of the partial updates."""
    partial = GraphRenderer(load(overrides).world, gl, want_linear=True)
    full = GraphRenderer(load(overrides).world, gl, want_linear=True, tuning=FULL)
    updates = partial.compiled.node("indirect_light").render_pass.updates
    found = []
    try:
        for index in range(frames):
            mine = partial.render(index).linear.astype(np.float64)
            truth = full.render(index).linear.astype(np.float64)
            found.append((float(np.abs(mine - truth).mean() / truth.mean()), int(updates.last.size)))
    finally:
        partial.release()
        full.release()
    return found


def main() -> None:
    frames = int(sys.argv[1]) if len(sys.argv) > 1 else 6
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    error_frames = int(sys.argv[3]) if len(sys.argv) > 3 else 16
    budgets = [int(b) for b in sys.argv[4].split(",")] if len(sys.argv) > 4 else [32]
    gl = create_context()
    table = cases(budgets)
    firsts = {name: [] for name in table}
    laters = {name: [] for name in table}
    for _ in range(rounds):
        for name, (overrides, tuning) in table.items():
            times = frame_times(gl, overrides, tuning, frames)
            firsts[name].append(times[0])
            laters[name].extend(times[1:])
    print(f"{gl.info['GL_RENDERER']}, {frames} frames x {rounds} rounds")
    print("| scene | first frame s (median) | later frames ms (median) |")
    print("|---|---|---|")
    for name in table:
        print(f"| {name} | {statistics.median(firsts[name]):.2f} | {1000 * statistics.median(laters[name]):.1f} |")
    print(f"\nerror of the partial updates against a full bake, frames 0-{error_frames - 1} "
          "(% of the mean; probes drawn)")
    for name, motion in (("ball rolling", ROLLING), ("sun moving", SUN)):
        for budget in budgets:
            found = partial_errors(gl, [SIZE, motion, f"render.indirect.probe_budget={budget}"], error_frames)
            cells = " ".join(f"{100 * error:.2f}({drawn})" for error, drawn in found)
            print(f"{name}, budget {budget}: {cells}")


if __name__ == "__main__":
    main()
