"""Does the reference render what another checkout's reference renders, to the byte?

    git archive COMMIT | tar -x -C /tmp/base
    python benchmarks/quality/reference_bytes.py --tree /tmp/base   # about 2 minutes on 2 cores

renders every scene of scenes/ and benchmarks/quality/scenes/ (48x36, 2x2 samples a pixel,
and benchmarks/quality/scenes/point.yaml again with --ambient-samples 4) with this
checkout's reference and with the other tree's, each in its own process, and compares every
array of the frames (linear, pixels, shadow, cone, object, mixed, blocked) byte for byte.
Prints the arrays that differ; exits 1 when any does. Scenes that a tree cannot render are
named and left out on both sides. What a new setting left at its default must keep.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
KEYS = ("linear", "pixels", "shadow", "cone", "object", "mixed", "blocked")


def cases() -> list[tuple[str, dict]]:
    """(scene path relative to the tree's root, render_reference keywords)."""
    scenes = sorted(str(p.relative_to(ROOT)) for p in [*(ROOT / "scenes").glob("*.yaml"),
                                                       *(HERE / "scenes").glob("*.yaml")])
    return [(scene, {}) for scene in scenes] + [("benchmarks/quality/scenes/point.yaml", {"ambient_samples": 4})]


def render_all(out: str) -> None:
    """In the tree this process imports scenerender from: every case's arrays into ``out``."""
    import scenerender
    from scenerender.raytrace import render_reference

    arrays = {}
    for index, (scene, keywords) in enumerate(cases()):
        try:
            frame = render_reference(scenerender.load(scene), 0, spp=2, size=(48, 36), **keywords)
        except Exception as error:  # a scene this tree cannot render: named, left out
            print(f"{scene}: not rendered ({type(error).__name__}: {error})", file=sys.stderr)
            continue
        for key in KEYS:
            arrays[f"{index}:{scene}:{key}"] = getattr(frame, key)
    np.savez(out, **arrays)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", type=Path, required=True, help="the other checkout's root")
    parser.add_argument("--render-into", help=argparse.SUPPRESS)  # the child processes' side
    args = parser.parse_args()
    if args.render_into:
        render_all(args.render_into)
        return 0
    found = {}
    with tempfile.TemporaryDirectory() as folder:
        for name, tree in (("this", ROOT), ("other", args.tree.resolve())):
            out = str(Path(folder) / f"{name}.npz")
            # each side imports its own tree's package, from its own root (the scenes' paths)
            environment = dict(os.environ, PYTHONPATH=str(tree))
            subprocess.run([sys.executable, str(Path(__file__).resolve()), "--tree", str(tree), "--render-into", out],
                           cwd=tree, env=environment, check=True)
            with np.load(out) as kept:
                found[name] = {key: kept[key] for key in kept.files}
    this, other = found["this"], found["other"]
    both = sorted(set(this) & set(other))
    for scene in sorted({key.rsplit(":", 1)[0] for key in set(this) ^ set(other)}):
        print(f"rendered by one tree only: {scene.split(':', 1)[1]}")
    differing = [key for key in both if this[key].dtype != other[key].dtype or this[key].shape != other[key].shape
                 or this[key].tobytes() != other[key].tobytes()]
    for key in differing:
        print(f"differs: {key}")
    print(f"{len(both)} arrays compared, {len(differing)} differ")
    return 1 if differing else 0


if __name__ == "__main__":
    sys.exit(main())
