"""Where each Cornell-box region's error against the path tracer comes from: the direct
light (the GPU without render.indirect against the direct-only truth) or the bounced
light (the GPU's default render.indirect less its direct light, against the 16-bounce
truth less the direct-only truth). A region's error is the sum of the two shares.

    python benchmarks/quality/cornell_split.py     # writes cornell_split.md

The truths, the regions and the renders are cornell_indirect.py's.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from cornell_indirect import normals_view, render, truth  # also puts the repository on sys.path
from scenerender.gpu.gl_context import create_context
from scenerender.tools.bounce_regions import bounce_regions

HERE = Path(__file__).resolve().parent


def region_shares(direct_gpu: np.ndarray, full_gpu: np.ndarray, direct_truth: np.ndarray,
                  full_truth: np.ndarray, mask: np.ndarray) -> dict:
    """One region's error split, each as a fraction of the region's full truth mean.
    Images: (H, W, 3) float64 linear; mask: (H, W) bool."""
    truth_mean = full_truth[mask].mean()
    bounce_truth = full_truth[mask].mean() - direct_truth[mask].mean()
    bounce_gpu = full_gpu[mask].mean() - direct_gpu[mask].mean()
    return {"total": full_gpu[mask].mean() / truth_mean - 1.0,
            "direct": (direct_gpu[mask].mean() - direct_truth[mask].mean()) / truth_mean,
            "bounce": (bounce_gpu - bounce_truth) / truth_mean,
            # the ceiling has no direct light to compare with
            "direct_alone": (direct_gpu[mask].mean() / direct_truth[mask].mean() - 1.0
                             if direct_truth[mask].mean() > 0 else None),
            "bounce_alone": bounce_gpu / bounce_truth - 1.0}


def table(shares: dict, renderer: str) -> str:
    lines = [f"Cornell box, 128x128, default render.indirect; GPU: {renderer}. Each region's error "
             "against the path tracer (%, of the region's truth) split into the direct light's share "
             "and the bounced light's; then each part against its own truth. The scene's light has "
             "`casters: solid` (render.shadows); with the nearest surface alone the floor in shadow read "
             "+11.2 % (its direct light +124.9 % of the direct truth: the soft shadow let light into the "
             "umbra beside the tall box's foot).", "",
             "| region | total | direct share | bounce share | direct vs direct truth | bounce vs bounce truth |",
             "|---|---|---|---|---|---|"]
    for name, row in shares.items():
        direct_alone = "-" if row["direct_alone"] is None else f"{100 * row['direct_alone']:+.1f}"
        lines.append(f"| {name} | {100 * row['total']:+.1f} | {100 * row['direct']:+.1f} | "
                     f"{100 * row['bounce']:+.1f} | {direct_alone} | {100 * row['bounce_alone']:+.1f} |")
    return "\n".join(lines)


def main() -> None:
    full_truth, direct_truth, objects = truth()
    gl = create_context()
    regions = bounce_regions(objects, normals_view(gl), direct_truth)
    direct_gpu, _ = render(gl, [])
    full_gpu, _ = render(gl, ["render.indirect={}"])
    shares = {name: region_shares(direct_gpu, full_gpu, direct_truth, full_truth, mask)
              for name, mask in regions.items()}
    (HERE / "cornell_split.md").write_text(table(shares, gl.info["GL_RENDERER"]) + "\n")
    print(table(shares, gl.info["GL_RENDERER"]))


if __name__ == "__main__":
    main()
