"""The filmed camera's settings at their defaults: each one's error against what it
approximates beside its cost. Writes film_exact.md and film_exact.json (or prints, with
--print).

    python benchmarks/quality/film_exact.py                  # about 10 minutes on 2 cores
    python benchmarks/quality/film_exact.py --tree /tmp/base --print   # another checkout's numbers
    (--references film.npz keeps the reference frames between runs)

Three measurements, all in one process and one GL context:

- lens: points of light 3 px across at 0.3 and 1.5 (focus 0.5) and at the focus, at f/0.5
  and f/1, 160x120, in front of black at infinity; each out-of-focus point's disc diameter
  from its second moment about its centroid (a uniform disc of diameter D has D^2 / 8),
  less the pinhole image's, as a ratio to the thin lens's circle of confusion (the worst of
  the four), the worst centroid offset from the pinhole image (px), and the growth of the
  point at the focus (px, the same measure);
- shutter: a box 40 px wide moving 40 px a frame at shutter 0.5, at whole and fractional
  pixel positions (0, 0.25, 0.5 px): each edge's ramp width (sqrt(12) times the standard
  deviation of where the linear coverage changes along the middle row) less the unblurred
  edge's, against the 20 px of its motion (the worst), and the most any pixel is brighter
  than the brightest of 64 sub-frames' 3 x 3 around it (8-bit levels; a box 10 px wide too);
- scenes/film.yaml at 320x180, frames 32 (the focus on the crate) and 36 (the pan starts),
  with its lens and shutter, its shutter alone and its lens alone (FILM_GROUPS): RMSE of
  the linear image (clipped to [0, 1]) against `scenerender reference` of the group's keys
  (4x4 rays a pixel, 32 instants over the shutter), and the median ms per frame, the
  variants taking turns frame by frame (benchmarks/film_cost.py).
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent


def _import_tree(tree: Path) -> None:
    """Import scenerender (and benchmarks/film_cost.py's helpers) from ``tree``."""
    sys.path.insert(0, str(tree))
    sys.path.insert(0, str(ROOT / "benchmarks"))


sys.path.insert(0, str(ROOT / "tests"))
from lens_points import COLUMNS, disc, points_scene, thin_lens_coc_px  # noqa: E402  (the lens tests' scene)

DEPTHS, FOCUS = (0.3, 1.5, 0.5), 0.5
APERTURES = (0.5, 1.0)

BOX = """
render: {{size: [160, 120], samples: 4, background: [0, 0, 0], shading: unlit}}
output: {{fps: 10, duration: 0.2}}
camera: {{position: [0, 0, 10], target: [0, 0, 0], projection: orthographic, height: 12, shutter: {shutter}}}
lights: []
objects:
  - mesh: {{primitive: box, size: [{size}, {size}, 2]}}
    position: {{keys: [[0, [{start}, {shift}, 0]], [0.2, [{end}, {shift}, 0]]]}}
    material: {{diffuse: [1, 1, 1]}}
"""

# film.yaml in three groups, each timed (alternated) and measured against the reference of
# its own keys: the lens and the shutter, the shutter alone, the lens alone; the first
# variant of each is the instant / pinhole its costs are compared with
FILM_GROUPS = {
    "lens and shutter": ([], [
        ("pinhole, instant", ["camera.aperture=null", "camera.shutter=0"]),
        ("sub-frames, 8", ["render.film_samples=8"]),
        ("sub-frames, 16 (default)", ["render.film_samples=16"]),
        ("sub-frames, 32", ["render.film_samples=32"]),
        ("velocity + gather", ["render.motion_blur=velocity", "render.depth_of_field=gather"]),
    ]),
    "shutter alone": (["camera.aperture=null"], [
        ("instant", ["camera.shutter=0"]),
        ("sub-frames, 16 (default)", ["render.film_samples=16"]),
        ("velocity", ["render.motion_blur=velocity"]),
    ]),
    "lens alone": (["camera.shutter=0"], [
        ("pinhole", ["camera.aperture=null"]),
        ("sub-frames, 16 (default)", ["render.film_samples=16"]),
        ("gather", ["render.depth_of_field=gather"]),
    ]),
}
FILM_FRAMES = (32, 36)

HEADER = """# The filmed camera: each setting's error at its default beside its cost

Made by `python benchmarks/quality/film_exact.py` (see its docstring for each measure) on
Mesa llvmpipe, 2 cores. "Its error": the setting against what it approximates, on scenes
made for it (the lens: points of light at two depths and two apertures against the thin
lens's circle of confusion; the shutter: a box moving 40 px a frame at shutter 0.5, its
smear against its 20 px of motion and its brightest pixel against 64 sub-frames'). Every
film.yaml variant is against the reference of its group's keys (the lens and the shutter,
the shutter alone, the lens alone; 4x4 rays a pixel, 32 instants), 320x180; ms/frame: the
median frame, the variants of a group taking turns frame by frame in one process.

"""


def render_levels(gl, text: str, frame: int = 0, overrides=()) -> np.ndarray:
    """(H, W) int: the 8-bit frame's red channel."""
    import scenerender

    with scenerender.Renderer(scenerender.Scene.from_yaml(text, ".", list(overrides)), gl=gl) as renderer:
        return renderer.render(frame).pixels[..., 0].astype(int)


def render(gl, text: str, frame: int = 0, overrides=()) -> np.ndarray:
    """(H, W) float64: the 8-bit frame's red channel in linear light."""
    from scenerender.colorspace import srgb_decode

    return srgb_decode(render_levels(gl, text, frame, overrides) / 255.0)


def lens_errors(gl, overrides: str) -> dict:
    """The worst disc ratio to the thin lens, centroid offset (px) and in-focus growth (px)."""
    sharp = render(gl, points_scene(DEPTHS, None, None, radius_px=1.5))
    ratios, offsets, growth = [], [], []
    for aperture in APERTURES:
        blurred = render(gl, points_scene(DEPTHS, aperture, FOCUS, overrides, radius_px=1.5))
        for column, depth in zip(COLUMNS, DEPTHS):
            (sx, sy, sharp_moment), (bx, by, moment) = disc(sharp, column), disc(blurred, column)
            diameter = math.sqrt(max(8.0 * (moment - sharp_moment), 0.0))
            if depth == FOCUS:
                growth.append(diameter)
            else:
                ratios.append(diameter / thin_lens_coc_px(depth, FOCUS, aperture))
                offsets.append(math.hypot(bx - sx, by - sy))
    worst = max(ratios, key=lambda r: abs(r - 1.0))
    return {"disc_ratio_worst": worst, "disc_ratio_range": [min(ratios), max(ratios)],
            "centroid_offset_px": max(offsets), "in_focus_growth_px": max(growth)}


def ramp_width(light: np.ndarray, columns: slice) -> float:
    change = np.abs(np.diff(light[60, columns]))
    x = np.arange(len(change)) + 0.5
    mean = (x * change).sum() / change.sum()
    return float(np.sqrt(12.0 * ((x - mean) ** 2 * change).sum() / change.sum()))


def box(size_px: int, shift_px: float, shutter: float) -> str:
    shift = shift_px / 10.0
    return BOX.format(shutter=shutter, size=size_px / 10.0, start=shift - 4, end=shift + 4, shift=shift)


def shutter_errors(gl, overrides: list) -> dict:
    """The smears (px) of both edges at each shift, and the worst seam excess (levels)."""
    from scipy import ndimage

    smears, excess = [], 0
    for shift in (0.0, 0.25, 0.5):
        sharp, blurred = render(gl, box(40, shift, 0.0), 1), render(gl, box(40, shift, 0.5), 1, overrides)
        for columns in (slice(30, 80), slice(80, 130)):
            smears.append(math.sqrt(ramp_width(blurred, columns) ** 2 - ramp_width(sharp, columns) ** 2))
        for size in (20, 10):
            levels = [render_levels(gl, box(size, shift, 0.5), 1, o) for o in (overrides, ["render.film_samples=64"])]
            excess = max(excess, int((levels[0] - ndimage.maximum_filter(levels[1], size=3)).max()))
    return {"smear_px_range": [min(smears), max(smears)], "seam_levels": excess}


def film_references(scene: str, sets: list, group: str, cache: Path | None) -> dict:
    """frame -> (H, W, 3) float32 linear reference of film.yaml with ``sets`` (a group's
    keys), kept in ``cache`` (an .npz, made if missing or without the group) between runs."""
    kept = dict(np.load(cache)) if cache is not None and cache.exists() else {}
    names = {frame: f"{group}/frame_{frame}" for frame in FILM_FRAMES}
    if all(name in kept for name in names.values()):
        return {frame: kept[name] for frame, name in names.items()}
    import scenerender
    from scenerender.raytrace import render_reference

    loaded = scenerender.load(scene, sets)
    references = {frame: render_reference(loaded, frame, spp=4, shutter_samples=32).linear for frame in FILM_FRAMES}
    if cache is not None:
        kept.update({names[frame]: image for frame, image in references.items()})
        np.savez_compressed(cache, **kept)
    return references


def film_errors(gl, frames: int, rounds: int, cache: Path | None) -> dict:
    """group -> variant -> {"ms": median ms/frame, "rmse_linear_frame_N": % against the
    group's reference}."""
    import scenerender
    from film_cost import rmse_percent, timings
    from scenerender.rendering.renderer import GraphRenderer

    scene, size = str(ROOT / "scenes" / "film.yaml"), ["render.size=[320, 180]"]
    found = {}
    for group, (keys, variants) in FILM_GROUPS.items():
        sets = size + keys
        totals = timings(scene, sets, variants, frames, rounds, gl)
        found[group] = {name: {"ms": statistics.median(totals[name])} for name, _ in variants}
        for frame, reference in film_references(scene, sets, group, cache).items():
            for name, overrides in variants:
                renderer = GraphRenderer(scenerender.load(scene, sets + overrides).world, gl, want_linear=True)
                linear = renderer.render(frame).linear
                renderer.release()
                found[group][name][f"rmse_linear_frame_{frame}"] = rmse_percent(np.clip(reference, 0, 1),
                                                                                 np.clip(linear, 0, 1))
    return found


def table(results: dict) -> str:
    lens, shutter = results["lens"], results["shutter"]
    rows = ["## Each setting's error at its default", "",
            "| setting | its error | goal |", "|---|---|---|"]
    for count in (4, 8, 12, 16, 32):
        row = lens[f"sub_frames_{count}"]
        rows.append(f"| `film_samples: {count}`{' (default)' if count == 16 else ''}, the lens | discs "
                    f"{row['disc_ratio_range'][0]:.3f}-{row['disc_ratio_range'][1]:.3f} of the thin lens's, "
                    f"centred within {row['centroid_offset_px']:.2f} px | 0.97-1.03, 0.25 px (8 and 16) |")
    sub = shutter["sub_frames_16"]
    rows.append(f"| `film_samples: 16` (default), the shutter | smear {sub['smear_px_range'][0]:.1f}-"
                f"{sub['smear_px_range'][1]:.1f} px for 20, seam {sub['seam_levels']} levels | 20 +- 1, <= 2 |")
    velocity = shutter["velocity"]
    rows.append(f"| `motion_blur: velocity` (24 taps) | smear {velocity['smear_px_range'][0]:.1f}-"
                f"{velocity['smear_px_range'][1]:.1f} px for 20, seam {velocity['seam_levels']} levels | 20 +- 1, <= 2 |")
    gather = lens["gather"]
    rows.append(f"| `depth_of_field: gather` (48 taps) | discs {gather['disc_ratio_range'][0]:.3f}-"
                f"{gather['disc_ratio_range'][1]:.3f}, the point at the focus grown by "
                f"{gather['in_focus_growth_px']:.2f} px | 0.90-1.10, <= 2 px |")
    for group, variants in results["film"].items():
        first = next(iter(variants.values()))["ms"]
        rows += ["", f"## film.yaml, 320x180: {group}", "",
                 "| variant | RMSE linear %, frame 32 / 36 | ms/frame | against the first |", "|---|---|---|---|"]
        for name, found in variants.items():
            rows.append(f"| {name} | {found['rmse_linear_frame_32']:.2f} / {found['rmse_linear_frame_36']:.2f} | "
                        f"{found['ms']:.0f} | {found['ms'] / first:.2f} |")
    return "\n".join(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tree", type=Path, default=ROOT, help="the checkout whose scenerender is measured")
    parser.add_argument("--print", action="store_true", help="print the table, write nothing")
    parser.add_argument("--frames", type=int, default=4, help="timed film.yaml frames a variant and round")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--references", type=Path, default=None,
                        help="an .npz keeping film.yaml's reference frames between runs (made if missing)")
    args = parser.parse_args()
    _import_tree(args.tree.resolve())
    from scenerender.gpu.gl_context import create_context

    gl = create_context()
    results = {
        "lens": {**{f"sub_frames_{n}": lens_errors(gl, f", film_samples: {n}") for n in (4, 8, 12, 16, 32)},
                 "gather": lens_errors(gl, ", depth_of_field: gather")},
        "shutter": {"sub_frames_16": shutter_errors(gl, ["render.film_samples=16"]),
                    "velocity": shutter_errors(gl, ["render.motion_blur=velocity"])},
        "film": film_errors(gl, args.frames, args.rounds, args.references),
    }
    text = table(results)
    if args.print:
        print(text)
        print(json.dumps(results, indent=1))
        return
    (HERE / "film_exact.json").write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    (HERE / "film_exact.md").write_text(HEADER + text + "\n", encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()
