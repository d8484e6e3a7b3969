"""How long a one-frame render takes as a whole process: start, imports, loading the scene,
the GL context, shaders, one frame, one PNG. The job of a CI run that renders many short
scenes, where start-up is most of the time.

Each run is `python -m scenerender render SCENE -o TMP -q --overwrite --size WxH --frames 0:1`
run in a source tree (--tree, repeatable: compare a branch against main's checkout); the trees
take turns, the order flipped every round, and the medians of wall and CPU time (user + system,
the process and its children) are printed per tree and scene.

By default Python's compiled files (.pyc) are used as users and CI have them: one warm-up run
per tree writes them, with PYTHONDONTWRITEBYTECODE unset. --no-pyc deletes the trees'
scenerender/**/__pycache__ first and sets PYTHONDONTWRITEBYTECODE=1, so every run compiles
scenerender's modules again (the installed libraries keep their own compiled files).

    python benchmarks/startup.py                                   # minimal.yaml and gltf_pbr.yaml
    python benchmarks/startup.py --tree . --tree /tmp/main --rounds 9
    python benchmarks/startup.py --no-pyc --scene scenes/gltf_pbr.yaml
    python benchmarks/startup.py --tree . --tree /tmp/main --filly-python /tmp/filly/bin/python

With --filly-python, filly's Suzanne (one frame at 640x480, 4x MSAA, the scene and the filly
script of benchmarks/compare/run_filly.py) is one more scene, and filly rendering it in its
own process takes its turn with the trees.
"""
from __future__ import annotations

import argparse
import functools
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = ("benchmarks/scenes/minimal.yaml", "scenes/gltf_pbr.yaml")
FILLY = "filly"  # in the table: filly's own process, where a tree would be


def run_once(tree: Path, scene: str, size: str, output: Path, env: dict) -> tuple[float, float]:
    """(wall seconds, CPU seconds) of one whole render process in ``tree``."""
    command = [sys.executable, "-m", "scenerender", "render", str(tree / scene), "-o", str(output), "-q",
               "--overwrite", "--size", size, "--frames", "0:1"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run(command, cwd=tree, env={**env, "PYTHONPATH": str(tree)}, check=True,
                   stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def filly_suzanne(filly_python: str, folder: Path) -> tuple[str, list[str]]:
    """(the Suzanne scene file for scenerender, the command that renders it with filly), as
    benchmarks/compare/run_filly.py sets them up."""
    sys.path.insert(0, str(ROOT / "benchmarks" / "compare"))
    import run_filly

    found = subprocess.run([filly_python, "-c", "import filly; print(filly.samples.SUZANNE)"], check=True,
                           capture_output=True, text=True)
    glb = folder / "suzanne.glb"
    shutil.copyfile(found.stdout.strip().splitlines()[-1], glb)
    positions, target, fov = run_filly.camera_for(glb, 1)
    setup = {"glb": str(glb), "size": run_filly.SIZE, "fov": fov, "light": run_filly.LIGHT, "intensity": 1.5,
             "positions": positions, "target": target, "output": str(folder / "filly_{index:04d}.png"),
             "ground": None}
    (folder / "suzanne.yaml").write_text(run_filly.scene_yaml(glb, setup), encoding="utf-8")
    (folder / "filly_run.py").write_text(run_filly.FILLY_SCRIPT, encoding="utf-8")
    return str(folder / "suzanne.yaml"), [filly_python, str(folder / "filly_run.py"), json.dumps(setup)]


def run_filly_once(command: list[str], env: dict) -> tuple[float, float]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run(command, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def forget_compiled(tree: Path) -> None:
    for cache in (tree / "scenerender").rglob("__pycache__"):
        shutil.rmtree(cache, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tree", action="append", type=Path, help="a scenerender source tree (default: this one)")
    parser.add_argument("--scene", action="append", help=f"relative to each tree (default: {', '.join(SCENES)})")
    parser.add_argument("--size", default="640x480")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--no-pyc", action="store_true", help="compile scenerender's modules in every run")
    parser.add_argument("--filly-python", help="an interpreter with filly: add filly's Suzanne, and filly")
    args = parser.parse_args()
    trees = [tree.resolve() for tree in (args.tree or [ROOT])]
    scenes = args.scene or list(SCENES)
    with tempfile.TemporaryDirectory() as folder:
        filly = None
        if args.filly_python:
            suzanne, filly = filly_suzanne(args.filly_python, Path(folder))
            scenes.append(suzanne)
        measure(args, trees, scenes, filly)


def measure(args, trees: list[Path], scenes: list[str], filly: list[str] | None) -> None:
    env = {key: value for key, value in os.environ.items() if key != "PYTHONDONTWRITEBYTECODE"}
    if args.no_pyc:
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        for tree in trees:
            forget_compiled(tree)
    times = {(tree, scene): [] for tree in trees for scene in scenes}
    runners = {(tree, scene): functools.partial(run_once, tree, scene, args.size) for tree, scene in times}
    if filly is not None:
        times[FILLY, scenes[-1]] = []
        runners[FILLY, scenes[-1]] = lambda output, env: run_filly_once(filly, env)
    with tempfile.TemporaryDirectory() as folder:
        output = Path(folder)
        for runner in runners.values():  # the warm-up: compiled files written, shader caches filled
            runner(output, env)
        for round_index in range(args.rounds):
            for scene in scenes:
                order = [key for key in runners if key[1] == scene]
                for key in (order if round_index % 2 == 0 else order[::-1]):
                    times[key].append(runners[key](output, env))
    print(f"one frame at {args.size}, whole process, {args.rounds} rounds alternated, "
          f"{'no .pyc (compiled every run)' if args.no_pyc else 'with .pyc'}; medians")
    for scene in scenes:
        for tree in [key[0] for key in times if key[1] == scene]:
            walls, cpus = zip(*times[tree, scene])
            print(f"  {Path(scene).name:20s} {str(tree):28s} wall {statistics.median(walls):.3f} s  "
                  f"cpu {statistics.median(cpus):.3f} s  (wall: {', '.join(f'{w:.2f}' for w in walls)})")


if __name__ == "__main__":
    main()
