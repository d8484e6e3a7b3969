"""What render.indirect costs: scenes/interior.yaml still (the bake once; every frame is
then the graph's cached result), with its camera moving (the bake once, every frame
shades with the probes) and with its ball rolling (the objects change every frame, so
every frame bakes again), each against the same scene without the key, in one run,
alternated.

    python benchmarks/indirect_cost.py [FRAMES] [ROUNDS]    # default 6 frames, 3 rounds

Prints, per scene and setting, the first frame's time (the bake with it) and the median
of the frames after it, at 320x200, 4x MSAA (the scene's own).
"""
from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import scenerender  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402

SCENE = ROOT / "scenes" / "interior.yaml"
SIZE = "render.size=[320, 200]"
ROLLING = "objects[13].position={keys: [[0, [0.6, 0.3, 0.6]], [1, [-0.4, 0.3, 1.2]]]}"
WALKING = "camera.position={keys: [[0, [2.2, 1.5, 2.2]], [1, [1.6, 1.5, 2.4]]]}"
CASES = {
    "still, indirect off": [SIZE, "render.indirect=null"],
    "still, indirect on": [SIZE],
    "camera moving, indirect off": [SIZE, "render.indirect=null", WALKING],
    "camera moving, indirect on": [SIZE, WALKING],
    "rolling ball, indirect off": [SIZE, "render.indirect=null", ROLLING],
    "rolling ball, indirect on": [SIZE, ROLLING],
}


def frame_times(gl, overrides: list, frames: int) -> list[float]:
    scene = scenerender.Scene.from_yaml(SCENE.read_text(), SCENE.parent, overrides, name="interior")
    times = []
    with scenerender.Renderer(scene, gl=gl) as renderer:
        for index in range(frames):
            started = time.perf_counter()
            renderer.render(index)
            times.append(time.perf_counter() - started)
    return times


def main() -> None:
    frames = int(sys.argv[1]) if len(sys.argv) > 1 else 6
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    gl = create_context()
    firsts = {name: [] for name in CASES}
    laters = {name: [] for name in CASES}
    for _ in range(rounds):
        for name, overrides in CASES.items():
            times = frame_times(gl, overrides, frames)
            firsts[name].append(times[0])
            laters[name].extend(times[1:])
    print(f"{gl.info['GL_RENDERER']}, {frames} frames x {rounds} rounds")
    print("| scene | first frame s (median) | later frames ms (median) |")
    print("|---|---|---|")
    for name in CASES:
        print(f"| {name} | {statistics.median(firsts[name]):.2f} | {1000 * statistics.median(laters[name]):.1f} |")


if __name__ == "__main__":
    main()
