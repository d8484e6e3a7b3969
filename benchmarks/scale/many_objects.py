"""Many separate objects: N spheres of 256 triangles, each an object of its own, on a ground
under a shadowed sun; 24 orbit frames at 640x480 with 4x MSAA, the camera the only thing
that moves. Whole processes, alternated: scenerender (``render`` with PNG writes) and a
loop of plain moderngl draws (``plain_loop.py``: the same spheres, one draw each, a shadow
map drawn once, 3x3 PCF, MSAA resolved by a blit, PNG per frame).

    python benchmarks/scale/many_objects.py                    # 1,000 and 3,000 objects, 3 rounds
    python benchmarks/scale/many_objects.py --counts 1000 --rounds 5
    python benchmarks/scale/many_objects.py --write-scene /tmp/many.yaml --counts 1000   # the scene only

``--main /path/to/checkout`` adds a third runner: ``python -m scenerender`` run from that
checkout, to compare two versions in the same alternation.
"""
from __future__ import annotations

import argparse
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent

SIZE = (640, 480)
FRAMES = 24
SAMPLES = 4
SPHERE = {"radius": 0.25, "segments": 16, "rings": 9}  # 2 * 16 * 8 = 256 triangles
SUN_DIRECTION = (-0.4, -1.0, -0.3)


def sphere_positions(count: int, seed: int = 7) -> np.ndarray:
    """``count`` sphere centres resting on the ground (y = radius), on a jittered grid
    so no two overlap."""
    side = math.ceil(math.sqrt(count))
    spacing = 0.8
    rng = np.random.default_rng(seed)
    cells = np.array([(i % side, i // side) for i in range(count)], dtype=np.float64)
    xz = (cells - (side - 1) / 2.0) * spacing + rng.uniform(-0.15, 0.15, (count, 2))
    return np.column_stack([xz[:, 0], np.full(count, SPHERE["radius"]), xz[:, 1]])


def orbit(count: int) -> list[tuple[float, tuple]]:
    """The camera's keys: one turn of an orbit, ``FRAMES`` frames at 24 fps."""
    side = math.ceil(math.sqrt(count)) * 0.8
    radius, height = side * 0.9 + 2.0, side * 0.45 + 1.5
    keys = []
    for frame in range(FRAMES + 1):
        angle = 2.0 * math.pi * frame / FRAMES * 0.25
        keys.append((frame / 24.0, (radius * math.sin(angle), height, radius * math.cos(angle))))
    return keys


def scene_yaml(count: int) -> str:
    side = math.ceil(math.sqrt(count)) * 0.8 + 2.0
    lines = [
        f"# {count} spheres of 256 triangles, each an object of its own (benchmarks/scale/many_objects.py)",
        "scenerender: 1",
        f"render: {{size: [{SIZE[0]}, {SIZE[1]}], samples: {SAMPLES}, background: [0.5, 0.6, 0.75]}}",
        f"output: {{fps: 24, frames: {FRAMES}, format: png}}",
        "camera:",
        "  fov: 50",
        "  target: [0, 0, 0]",
        "  position:",
        "    interpolation: linear",
        "    keys:",
    ]
    lines += [f"      - [{t:.6f}, [{p[0]:.6f}, {p[1]:.6f}, {p[2]:.6f}]]" for t, p in orbit(count)]
    lines += [
        "lights:",
        f"  - {{name: sun, type: directional, direction: {list(SUN_DIRECTION)}, shadows: true}}",
        "  - {type: ambient, color: [0.2, 0.22, 0.26]}",
        "objects:",
        f"  - {{name: ground, mesh: {{primitive: plane, size: {side * 2:.3f}}}, cast_shadows: false}}",
    ]
    mesh = (f"{{primitive: sphere, radius: {SPHERE['radius']}, segments: {SPHERE['segments']},"
            f" rings: {SPHERE['rings']}}}")
    for i, (x, y, z) in enumerate(sphere_positions(count)):
        lines.append(f"  - {{name: s{i}, mesh: {mesh}, position: [{x:.4f}, {y:.4f}, {z:.4f}],"
                     f" material: {{base_color: [0.8, 0.55, 0.35]}}}}")
    return "\n".join(lines) + "\n"


def timed(command: list[str], cwd: Path) -> float:
    started = time.perf_counter()
    subprocess.run(command, cwd=cwd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--counts", type=int, nargs="+", default=[1000, 3000])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--main", help="another checkout to time in the same alternation")
    parser.add_argument("--write-scene", help="write the scene of the first count here and stop")
    args = parser.parse_args()
    if args.write_scene:
        Path(args.write_scene).write_text(scene_yaml(args.counts[0]))
        return
    print("| objects | runner | whole process, s (median) | runs | vs plain loop |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for count in args.counts:
            scene = Path(work) / f"many_{count}.yaml"
            scene.write_text(scene_yaml(count))
            out = Path(work) / "out"
            runners = {
                "scenerender": ([sys.executable, "-m", "scenerender", "render", str(scene), "-o", str(out),
                                 "--overwrite", "-q"], ROOT),
                "plain moderngl loop": ([sys.executable, str(HERE / "plain_loop.py"), "--count", str(count),
                                         "-o", str(Path(work) / "plain")], ROOT),
            }
            if args.main:
                runners["scenerender (other checkout)"] = (runners["scenerender"][0], Path(args.main))
            times: dict[str, list[float]] = {name: [] for name in runners}
            for _ in range(args.rounds):
                for name, (command, cwd) in runners.items():
                    times[name].append(timed(command, cwd))
            floor = statistics.median(times["plain moderngl loop"])
            for name, values in times.items():
                median = statistics.median(values)
                runs = " ".join(f"{v:.2f}" for v in values)
                print(f"| {count} | {name} | {median:.2f} | {runs} | {median / floor:.2f}x |", flush=True)


if __name__ == "__main__":
    os.environ.setdefault("PYTHONDONTWRITEBYTECODE", "1")
    main()
