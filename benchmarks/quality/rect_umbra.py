"""The area light's umbra against the reference: a Cornell-box-like room lit by a 1 x 1 m
rectangle light over a Lambert floor with a short and a tall box (scenes/rect_umbra.yaml),
each setting's error on the floor by region. Writes rect_umbra.md and .json.

    python benchmarks/quality/rect_umbra.py    # about a minute on 2 cores

Regions of the floor from the reference's per-pixel shadow record (scenerender/tools/
penumbra.py; 8 x 8 samples a pixel, each ray towards its own point of the light): umbra
(every sample blocked), penumbra band, open floor. Umbra leak: the GPU's mean radiance
over the floor's umbra, in percent of the open floor's; shadowed floor: the GPU's mean
radiance over umbra and band together over the reference's. Also by the distance inside
the umbra (1, 2, 3 pixels from its edge), the light the GPU lets through there against the
reference's (a reference of 24 x 24 samples a pixel marks the umbra: at 8 x 8, a pixel
whose few unblocked points of the light drew no sample reads as umbra).
"""
from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path

import numpy as np
from scipy import ndimage

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))
sys.path.insert(0, str(HERE))

import scenerender  # noqa: E402
from scenerender.raytrace import render_reference  # noqa: E402
from scenerender.tools.penumbra import penumbra_errors, penumbra_regions  # noqa: E402
from environment_contact import frame_times  # noqa: E402  (the same alternation)

SCENE = HERE / "scenes" / "rect_umbra.yaml"
FLOOR = 0
VARIANTS = {
    "default": [],
    "map 2048": ["lights[0].shadows={size: 2048}"],
    "filter 128, blockers 64": ["render.shadows.filter_samples=128", "render.shadows.blocker_samples=64"],
    "casters: solid": ["render.shadows.casters=solid"],
}
# what the table read before the soft shadow's fade near the umbra where the light's centre
# is hidden (shaders/lighting/soft_shadows.glsl), and the alternatives measured for it
BEFORE = [
    "Before the fade near the umbra where the light's centre is hidden (the same table, the default:",
    "umbra leak 1.36 %, 1 px in 2.66 %, 2 px in 0.59 %, shadowed floor 1.022, band RMS 6.72 %, band mean",
    "+0.96 %; ms are of another moment). Tried, one at a time (256x192, leak % / band RMS % / band mean %):",
    "each open filter tap's segment to its point of the light marched through the map, solid behind",
    "a stored depth for half the casters' distance, at every light level: 0.01 / 18.2 / -10.6 (the empty space behind a box as the light's",
    "centre sees it counts as solid, so the penumbra's inner half goes dark); solid for 0.3 of the",
    "casters' distance (4 points): 0.14 / 10.7 / -5.1; a segment that must leave the map's surface continuously (no",
    "false hits behind a box, but a ray leaving a box through a side the map does not see is missed):",
    "1.05 / 6.39 / +0.55; the march near the umbra only, fading out from 10 % to 20 %, 30 %, 50 % of the",
    "light seen: 0.36 / 6.93 / +0.10, 0.27 / 7.67 / -1.01, 0.21 / 11.3 / -4.5 (and the sized lights'",
    "box tests' bands: the disk 5.6 -> 6.1 %, 7.4 % and the sphere 6.8 -> 8.2 %, 9.9 % at 20 % and",
    "30 %). Near the umbra the segments to the light's points gave the image the segment to its centre",
    "gives (0.36 against 0.35 %), which is p's own depth comparison: the default takes that, at 1.00-1.02",
    "of the frame's CPU time where the march took 1.06.",
    "",
    "`casters: solid` (render.shadows: a second map of the casters' back faces; each filter tap's ray",
    "marched through both at 8 points evenly spread in 1 / depth, blocked between a texel's front and",
    "back depths, an open surface or a box's edge thinner than a step taken one step thick; the",
    "receiver's bias at the first point only, a tenth of it past it). Tried with it (leak % / band RMS %",
    "/ band mean %): the receiver's whole bias at every point: 0.08 / 5.86 / +1.98 (it hides a box's",
    "top from rays that graze its edge: the box tests' bands +3.6 % for the rectangle, +15 % for the",
    "spot light); blocked only between the two depths, no step's thickness: much brighter bands (the",
    "box under a 1 x 0.5 m rectangle +11.6 %); the depths a ray spans between two points overlapping a",
    "texel's front and back: 0.20 / 12.1 / -5.9; the same from halfway between the points: 0.23 / 6.50",
    "/ +4.14; the 8 points evenly spread in depth rather than 1 / depth: 0.74 / 12.4 / +6.2; 16 points:",
    "the box tests' bands 1.4-3.6 points brighter (the last four with the whole bias).",
]
# the light drifts, so its map and soft shadow are drawn again every frame
DRIFT = ["lights[0].position={keys: [[0, [0.2, 3.9, -0.7]], [1, [0.3, 3.9, -0.7]]]}", "output={fps: 30, frames: 31}"]


def floor_errors(reference, fine, linear: np.ndarray) -> dict:
    """The floor's numbers (see the module's docstring) of the GPU's (H, W, 3) ``linear``
    against ``reference`` (its regions) and ``fine`` (the umbra's depth)."""
    errors = penumbra_errors(reference, linear)
    masks = penumbra_regions(reference)
    floor = (reference.object == FLOOR) & ~reference.mixed
    gpu = linear[..., :3].astype(np.float64).mean(axis=2)
    truth = reference.linear.astype(np.float64).mean(axis=2)
    umbra, shadowed = masks["umbra"] & floor, (masks["umbra"] | masks["penumbra"]) & floor
    lit = float(truth[masks["open"] & floor].mean())
    found = {"umbra leak %": 100.0 * float(gpu[umbra].mean()) / lit,
             "shadowed floor ratio": float(gpu[shadowed].mean() / truth[shadowed].mean()),
             "band RMS %": errors["penumbra_rms"], "band mean %": errors["penumbra_bias"],
             "open floor %": 100.0 * (float(gpu[masks["open"] & floor].mean()) / lit - 1.0)}
    inside = (fine.shadow[..., 0] >= 1.0) & (fine.object == FLOOR) & ~fine.mixed
    depth = ndimage.distance_transform_edt(fine.shadow[..., 0] >= 1.0)
    fine_truth = fine.linear.astype(np.float64).mean(axis=2)
    for pixels in (1, 2, 3):
        ring = inside & (depth >= pixels) & (depth < pixels + 1)
        found[f"umbra {pixels} px in %"] = 100.0 * float(gpu[ring].mean()) / lit
        found[f"umbra {pixels} px in, reference %"] = 100.0 * float(fine_truth[ring].mean()) / lit
    found["umbra pixels"] = int(umbra.sum())
    return found


def gpu_linear(overrides: list) -> np.ndarray:
    scene = scenerender.load(SCENE, overrides)
    with scenerender.Renderer(scene, want_linear=True) as renderer:
        return renderer.render(0).linear[..., :3].astype(np.float64)


def main() -> None:
    scene = scenerender.load(SCENE)
    reference = render_reference(scene, 0, spp=8)
    fine = render_reference(scene, 0, spp=24)
    results = {name: floor_errors(reference, fine, gpu_linear(overrides)) for name, overrides in VARIANTS.items()}
    for name, values in frame_times(VARIANTS, DRIFT, scene_path=SCENE).items():
        results[name]["ms"] = statistics.median(values)
    for name, row in results.items():
        print(name, {k: round(v, 2) for k, v in row.items()}, flush=True)
    (HERE / "rect_umbra.json").write_text(json.dumps(results, indent=1))
    columns = ["umbra leak %", "umbra 1 px in %", "umbra 2 px in %", "shadowed floor ratio", "band RMS %",
               "band mean %", "open floor %", "ms"]
    lines = ["# The area light's umbra: two boxes on a Lambert floor under a rectangle light", "",
             "Made by `python benchmarks/quality/rect_umbra.py` (see its docstring) on Mesa llvmpipe, 256x192,",
             "the default MSAA, against the reference at 8x8 samples a pixel (the umbra's depth: 24x24);",
             "ms: the median frame after the first as the light drifts, the settings taking turns.", "",
             "| setting | " + " | ".join(columns) + " |", "|---|" + "---|" * len(columns)]
    for name, row in results.items():
        lines.append(f"| {name} | " + " | ".join(f"{row[c]:.3f}" if "ratio" in c else f"{row[c]:.2f}" for c in columns) + " |")
    lines += ["", *BEFORE]
    (HERE / "rect_umbra.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
