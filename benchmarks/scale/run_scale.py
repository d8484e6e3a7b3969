"""Scale benchmarks: a 1M-triangle OBJ loaded cold and from the mesh cache, 10,000
instances, a 3840x2160 frame, and memory over a 10,000-frame animation. Each section
prints a Markdown table.

    python benchmarks/scale/run_scale.py                      # every section
    python benchmarks/scale/run_scale.py --only mesh instances
    python benchmarks/scale/run_scale.py --only animation --frames 2000

Loads run in fresh processes (the way a user meets them: a new `scenerender render`), with
a cache folder of their own so the user's cache is neither used nor touched.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE.parent))  # benchmarks/run.py: the memory run is reused as it is

SECTIONS = ("encode", "mesh", "instances", "frame4k", "animation")


# -- the PNG encoder pool ------------------------------------------------------------------

def encode_pool(frames: int = 48, rounds: int = 3) -> list[str]:
    """Frames/s of the writing path alone (ThreadedSink -> PNG files), fed one rendered
    showcase frame over and over, with 1, 2 and 4 encoder threads: how encoding scales with
    cores when the renderer does not compete for them."""
    import numpy as np
    import scenerender
    from scenerender.gpu.gl_context import create_context
    from scenerender.sinks import ImageSequenceSink, ThreadedSink
    from scenerender.machine import available_cores

    with scenerender.Renderer(scenerender.load(ROOT / "scenes" / "showcase.yaml", ["render.size=[640,480]"]),
                              gl=create_context()) as renderer:
        pixels = np.array(renderer.render(30).pixels)

    class Frame:
        def __init__(self, index):
            self.index, self.pixels, self.linear = index, pixels, None

    counts = (1, 2, 4)
    rates: dict[int, list[float]] = {n: [] for n in counts}
    with tempfile.TemporaryDirectory() as work:
        for _ in range(rounds):
            for n in counts:
                sink = ThreadedSink(ImageSequenceSink(Path(work) / str(n), "png", "f{frame:04d}"), encoders=n)
                started = time.perf_counter()
                for i in range(frames):
                    sink.write(Frame(i))
                sink.close()
                rates[n].append(frames / (time.perf_counter() - started))
    rows = [f"| PNG writes only, 640x480 showcase frame, {available_cores()} cores | frames/s (median of {rounds}) |",
            "|---|---|"]
    rows += [f"| {n} encoder thread{'s' if n > 1 else ''} | {statistics.median(rates[n]):.0f} |" for n in counts]
    return rows


# -- 1M-triangle OBJ -----------------------------------------------------------------------

def write_grid_obj(path: Path, side: int) -> int:
    """A wavy (side x side)-vertex grid with texture coordinates and normals, as an
    exporter writes it (every corner v/vt/vn) -> its triangle count, 2 * (side - 1)**2."""
    import numpy as np

    u, v = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    height = 0.05 * np.sin(12 * u) * np.cos(9 * v)
    positions = np.stack([u - 0.5, height, v - 0.5], axis=-1).reshape(-1, 3)
    texcoords = np.stack([u, v], axis=-1).reshape(-1, 2)
    quads = np.arange(side * side).reshape(side, side)[:-1, :-1].reshape(-1) + 1
    corners = np.stack([quads, quads + side, quads + side + 1, quads + 1], axis=-1)
    with open(path, "w") as out:
        out.write("# generated grid\n")
        np.savetxt(out, positions, fmt="v %.6f %.6f %.6f")
        np.savetxt(out, texcoords, fmt="vt %.6f %.6f")
        out.write("vn 0 1 0\n" * len(positions))
        triangles = np.concatenate([corners[:, [0, 1, 2]], corners[:, [0, 2, 3]]])
        np.savetxt(out, np.repeat(triangles, 3, axis=1), fmt="f %d/%d/%d %d/%d/%d %d/%d/%d")
    return len(triangles)


_LOAD_ONE = """
import sys, time
from pathlib import Path
from scenerender.errors import Warnings
from scenerender.mesh import load_mesh
started = time.perf_counter()
mesh = load_mesh(Path(sys.argv[1]), warnings=Warnings())
print(time.perf_counter() - started, mesh.triangle_count)
"""


def _load_in_fresh_process(obj: Path, env: dict) -> float:
    done = subprocess.run([sys.executable, "-c", _LOAD_ONE, str(obj)], env=env, check=True,
                          capture_output=True, text=True)
    return float(done.stdout.split()[0])


def mesh_cache(runs: int = 3) -> list[str]:
    """Seconds to load a 1M-triangle OBJ: parsed (cache off), first load (parse + store),
    cached loads (each in a fresh process)."""
    rows = ["| 1M-triangle OBJ load (fresh process, load_mesh only) | seconds |", "|---|---|"]
    with tempfile.TemporaryDirectory() as work:
        obj = Path(work) / "grid.obj"
        triangles = write_grid_obj(obj, 709)
        env = dict(os.environ, SCENERENDER_CACHE_DIR=str(Path(work) / "cache"))
        env.pop("SCENERENDER_CACHE", None)
        uncached = [_load_in_fresh_process(obj, dict(env, SCENERENDER_CACHE="0")) for _ in range(runs)]
        first = _load_in_fresh_process(obj, env)
        cached = [_load_in_fresh_process(obj, env) for _ in range(runs)]
        entry = sum(p.stat().st_size for p in (Path(work) / "cache").rglob("*.npz"))
        rows += [f"| file: {triangles:,} triangles, {obj.stat().st_size / 2**20:.0f} MB; "
                 f"cache entry {entry / 2**20:.0f} MB | |",
                 f"| parse, cache off (median of {runs}) | {statistics.median(uncached):.2f} |",
                 f"| first load: parse + store | {first:.2f} |",
                 f"| second and later loads: from the cache (median of {runs}) | {statistics.median(cached):.2f} |"]
    return rows


# -- 10,000 instances ------------------------------------------------------------------------

INSTANCES_SCENE = """\
render: {{size: [640, 480], samples: 4}}
output: {{fps: 30, frames: {frames}}}
camera:
  position: {{keys: [[0, [0, 14, 30]], [2, [30, 14, 0]]], loop: true}}
  target: [0, 0, 0]
lights:
  - {{type: directional, direction: [-0.4, -1, -0.3], shadows: true}}
objects:
  - mesh: {{primitive: plane, size: 60}}
    cast_shadows: false
  - mesh: {{primitive: sphere, radius: 0.15, segments: 12, rings: 6}}
    instances:
      random: {{count: {count}, seed: 3, position: {{min: [-20, 0, -20], max: [20, 8, 20]}},
               scale: {{min: 0.5, max: 1.5}}}}
"""


def instances(count: int = 10_000, frames: int = 10) -> list[str]:
    """Load time and ms per frame (render-only and whole process with PNG writes) of a
    scene with ``count`` random instances of a small sphere."""
    import scenerender
    from scenerender.gpu.gl_context import create_context
    from scenerender.mesh.primitives import sphere

    triangles = sphere(0.15, 12, 6).triangle_count
    rows = [f"| {count:,} instances of a {triangles}-triangle sphere ({count * triangles:,} triangles), "
            "640x480, 4x MSAA, shadowed | value |", "|---|---|"]
    with tempfile.TemporaryDirectory() as work:
        scene = Path(work) / "instances.yaml"
        scene.write_text(INSTANCES_SCENE.format(count=count, frames=frames))
        started = time.perf_counter()
        renderer = scenerender.Renderer(scenerender.load(scene), gl=create_context())
        rows.append(f"| scene load + renderer set-up, s | {time.perf_counter() - started:.2f} |")
        renderer.render(0)
        times = []
        for i in range(1, frames):
            started = time.perf_counter()
            renderer.render(i)
            times.append(time.perf_counter() - started)
        renderer.close()
        rows.append(f"| render-only, ms per frame (median of {frames - 1}) | {statistics.median(times) * 1000:.0f} |")
        started = time.perf_counter()
        subprocess.run([sys.executable, "-m", "scenerender", "render", str(scene), "-o", str(Path(work) / "out"),
                        "--overwrite", "-q"], check=True)
        whole = time.perf_counter() - started
        rows.append(f"| `scenerender render` with PNG writes, whole process, {frames} frames, s | {whole:.2f} |")
    return rows


# -- one 3840x2160 frame -------------------------------------------------------------------

def frame_4k(runs: int = 3) -> list[str]:
    """A 3840x2160 showcase frame: render, PNG encode, and the whole command."""
    import scenerender
    from scenerender.gpu.gl_context import create_context
    from scenerender.sinks.images import encode_image

    scene = ROOT / "scenes" / "showcase.yaml"
    rows = ["| showcase frame at 3840x2160, 4x MSAA | median of %d |" % runs, "|---|---|"]
    renderer = scenerender.Renderer(scenerender.load(scene, ["render.size=[3840,2160]"]), gl=create_context())
    renderer.render(0)  # compiles shaders and builds the static passes
    render_times, encode_times = [], []
    for i in range(1, runs + 1):
        started = time.perf_counter()
        frame = renderer.render(i)
        render_times.append(time.perf_counter() - started)
        started = time.perf_counter()
        data = encode_image(frame.pixels, "png")
        encode_times.append(time.perf_counter() - started)
    renderer.close()
    rows += [f"| render (incl. readback), s | {statistics.median(render_times):.2f} |",
             f"| PNG encode, s ({len(data) / 2**20:.1f} MB) | {statistics.median(encode_times):.2f} |"]
    with tempfile.TemporaryDirectory() as work:
        started = time.perf_counter()
        subprocess.run([sys.executable, "-m", "scenerender", "render", str(scene), "-o", str(Path(work) / "f.png"),
                        "--size", "3840x2160", "--frames", "0:1", "--format", "png", "-q"], check=True)
        rows.append(f"| `scenerender render --size 3840x2160 --frames 0:1 --format png`, whole process, s | "
                    f"{time.perf_counter() - started:.2f} |")
    return rows


# -- long animation ------------------------------------------------------------------------

def animation(frames: int) -> list[str]:
    """RSS over ``frames`` frames of an animated scene (benchmarks/run.py's memory run)."""
    from run import memory  # benchmarks/run.py

    from scenerender.gpu.gl_context import create_context

    return memory(create_context(), frames)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--only", nargs="*", default=list(SECTIONS), choices=SECTIONS)
    parser.add_argument("--frames", type=int, default=10_000, help="frames of the animation section")
    parser.add_argument("--instances", type=int, default=10_000)
    args = parser.parse_args()
    sections = {"encode": encode_pool, "mesh": mesh_cache, "instances": lambda: instances(args.instances),
                "frame4k": frame_4k, "animation": lambda: animation(args.frames)}
    for name in args.only:
        print(f"## {name}\n")
        print("\n".join(sections[name]()) + "\n", flush=True)


if __name__ == "__main__":
    main()
