"""The environment's specular term against the reference: three spheres resting on a
ground under a sky with a bright patch (scenes/three_spheres.yaml: a grey and a white
dielectric, a copper-like metal of roughness 0.5), each sphere's error and each
setting's cost; and the copper sphere alone (the others and the ground hidden, visibility
off: nothing blocks its sky, so the specular term is all that is measured). Writes
three_spheres.md and .json.

    python benchmarks/quality/three_spheres.py [REFERENCE.npz]   # about 8 minutes on 2 cores

REFERENCE.npz, where given, keeps the reference frames between runs (made if missing).

Each sphere's error is the GPU's mean linear radiance over the pixels whose centre sees it
(analytic intersection; pixels whose samples see more than one surface left out) against
the reference's. The reference shades with the same BRDF, every direction of the
environment blocked by the surfaces in its way; the GPU's visibility is the light's
default (32 directions; three rows show 16 and 64).

Cost: the camera drifts (every frame drawn; the prefiltered image and the visibility maps
on the first frame only): the median ms per frame after the first, the settings taking
turns frame by frame in one process (A B A B ...).
"""
from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))
sys.path.insert(0, str(HERE))

import scenerender  # noqa: E402
from environment_contact import camera_rays, frame_times  # noqa: E402  (the same rays and alternation)

SCENE = HERE / "scenes" / "three_spheres.yaml"
# (name, centre) of each sphere, radius 1, as scenes/three_spheres.yaml places them
SPHERES = (("grey", np.array([-2.4, 1.0, 0.0])), ("copper", np.array([0.0, 1.0, 0.0])),
           ("white", np.array([2.4, 1.0, 0.0])))
SIZE = (256, 192)
SAMPLED = "lights[0].specular=sampled"
VARIANTS = {
    "split_sum (default)": [],
    "sampled, 4 samples": [SAMPLED, "lights[0].specular_samples=4"],
    "sampled, 8 samples": [SAMPLED, "lights[0].specular_samples=8"],
    "sampled, 16 samples": [SAMPLED, "lights[0].specular_samples=16"],
    "sampled, 32 samples (the count's default)": [SAMPLED, "lights[0].specular_samples=32"],
    "sampled, 64 samples": [SAMPLED, "lights[0].specular_samples=64"],
    "split_sum, visibility at 16 directions (the default before 0.7.0)": ["lights[0].visibility_directions=16"],
    "split_sum, visibility at 64 directions": ["lights[0].visibility_directions=64"],
    "sampled, 32 samples, visibility at 64 directions": [SAMPLED, "lights[0].visibility_directions=64"],
    "split_sum, visibility in 3x3 blocks (auto from 240 pixels high)": ["lights[0].visibility_interleave=3"],
}
UNTIMED = tuple(list(VARIANTS)[6:])
# the copper sphere by itself: its neighbours and the ground hidden, nothing to block its sky
ALONE = ["objects[0].visible=false", "objects[2].visible=false", "objects[3].visible=false",
         "lights[0].visibility=false"]
DRIFT = ["camera.position={keys: [[0, [0.0, 2.1, 7.2]], [1, [0.4, 2.1, 7.2]]]}", "output={fps: 30, frames: 31}"]


def surface_points(world, size: tuple) -> np.ndarray:
    """(H, W) int: the surface each pixel's centre sees, 0.. the SPHERES in order, len(SPHERES)
    the ground, -1 nothing (the scene's surfaces intersected analytically)."""
    origin, direction = camera_rays(world, size)
    hits = []
    for _, centre in SPHERES:  # |o + t d - c|^2 = 1
        oc = origin - centre
        b = direction @ oc
        disc = b * b - (oc @ oc - 1.0)
        hits.append(np.where(disc > 0, -b - np.sqrt(np.maximum(disc, 0.0)), np.inf))
    hits.append(np.where(direction[..., 1] < 0, -origin[1] / np.minimum(direction[..., 1], -1e-12), np.inf))
    t = np.stack(hits)
    return np.where(np.isinf(t.min(axis=0)), -1, t.argmin(axis=0))


def sphere_masks(which: np.ndarray, mixed: np.ndarray) -> dict:
    """{sphere name: (H, W) bool, the pixels that see only it}."""
    return {name: (which == index) & ~mixed for index, (name, _) in enumerate(SPHERES)}


def sphere_errors(linear: np.ndarray, truth: np.ndarray, masks: dict) -> dict:
    """{sphere: the GPU's mean linear radiance over it / the reference's - 1}; linear and
    truth (H, W) float64, the mean of the three channels."""
    return {name: float(linear[mask].mean() / truth[mask].mean() - 1.0) for name, mask in masks.items()}


def reference(scene, spp: int, environment_samples: int) -> tuple[np.ndarray, np.ndarray]:
    """((H, W) float64 the reference's linear radiance, mean of the channels; (H, W) bool
    the pixels whose samples see more than one surface): seeded, so the same each run."""
    from scenerender.raytrace.render import render_reference

    found = render_reference(scene, 0, spp=spp, environment_samples=environment_samples)
    return found.linear.astype(np.float64).mean(axis=2), found.mixed


def gpu_linear(overrides: list, size: tuple, gl=None) -> np.ndarray:
    """(H, W) float64: the GPU's linear radiance, mean of the channels."""
    scene = scenerender.load(SCENE, [f"render.size=[{size[0]},{size[1]}]", *overrides])
    with scenerender.Renderer(scene, gl=gl, want_linear=True) as renderer:
        return renderer.render(0).linear[..., :3].astype(np.float64).mean(axis=2)


def references(cache: Path | None) -> dict:
    """{"scene" | "alone": ((H, W) truth, (H, W) mixed)} at SIZE, 8x8 samples a pixel, 32
    directions each; kept in ``cache`` (an .npz) where given."""
    if cache is not None and cache.exists():
        kept = np.load(cache)
        return {name: (kept[f"{name}_truth"], kept[f"{name}_mixed"]) for name in ("scene", "alone")}
    found = {"scene": reference(scenerender.load(SCENE), spp=8, environment_samples=32),
             "alone": reference(scenerender.load(SCENE, ALONE), spp=8, environment_samples=32)}
    if cache is not None:
        np.savez(cache, **{f"{name}_{what}": value for name, pair in found.items()
                           for what, value in zip(("truth", "mixed"), pair)})
    return found


def main() -> None:
    scene = scenerender.load(SCENE)
    found = references(Path(sys.argv[1]) if len(sys.argv) > 1 else None)
    truth, mixed = found["scene"]
    masks = sphere_masks(surface_points(scene.world, SIZE), mixed)
    alone_truth, alone_mixed = found["alone"]
    alone = {"copper alone": (alone_truth > 0.0) & ~alone_mixed}
    results = {}
    for name, overrides in VARIANTS.items():
        errors = sphere_errors(gpu_linear(overrides, SIZE), truth, masks)
        if name not in UNTIMED:
            errors.update(sphere_errors(gpu_linear([*ALONE, *overrides], SIZE), alone_truth, alone))
        results[name] = {"errors": errors}
        print(name, {k: round(v * 100, 1) for k, v in errors.items()}, flush=True)
    for name, values in frame_times({k: v for k, v in VARIANTS.items() if k not in UNTIMED}, DRIFT, scene_path=SCENE).items():
        results[name]["ms"] = statistics.median(values)
        print(name, round(statistics.median(values), 1), flush=True)
    pixels = {name: int(mask.sum()) for name, mask in {**masks, **alone}.items()}
    (HERE / "three_spheres.json").write_text(json.dumps({"pixels": pixels, "results": results}, indent=1))
    write_table(results, pixels)


def write_table(results: dict, pixels: dict) -> None:
    """three_spheres.md: each setting's error per sphere and its cost, one row a setting."""
    base = results["split_sum (default)"]["ms"]
    names = [name for name, _ in SPHERES] + ["copper alone"]
    lines = ["# The environment's specular term: three spheres under a sky with a bright patch", "",
             "Made by `python benchmarks/quality/three_spheres.py` (see its docstring) on Mesa llvmpipe,",
             "2 cores, 256x192, the default MSAA, visibility at its default 32 directions: each sphere's error is the GPU's mean",
             "linear radiance over it against the reference's (8x8 samples a pixel, 32 environment",
             "directions each, every direction blocked by the surfaces in its way). ms/frame: the",
             "median frame after the first as the camera drifts, the settings taking turns frame by",
             "frame in one process. The scene: benchmarks/quality/scenes/three_spheres.yaml; copper",
             "alone: the same with the other spheres and the ground hidden and visibility off (the",
             "specular term by itself).", "",
             "| setting | " + " | ".join(f"{name} % ({pixels[name]} px)" for name in names)
             + " | ms/frame | vs split_sum |",
             "|---|" + "---|" * (len(names) + 2)]
    for name, result in results.items():
        cells = [f"{100.0 * result['errors'][sphere]:+.1f}" if sphere in result["errors"] else "-" for sphere in names]
        cells += [f"{result['ms']:.1f}", f"{result['ms'] / base:.2f}"] if "ms" in result else ["-", "-"]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    (HERE / "three_spheres.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
