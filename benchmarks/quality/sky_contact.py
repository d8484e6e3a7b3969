"""The sky's contact shadows against the reference: a box and a tall box on a ground under a
sky with no sun (scenes/sky_contact.yaml), each region's error and, for the ground near the
boxes, the blotches. Writes sky_contact.md and .json.

    python benchmarks/quality/scenes/make_open_sky.py   # open_sky.hdr (committed)
    python benchmarks/quality/sky_contact.py [REFERENCE.npz]   # about 3 minutes on 2 cores

REFERENCE.npz, where given, keeps the reference frame between runs (made if missing).

Regions, from the reference's per-pixel records (pixels whose samples see more than one
surface left out); ground points by their distance across the ground from the nearest
box's footprint:
- foot: ground within 0.1 of a box;
- contact: ground within 0.25 of a box;
- near ground: ground 0.25 to 1.0 from a box;
- open ground: ground more than 3.0 from both;
- vertical faces: the boxes' sides;
- face bottoms: the boxes' sides within 0.15 of the ground (where the ground and a side
  meet at one distance from the camera, and a blur that tells them apart by distance alone
  mixes their visibility).
Each region's error is the GPU's mean linear radiance over it against the reference's.
Blotches: over the ground within 1.0 of a box, the RMS of the GPU's radiance over the
reference's less 1, both first averaged over 3 x 3 pixels of the ground (the reference's
own noise there, against one of four times its samples, is about 0.5 %).
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
from environment_contact import camera_rays, frame_times  # noqa: E402  (the same rays and alternation)

SCENE = HERE / "scenes" / "sky_contact.yaml"
# (centre x, z, half sizes x, z, turn about +Y in degrees, height) of each box, as the scene places them
BOXES = ((0.6, 0.4, 0.5, 0.5, 25.0, 1.0), (-1.0, -0.6, 0.3, 0.3, -15.0, 1.6))
SIZE = (256, 192)
OBJECT_GROUND, OBJECT_BOXES = 2, (0, 1)
REGIONS = ("foot", "contact", "near ground", "open ground", "vertical faces", "face bottoms")
FACE_BOTTOM = 0.15  # the boxes' sides this close to the ground are the face bottoms
VARIANTS = {
    "visibility off": ["lights[0].visibility=false"],
    "default": [],  # 32 directions, each region in halves, 2x2 blocks here, half resolution
    "32 directions, exact (every pixel all 32)": ["lights[0].visibility_interleave=1"],
    "64 directions, exact": ["lights[0].visibility_directions=64", "lights[0].visibility_interleave=1"],
    "16 directions (in halves)": ["lights[0].visibility_directions=16"],
    "32 directions (in halves), 3x3 blocks": ["lights[0].visibility_interleave=3"],
    "32 directions (in halves), full resolution": ["lights[0].visibility_half_resolution=false"],
    # 64 directions are 64 maps already: no halves
    "64 directions, auto blocks (2x2 here)": ["lights[0].visibility_directions=64"],
}
TIMED = ("visibility off", "default", "64 directions, auto blocks (2x2 here)")
# what the candidates cost where the default's speed is held: scenes/gltf_pbr.yaml at
# 640x360 (auto: 3x3 blocks), its camera turning, the settings taking turns
GLTF_PBR = HERE.parent.parent / "scenes" / "gltf_pbr.yaml"
GLTF_PBR_MOTION = ["render.size=[640,360]"]
GLTF_PBR_VARIANTS = {"default (32 directions in halves, 3x3 blocks)": [],
                     "64 directions, auto (3x3 blocks)": ["lights[2].visibility_directions=64"]}
DRIFT = ["camera.position={keys: [[0, [1.5, 3.0, 6.0]], [1, [1.9, 3.0, 6.0]]]}", "output={fps: 30, frames: 31}"]


def footprint_distance(points: np.ndarray, boxes=BOXES) -> np.ndarray:
    """(H, W) the distance across the ground from each point (H, W, 3) to the nearest of
    ``boxes``' footprints (0 inside one)."""
    found = np.full(points.shape[:2], np.inf)
    for cx, cz, hx, hz, degrees, _ in boxes:
        turn = np.radians(degrees)
        dx, dz = points[..., 0] - cx, points[..., 2] - cz
        # into the box's frame (the scene turns it by +degrees about +Y)
        local_x = np.cos(turn) * dx - np.sin(turn) * dz
        local_z = np.sin(turn) * dx + np.cos(turn) * dz
        outside = np.hypot(np.maximum(np.abs(local_x) - hx, 0.0), np.maximum(np.abs(local_z) - hz, 0.0))
        found = np.minimum(found, outside)
    return found


def box_tops(origin: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """(H, W) bool: the pixel's centre ray meets a box's top (the plane of its height, over
    its footprint)."""
    found = np.zeros(direction.shape[:2], dtype=bool)
    for box in BOXES:
        t = (box[5] - origin[1]) / np.where(np.abs(direction[..., 1]) > 1e-12, direction[..., 1], 1e-12)
        found |= (t > 0) & (footprint_distance(origin + direction * t[..., None], (box,)) == 0.0)
    return found


def box_hit_heights(origin: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """(H, W) the height of the nearest point where each pixel's centre ray enters a box
    (inf where it meets none): a slab test in each box's own frame."""
    found_t = np.full(direction.shape[:2], np.inf)
    for cx, cz, hx, hz, degrees, height in BOXES:
        turn = np.radians(degrees)
        c, s = np.cos(turn), np.sin(turn)
        o = origin - np.array([cx, height / 2.0, cz])
        local_o = np.stack([c * o[..., 0] - s * o[..., 2], o[..., 1], s * o[..., 0] + c * o[..., 2]], axis=-1)
        local_d = np.stack([c * direction[..., 0] - s * direction[..., 2], direction[..., 1],
                            s * direction[..., 0] + c * direction[..., 2]], axis=-1)
        half = np.array([hx, height / 2.0, hz])
        safe = np.where(np.abs(local_d) > 1e-12, local_d, 1e-12)
        t1, t2 = (-half - local_o) / safe, (half - local_o) / safe
        near, far = np.minimum(t1, t2).max(axis=-1), np.maximum(t1, t2).min(axis=-1)
        found_t = np.where((near <= far) & (near > 0) & (near < found_t), near, found_t)
    return np.where(np.isfinite(found_t), origin[..., 1] + direction[..., 1] * found_t, np.inf)


def region_masks(world, reference, size: tuple = SIZE) -> dict:
    """{region name: (H, W) bool} (see the module's docstring), and "blotch" the ground the
    blotches are measured over, of a frame ``size`` (width, height)."""
    origin, direction = camera_rays(world, size)
    t = -origin[1] / np.minimum(direction[..., 1], -1e-12)
    distance = footprint_distance(origin + direction * t[..., None])
    clean = ~reference.mixed
    ground = clean & (reference.object == OBJECT_GROUND)
    boxes = clean & np.isin(reference.object, OBJECT_BOXES)
    masks = {"foot": ground & (distance < 0.1), "contact": ground & (distance < 0.25), "near ground": ground & (distance >= 0.25) & (distance < 1.0),
             "open ground": ground & (distance > 3.0), "vertical faces": boxes & ~box_tops(origin, direction)}
    masks["face bottoms"] = masks["vertical faces"] & (box_hit_heights(origin, direction) < FACE_BOTTOM)
    masks["blotch"] = ground & (distance < 1.0)
    return masks


def smoothed(values: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """(H, W) values averaged over 3 x 3 pixels of ``mask``."""
    total = ndimage.uniform_filter(np.where(mask, values, 0.0), 3, mode="constant")
    weight = ndimage.uniform_filter(mask.astype(np.float64), 3, mode="constant")
    return np.where(weight > 0, total / np.maximum(weight, 1e-12), 0.0)


def errors(linear: np.ndarray, truth: np.ndarray, masks: dict) -> dict:
    """{region: mean GPU / mean reference - 1, "blotches": the RMS above}; (H, W) float64."""
    found = {name: float(linear[masks[name]].mean() / truth[masks[name]].mean() - 1.0) for name in REGIONS}
    near = masks["blotch"]
    ratio = smoothed(linear, near)[near] / np.maximum(smoothed(truth, near)[near], 1e-9) - 1.0
    found["blotches"] = float(np.sqrt(np.mean(ratio ** 2)))
    return found


def reference(cache: Path | None, overrides=(), spp: int = 8, environment_samples: int = 32):
    """The reference frame (``spp`` x ``spp`` samples a pixel, ``environment_samples``
    directions each), kept in ``cache`` where given."""
    import pickle

    if cache is not None and cache.exists():
        return pickle.loads(cache.read_bytes())
    from scenerender.raytrace.render import render_reference

    found = render_reference(scenerender.load(SCENE, list(overrides)), 0, spp=spp, environment_samples=environment_samples)
    if cache is not None:
        cache.write_bytes(pickle.dumps(found))
    return found


def gpu_linear(overrides: list, gl=None) -> np.ndarray:
    """(H, W) float64: the GPU's linear radiance, mean of the channels."""
    scene = scenerender.load(SCENE, overrides)
    with scenerender.Renderer(scene, gl=gl, want_linear=True) as renderer:
        return renderer.render(0).linear[..., :3].astype(np.float64).mean(axis=2)


def main() -> None:
    found = reference(Path(sys.argv[1]) if len(sys.argv) > 1 else None)
    truth = found.linear.astype(np.float64).mean(axis=2)
    masks = region_masks(scenerender.load(SCENE).world, found)
    results = {}
    for name, overrides in VARIANTS.items():
        results[name] = {"errors": errors(gpu_linear(overrides), truth, masks)}
        print(name, {k: round(v * 100, 1) for k, v in results[name]["errors"].items()}, flush=True)
    if "--untimed" not in sys.argv:
        for name, values in frame_times({k: VARIANTS[k] for k in TIMED}, DRIFT, scene_path=SCENE).items():
            results[name]["ms"] = statistics.median(values)
        gltf = {name: statistics.median(values) for name, values in
                frame_times(GLTF_PBR_VARIANTS, GLTF_PBR_MOTION, frames=40, scene_path=GLTF_PBR).items()}
        results["gltf_pbr 640x360 ms/frame"] = gltf
    pixels = {name: int(masks[name].sum()) for name in (*REGIONS, "blotch")}
    (HERE / "sky_contact.json").write_text(json.dumps({"pixels": pixels, "results": results}, indent=1))
    write_table(results, pixels)


def write_table(results: dict, pixels: dict) -> None:
    """sky_contact.md: each setting's error per region, its blotches and its cost."""
    base = results["visibility off"].get("ms")
    lines = ["# The sky's contact shadows: two boxes on a ground under a sky with no sun", "",
             "Made by `python benchmarks/quality/sky_contact.py` (see its docstring) on Mesa llvmpipe, 2 cores,",
             "256x192, the default MSAA: each region's error is the GPU's mean linear radiance over it",
             "against the reference's (8x8 samples a pixel, 32 environment directions each); blotches:",
             "the RMS of the GPU over the reference less 1 on the ground within 1 m of a box, 3x3 averaged.",
             "ms/frame: the median frame after the first as the camera drifts, settings taking turns.", "",
             "| setting | " + " | ".join(f"{name} % ({pixels[name]} px)" for name in REGIONS)
             + f" | blotches % ({pixels['blotch']} px) | ms/frame | vs off |",
             "|---|" + "---|" * (len(REGIONS) + 3)]
    gltf = results.pop("gltf_pbr 640x360 ms/frame", None)
    for name, row in results.items():
        cells = [f"{row['errors'][region] * 100:+.1f}" for region in REGIONS] + [f"{row['errors']['blotches'] * 100:.1f}"]
        ms = row.get("ms")
        cells += [f"{ms:.1f}", f"{ms / base:.2f}"] if ms is not None and base else ["-", "-"]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    if gltf:
        first = next(iter(gltf.values()))
        lines += ["", "What the candidates cost where the defaults' speed is held: `scenes/gltf_pbr.yaml` at 640x360,",
                  "its camera turning, median ms a frame after the first, the settings taking turns (40 frames each):", "",
                  "| setting | ms/frame | vs default |", "|---|---|---|"]
        lines += [f"| {name} | {ms:.1f} | {ms / first:.2f} |" for name, ms in gltf.items()]
    lines += ["", *BEFORE_HALVES]
    (HERE / "sky_contact.md").write_text("\n".join(lines) + "\n")


# The default before each direction's region was cut in two halves (commit b17b6a6, its
# tree rendered, this script's regions and reference): kept as words, since this tree
# cannot draw it.
BEFORE_HALVES = [
    "Before each direction's region was cut in two halves that take turns from block to block, and",
    "before the blur and the read-back told surfaces apart by their normals (commit b17b6a6, its tree",
    "rendering, this reference and these regions): the default +3.2, +0.3, +0.5, -0.7, +1.6, -7.4 %",
    "(foot, contact, near ground, open ground, vertical faces, face bottoms), blotches 4.5 %; 16",
    "directions blotches 9.4 %. What the change costs: docs/performance.md, \"The sky's visibility",
    "in halves\".",
]


if __name__ == "__main__":
    main()
