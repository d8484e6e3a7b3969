"""The 8-bit sRGB output that PNG frames carry, of one or more source trees, against the CPU
reference. `scenerender bench` measures the float target (it asks for the linear image);
this measures the default path: the 8-bit sRGB target, its MSAA resolve and encoding.

For each scene (frame 0, its own settings) it prints, per tree, the sRGB RMSE of the whole
image and the linear RMSE of the decoded pixels over the whole image and over the
shadow-edge and geometry-edge regions of `scenerender/tools/quality.py` (in % of full
scale), and how many output values differ from the first tree's.

    git worktree add /tmp/base main
    python benchmarks/quality/eight_bit_output.py point directional spot_hard contact --tree /tmp/base --tree .
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from scenerender.run.session import load  # noqa: E402
from scenerender.raytrace.render import render_reference  # noqa: E402
from scenerender.tools.quality import region_masks, rmse_percent  # noqa: E402

SCENES = ROOT / "benchmarks" / "quality" / "scenes"
# runs in the tree's own process, so that tree's scenerender renders
RENDER = r"""
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
from scenerender.run.session import Renderer, load
with Renderer(load(sys.argv[2])) as renderer:
    np.save(sys.argv[3], renderer.render(0).pixels)
"""


def srgb_decode(pixels: np.ndarray) -> np.ndarray:
    """(H, W, 3) uint8 sRGB -> float64 linear, the exact curve."""
    c = pixels.astype(np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def tree_pixels(tree: Path, scene: Path, folder: Path) -> np.ndarray:
    out = folder / f"{abs(hash(str(tree)))}.npy"
    subprocess.run([sys.executable, "-c", RENDER, str(tree), str(scene), str(out)], check=True, cwd=folder)
    return np.load(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenes", nargs="+", help="names in benchmarks/quality/scenes/")
    parser.add_argument("--tree", type=Path, action="append", default=None, help="a source tree (default: this one)")
    parser.add_argument("--spp", type=int, default=16, help="reference samples a pixel along each axis (default 16)")
    args = parser.parse_args()
    trees = [tree.resolve() for tree in (args.tree or [ROOT])]
    print("| scene | tree | whole image, sRGB | whole image, linear | shadow edges, linear | "
          "geometry edges, linear | values differing from the first tree's |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for name in args.scenes:
            scene = SCENES / f"{name}.yaml"
            reference = render_reference(load(scene), 0, spp=args.spp)
            masks = region_masks(reference)
            truth = np.clip(reference.linear, 0.0, 1.0)
            first = None
            for tree in trees:
                pixels = tree_pixels(tree, scene, Path(folder))
                first = pixels if first is None else first
                linear = srgb_decode(pixels)
                changed = (pixels != first).mean()
                print(f"| {name} | {tree} | {rmse_percent(reference.pixels, pixels, scale=255.0):.4f} | "
                      f"{rmse_percent(truth, linear):.4f} | {rmse_percent(truth, linear, masks['shadow_edge']):.4f} | "
                      f"{rmse_percent(truth, linear, masks['geometry_edge']):.4f} | {changed:.2%} |", flush=True)


if __name__ == "__main__":
    main()
