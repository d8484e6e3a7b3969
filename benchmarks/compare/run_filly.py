"""scenerender's pbr model against filly (Google Filament for Python) on one GLB: whole
processes alternated, and a side-by-side image with the numbers that say whether the two
agree (base colour, highlight place and size).

    python -m venv --system-site-packages /tmp/filly && /tmp/filly/bin/pip install filly
    python benchmarks/compare/run_filly.py --filly-python /tmp/filly/bin/python            # filly's Suzanne
    python benchmarks/compare/run_filly.py --filly-python /tmp/filly/bin/python --glb scenes/assets/models/pbr_props.glb

filly is not a dependency of scenerender: it runs in the interpreter given, as its own
process. Both render the same GLB with its own materials at 640x480, 4x MSAA, sRGB output,
one directional light and nothing else (no ambient, no environment, no tone mapping; with
--ground a grey rough ground under the model and the light's 2048 px shadow map), the camera looking at the model's bounds from +Z (or --camera). Light units: a
scenerender light of intensity I gives pi f I N.L; Filament gives f E N.L times the camera's
exposure, so filly's light is pi I lux with the exposure set to 1 (EV100 = log2(1 / 1.2)).

Timing: each run is a whole process (start, load, render, write one PNG, or --frames PNGs of
a turning camera); the two renderers take turns, --rounds times; medians and each round's
ratio are printed.
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import numpy as np
from PIL import Image

import scenerender

ROOT = Path(__file__).resolve().parents[2]
SIZE = (640, 480)
LIGHT = (-1.0, -1.0, -1.0)

FILLY_SCRIPT = textwrap.dedent("""
    import json, math, sys
    import filly
    from PIL import Image
    setup = json.loads(sys.argv[1])
    with filly.Renderer() as renderer:
        scene = renderer.create_scene()
        scene.msaa = 4
        scene.tone_mapping = "linear"
        scene.encoding = "srgb"
        scene.load(setup["glb"])
        camera = renderer.create_camera()
        camera.set_perspective(fov_y_deg=setup["fov"], aspect=setup["size"][0] / setup["size"][1])
        camera.exposure = math.log2(1.0 / 1.2)   # EV100: exposure factor 1
        scene.camera = camera
        light = scene.add_directional_light(direction=setup["light"], intensity=math.pi * setup["intensity"])
        if setup["ground"] is not None:
            import numpy as np
            y, half = setup["ground"]
            corners = np.array([[-half, y, -half], [half, y, -half], [half, y, half], [-half, y, half]], np.float32)
            scene.create_mesh(corners, np.array([[0, 2, 1], [0, 3, 2]], np.uint32),
                              normals=np.tile(np.array([[0, 1, 0]], np.float32), (4, 1)),
                              base_color=[0.5, 0.5, 0.5, 1.0], metallic=0.0, roughness=1.0)
            scene.shadows = True
            light.casts_shadows = True
            light.shadow_map_size = 2048
        target = renderer.create_render_target(width=setup["size"][0], height=setup["size"][1])
        for index, position in enumerate(setup["positions"]):
            camera.position = position
            camera.look_at(setup["target"])
            renderer.render(scene, target)
            Image.fromarray(target.read()[:, :, :3]).save(setup["output"].format(index=index))
""")


def scene_yaml(glb: Path, setup: dict) -> str:
    keys = ", ".join(f"[{i / 24.0:.6f}, {list(p)}]" for i, p in enumerate(setup["positions"]))
    position = f"{{keys: [{keys}]}}" if len(setup["positions"]) > 1 else list(setup["positions"][0])
    return textwrap.dedent(f"""
        render: {{size: {list(setup['size'])}, samples: 4, shading: pbr, background: [0, 0, 0]}}
        output: {{fps: 24, frames: {len(setup['positions'])}}}
        camera: {{position: {position}, target: {list(setup['target'])}, fov: {setup['fov']}}}
        lights:
          - {{type: directional, direction: {list(setup['light'])}, intensity: {setup['intensity']},
              shadows: {'{size: 2048}' if setup['ground'] is not None else 'false'}}}
        objects:
          - mesh: {glb.resolve()}
        """) + (ground_yaml(*setup["ground"]) if setup["ground"] is not None else "")


def ground_yaml(y: float, half: float) -> str:
    """A grey rough dielectric square under the model (the --ground option)."""
    return textwrap.indent(textwrap.dedent(f"""
        - mesh: {{primitive: plane, size: {2 * half}}}
          position: [0, {y}, 0]
          material: {{base_color: [0.5, 0.5, 0.5], metallic: 0, roughness: 1}}
        """), "  ")


def camera_for(glb: Path, frames: int) -> tuple[list, list, float]:
    """Positions (one per frame, turning 30 degrees about the bounds' centre), the target and
    the field of view that frames the model's bounds from +Z."""
    scene = scenerender.Scene.from_yaml(f"objects: [{{mesh: {glb.resolve()}}}]\n", glb.parent,
                                        asset_roots=[glb.resolve().parent])
    low, high = scene.world.objects[0].mesh.bounds()
    centre = (low + high) / 2.0
    radius = float(np.linalg.norm(high - low)) / 2.0
    distance = radius / math.tan(math.radians(22.5)) * 1.15
    positions = []
    for k in range(frames):
        angle = math.radians(30.0 * k / max(frames - 1, 1))
        positions.append([round(float(centre[0] + distance * math.sin(angle)), 6), round(float(centre[1]), 6),
                          round(float(centre[2] + distance * math.cos(angle)), 6)])
    return positions, [round(float(x), 6) for x in centre], 45.0


def ground_for(glb: Path) -> tuple[float, float]:
    """(height, half size) of a ground just under the model's bounds, ten times its size."""
    scene = scenerender.Scene.from_yaml(f"objects: [{{mesh: {glb.resolve()}}}]\n", glb.parent,
                                        asset_roots=[glb.resolve().parent])
    low, high = scene.world.objects[0].mesh.bounds()
    return round(float(low[1]), 6), round(float(np.max(high - low)) * 5.0, 6)


def run(command: list[str]) -> float:
    started = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - started


def compare(ours: np.ndarray, theirs: np.ndarray) -> dict:
    """Where the model is (not black in either), its mean colour in each, and the highlight:
    the pixels within 10 % of each image's brightest, their centroid and count."""
    covered = (ours.max(axis=2) > 8) & (theirs.max(axis=2) > 8)
    result = {"pixels": int(covered.sum())}
    for name, image in (("scenerender", ours), ("filly", theirs)):
        values = image.astype(float)
        brightness = values.sum(axis=2)
        peak = brightness[covered].max()
        highlight = covered & (brightness >= 0.9 * peak)
        ys, xs = np.nonzero(highlight)
        result[name] = {"mean_rgb": [round(float(v), 1) for v in values[covered].mean(axis=0)],
                        "highlight_pixels": int(highlight.sum()),
                        "highlight_centre": [round(float(xs.mean()), 1), round(float(ys.mean()), 1)]}
    diff = np.abs(ours.astype(float) - theirs.astype(float))[covered]
    result["mean_abs_difference"] = round(float(diff.mean()), 2)
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--filly-python", required=True, help="an interpreter with filly installed")
    parser.add_argument("--glb", type=Path, help="default: filly's own sample, Suzanne")
    parser.add_argument("--intensity", type=float, default=1.5)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--frames", type=int, default=1, help="frames a process renders (a turning camera)")
    parser.add_argument("--image", type=Path, help="where the side-by-side PNG goes")
    parser.add_argument("--ground", action="store_true",
                        help="a ground under the model, and the light's shadow on it (2048 px map)")
    args = parser.parse_args()
    glb = args.glb
    if glb is None:
        found = subprocess.run([args.filly_python, "-c", "import filly; print(filly.samples.SUZANNE)"],
                               check=True, capture_output=True, text=True)
        glb = Path(found.stdout.strip().splitlines()[-1])
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        positions, target, fov = camera_for(glb, args.frames)
        setup = {"glb": str(glb.resolve()), "size": SIZE, "fov": fov, "light": LIGHT, "intensity": args.intensity,
                 "positions": positions, "target": target, "output": str(folder / "filly_{index:04d}.png"),
                 "ground": ground_for(glb) if args.ground else None}
        (folder / "scene.yaml").write_text(scene_yaml(glb, setup), encoding="utf-8")
        (folder / "filly_run.py").write_text(FILLY_SCRIPT, encoding="utf-8")
        commands = {
            "scenerender": [sys.executable, "-m", "scenerender", "render", str(folder / "scene.yaml"), "-o",
                            str(folder / "ours"), "-q", "--overwrite", "--asset-root", str(glb.resolve().parent)],
            "filly": [args.filly_python, str(folder / "filly_run.py"), json.dumps(setup)],
        }
        times = {name: [] for name in commands}
        for round_index in range(args.rounds):
            order = list(commands) if round_index % 2 == 0 else list(commands)[::-1]
            for name in order:
                times[name].append(run(commands[name]))
        ours = np.asarray(Image.open(folder / "ours" / "frame_0000.png").convert("RGB"))
        theirs = np.asarray(Image.open(folder / "filly_0000.png").convert("RGB"))
        numbers = compare(ours, theirs)
        if args.image is not None:
            side = Image.new("RGB", (SIZE[0] * 2, SIZE[1]))
            side.paste(Image.fromarray(ours), (0, 0))
            side.paste(Image.fromarray(theirs), (SIZE[0], 0))
            side.save(args.image, optimize=True)
    ratios = [f / s for s, f in zip(times["scenerender"], times["filly"])]
    print(f"{glb.name}, {SIZE[0]}x{SIZE[1]}, {args.frames} frame(s) a process, {args.rounds} rounds alternated")
    for name, values in times.items():
        print(f"  {name}: median {statistics.median(values):.2f} s ({', '.join(f'{v:.2f}' for v in values)})")
    print(f"  filly / scenerender per round: {', '.join(f'{r:.2f}' for r in ratios)}")
    print(json.dumps(numbers, indent=2))


if __name__ == "__main__":
    main()
