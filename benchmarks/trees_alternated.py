"""One scene's frame time under two or more checkouts of scenerender, in one process, the
checkouts taking turns frame by frame (A B B A A B ...), so that a busy machine slows
them alike. Each checkout's package is imported on its own (its modules removed from
sys.modules before the next is imported), on one GL context. Prints, per checkout, the
median wall-clock and process-CPU ms a frame after the first (CPU counts llvmpipe's
threads, and is steadier than wall-clock on a loaded machine), and each one's ratio to
the first's.

    git archive COMMIT | tar -x -C /tmp/before      # a commit before a change
    python benchmarks/trees_alternated.py --tree before=/tmp/before --tree after=. \\
        scenes/gltf_pbr.yaml --set "render.size=[640,360]" --frames 60

The scene path is taken inside each checkout (relative paths), so each renders its own
copy of the scene and its assets.
"""
from __future__ import annotations

import argparse
import importlib
import statistics
import sys
import time
from pathlib import Path


def load_tree(root: Path, scene: str, overrides: list, gl):
    """(GraphRenderer of ``scene`` by the package in ``root``, its GL context, the scene's
    frame count): the package imported afresh from ``root``, its own copy of every module."""
    for name in [n for n in sys.modules if n == "scenerender" or n.startswith("scenerender.")]:
        del sys.modules[name]
    sys.path.insert(0, str(root))
    try:
        package = importlib.import_module("scenerender")
        if not Path(package.__file__).resolve().is_relative_to(root):
            raise SystemExit(f"{root}: imported scenerender from {package.__file__}")
        if gl is None:
            gl = importlib.import_module("scenerender.gpu.gl_context").create_context()
        renderer_module = importlib.import_module("scenerender.rendering.renderer")
        loaded = package.load(root / scene, overrides)
        renderer = renderer_module.GraphRenderer(loaded.world, gl)
    finally:
        sys.path.remove(str(root))
    renderer.render(0)  # programs compiled, static passes drawn
    return renderer, gl, loaded.frame_count


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="the scene, relative to each checkout")
    parser.add_argument("--tree", action="append", required=True, metavar="NAME=PATH",
                        help="a checkout (repeat; the first is the baseline)")
    parser.add_argument("--set", action="append", default=[], dest="overrides", help="a scene override, as render --set")
    parser.add_argument("--frames", type=int, default=40, help="frames a checkout after the first")
    args = parser.parse_args()
    trees = dict(tree.split("=", 1) for tree in args.tree)
    gl = None
    renderers = {}
    for name, path in trees.items():
        renderers[name], gl, count = load_tree(Path(path).resolve(), args.scene, args.overrides, gl)
    wall = {name: [] for name in renderers}
    cpu = {name: [] for name in renderers}
    order = list(renderers)
    for frame in range(1, args.frames + 1):
        for name in (order if frame % 2 else order[::-1]):
            started, used = time.perf_counter(), time.process_time()
            renderers[name].render(1 + (frame - 1) % max(count - 1, 1))  # the scene's frames after the first, again
            wall[name].append((time.perf_counter() - started) * 1000.0)
            cpu[name].append((time.process_time() - used) * 1000.0)
    base = order[0]
    print("| checkout | wall ms/frame | vs first | CPU ms/frame | vs first |")
    print("|---|---|---|---|---|")
    for name in order:
        w, c = statistics.median(wall[name]), statistics.median(cpu[name])
        print(f"| {name} | {w:.2f} | {w / statistics.median(wall[base]):.3f} | {c:.2f} | "
              f"{c / statistics.median(cpu[base]):.3f} |")
    for renderer in renderers.values():
        renderer.release()
    gl.release()


if __name__ == "__main__":
    main()
