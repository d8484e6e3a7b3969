"""Many separate objects: N spheres of 256 triangles, each an object of its own, on a ground
under a shadowed sun; 24 orbit frames at 640x480 with 4x MSAA, the camera the only thing
that moves. Whole processes, alternated: scenerender (``render`` with PNG writes) and a
loop of plain moderngl draws (``plain_loop.py``: the same spheres, one draw each, a shadow
map drawn once, 3x3 PCF, MSAA resolved by a blit, PNG per frame).

    python benchmarks/scale/many_objects.py                    # 1,000 and 3,000 objects, 3 rounds
    python benchmarks/scale/many_objects.py --counts 1000 --rounds 5
    python benchmarks/scale/many_objects.py --write-scene /tmp/many.yaml --counts 1000   # the scene only

``--main /path/to/checkout`` adds a third runner: ``python -m scenerender`` run from that
checkout, to compare two versions in the same alternation. ``--filly-python PYTHON`` adds
filly (Filament's Python binding) in that interpreter, rendering the same scene: one model
per sphere (filly's ``uv_sphere``, 256 triangles too), the ground, the sun with a 2048 px
shadow map, the same 24 camera positions, 4x MSAA, a PNG per frame (``FILLY_SCRIPT``).

    python benchmarks/scale/many_objects.py --counts 1000 --rounds 2 --filly-python /tmp/filly/bin/python
"""
from __future__ import annotations

import argparse
import json
import math
import textwrap
import os
import resource
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


# filly's side of the scene, run in filly's interpreter with the setup as a JSON file (3,000
# positions are too long for one command-line argument). The exposure, tone mapping and
# encoding are those of benchmarks/compare/run_filly.py; filly has no ambient light, which
# changes the spheres' shade, not the work.
FILLY_SCRIPT = textwrap.dedent("""
    import json, math, sys
    import numpy as np
    import filly
    from PIL import Image
    setup = json.loads(open(sys.argv[1]).read())
    with filly.Renderer() as renderer:
        scene = renderer.create_scene()
        scene.msaa = setup["samples"]
        scene.tone_mapping = "linear"
        scene.encoding = "srgb"
        scene.shadows = True
        scene.background = setup["background"] + [1.0]
        half = setup["ground_half"]
        corners = np.array([[-half, 0, -half], [half, 0, -half], [half, 0, half], [-half, 0, half]], np.float32)
        scene.create_mesh(corners, np.array([[0, 2, 1], [0, 3, 2]], np.uint32),
                          normals=np.tile(np.array([[0, 1, 0]], np.float32), (4, 1)), base_color=[0.8, 0.8, 0.8, 1])
        sphere = filly.shapes.uv_sphere(setup["radius"], segments=setup["segments"], rings=setup["rings"])
        for position in setup["positions"]:
            model = scene.create_mesh(sphere["positions"], sphere["indices"], normals=sphere["normals"],
                                      base_color=[0.8, 0.55, 0.35, 1.0], roughness=0.5)
            model.position = tuple(position)
        light = scene.add_directional_light(direction=setup["sun"], intensity=math.pi)
        light.casts_shadows = True
        light.shadow_map_size = 2048
        camera = renderer.create_camera()
        camera.set_perspective(fov_y_deg=setup["fov"], aspect=setup["size"][0] / setup["size"][1])
        camera.exposure = math.log2(1.0 / 1.2)  # EV100: exposure factor 1
        scene.camera = camera
        target = renderer.create_render_target(width=setup["size"][0], height=setup["size"][1])
        for index, position in enumerate(setup["cameras"]):
            camera.position = position
            camera.look_at([0.0, 0.0, 0.0])
            renderer.render(scene, target)
            Image.fromarray(target.read()[:, :, :3]).save(setup["output"].format(index=index))
""")


def filly_setup(count: int, output: Path) -> dict:
    """What FILLY_SCRIPT renders: scene_yaml's scene for ``count`` spheres. filly's
    ``uv_sphere`` with SPHERE's rings has 256 triangles, as scenerender's sphere."""
    return {"size": list(SIZE), "samples": SAMPLES, "background": [0.5, 0.6, 0.75],
            "ground_half": math.ceil(math.sqrt(count)) * 0.8 + 2.0, "radius": SPHERE["radius"],
            "segments": SPHERE["segments"], "rings": SPHERE["rings"], "positions": sphere_positions(count).tolist(),
            "sun": list(SUN_DIRECTION), "fov": 50.0, "cameras": [list(p) for _, p in orbit(count)[:FRAMES]],
            "output": str(output / "frame_{index:04d}.png")}


def timed(command: list[str], cwd: Path) -> tuple[float, float]:
    """(wall seconds, CPU seconds: user + system of the process and its children); the CPU
    time is the steadier of the two on a shared machine."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run(command, cwd=cwd, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--counts", type=int, nargs="+", default=[1000, 3000])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--main", help="another checkout to time in the same alternation")
    parser.add_argument("--write-scene", help="write the scene of the first count here and stop")
    parser.add_argument("--filly-python", help="an interpreter with filly: filly renders the scene too")
    args = parser.parse_args()
    if args.write_scene:
        Path(args.write_scene).write_text(scene_yaml(args.counts[0]))
        return
    print("| objects | runner | whole process, s (median) | CPU, s (median) | runs (wall) | vs plain loop |")
    print("|---|---|---|---|---|---|")
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
            if args.filly_python:
                (Path(work) / "filly").mkdir(exist_ok=True)
                setup = Path(work) / f"filly_{count}.json"
                setup.write_text(json.dumps(filly_setup(count, Path(work) / "filly")))
                (Path(work) / "filly_run.py").write_text(FILLY_SCRIPT)
                runners["filly"] = ([args.filly_python, str(Path(work) / "filly_run.py"), str(setup)], ROOT)
            times: dict[str, list[tuple[float, float]]] = {name: [] for name in runners}
            for _ in range(args.rounds):
                for name, (command, cwd) in runners.items():
                    times[name].append(timed(command, cwd))
            floor = statistics.median(wall for wall, _ in times["plain moderngl loop"])
            for name, values in times.items():
                median = statistics.median(wall for wall, _ in values)
                cpu = statistics.median(cpu for _, cpu in values)
                runs = " ".join(f"{wall:.2f}" for wall, _ in values)
                print(f"| {count} | {name} | {median:.2f} | {cpu:.2f} | {runs} | {median / floor:.2f}x |", flush=True)


if __name__ == "__main__":
    os.environ.setdefault("PYTHONDONTWRITEBYTECODE", "1")
    main()
