"""A small CPU reference renderer: the truth that GPU error is measured against.

    import scenerender
    from scenerender.raytrace import render_reference, write_reference

    scene = scenerender.load("benchmarks/quality/scenes/point.yaml")
    ref = render_reference(scene, 0, spp=4)   # ref.linear (H, W, 3) float32, ref.pixels uint8
    write_reference(ref, "ref/")              # ref/frame_0000.exr (linear) and .png (display)

It shares the shading equations with the GPU (scenerender.raytrace.shading) and sees the
same World and per-frame camera and lights (scenerender.world.frame); visibility, hard
shadows and pixel coverage are exact up to the stratified supersampling.
"""
from __future__ import annotations

from pathlib import Path

from scenerender.raytrace.rays import embree_available
from scenerender.raytrace.render import (
    ReferenceFrame,
    render_reference,
    unsupported_features,
)
from scenerender.sinks.base import atomic_path
from scenerender.sinks.images import write_exr, write_image

__all__ = ["ReferenceFrame", "render_reference", "write_reference", "unsupported_features", "embree_available"]


def write_reference(frame: ReferenceFrame, folder, formats=("exr", "png")) -> list[Path]:
    """Write ``frame`` as ``folder/frame_NNNN.exr`` (linear float) and ``.png`` (display
    values), each to a temporary name renamed when whole. Returns the paths written."""
    folder = Path(folder)
    written = []
    for fmt in formats:
        final = folder / f"frame_{frame.index:04d}.{fmt}"
        with atomic_path(final) as temp:
            if fmt == "exr":
                write_exr(temp, frame.linear)
            else:
                write_image(temp, frame.pixels, fmt)
        written.append(final)
    return written
