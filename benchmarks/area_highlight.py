"""An area light's highlight against the reference: benchmarks/quality/scenes/area_highlight.yaml
(a 1.5 x 0.4 m rectangle light low over a glossy floor) rendered on the GPU and by
``scenerender reference``, and the GPU's mean linear radiance over the reference's by region:
the floor where the reference is above a quarter of its brightest (the light's reflection),
the rest of the floor, the box, and the whole image. Both images are averaged over 3 x 3
pixels first; the reference draws one point of the light a sample, so a pixel of its
reflection is noisy on its own and only the regions' means are worth reading.

    python benchmarks/area_highlight.py [--spp 8] [--set KEY=VALUE ...]
    python benchmarks/area_highlight.py --set objects[0].material.metallic=1 \\
        --set "objects[0].material.base_color=[0.9, 0.9, 0.9]"       # the specular alone
    python benchmarks/area_highlight.py --set objects[0].material.roughness=1   # diffuse
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy import ndimage

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import scenerender  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.raytrace import render_reference  # noqa: E402

SCENE = ROOT / "benchmarks" / "quality" / "scenes" / "area_highlight.yaml"
FLOOR, BOX = 0, 1


def regions(reference) -> dict:
    """Region name -> (H, W) mask of pixels that see one surface."""
    clean = ~reference.mixed
    level = ndimage.uniform_filter(reference.linear.astype(np.float64).mean(axis=2), 3)
    floor = clean & (reference.object == FLOOR)
    reflection = floor & (level > level[floor].max() / 4.0)
    return {"reflection": reflection, "rest of the floor": floor & ~reflection,
            "box": clean & (reference.object == BOX), "whole image": np.ones_like(clean)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, default=8, help="reference samples a pixel along each axis")
    parser.add_argument("--set", action="append", default=[], dest="overrides", metavar="KEY=VALUE")
    args = parser.parse_args()
    scene = scenerender.Scene.from_yaml(SCENE.read_text(), str(SCENE.parent), args.overrides)
    reference = render_reference(scene, 0, spp=args.spp)
    with scenerender.Renderer(scene, gl=create_context(), want_linear=True) as renderer:
        gpu = renderer.render(0).linear[:, :, :3].astype(np.float64).mean(axis=2)
    ref = reference.linear.astype(np.float64).mean(axis=2)
    gpu, ref = ndimage.uniform_filter(gpu, 3), ndimage.uniform_filter(ref, 3)
    print(f"{'region':20s} {'pixels':>7s} {'GPU / reference':>16s}")
    for name, mask in regions(reference).items():
        print(f"{name:20s} {int(mask.sum()):7d} {gpu[mask].mean() / ref[mask].mean():16.3f}")


if __name__ == "__main__":
    main()
