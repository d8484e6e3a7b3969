"""The golden-image cases: which scene, frame and settings each reference image shows.

References live in tests/golden/ and are made by `make goldens` (tests/golden_update.py)
on Mesa llvmpipe; look at every image you commit.

Tolerance: the default rule of `scenerender diff` (scenerender.compare.DEFAULT_RULE): no
8x8 block averaging more than 1 level of difference outside the other image's 3x3 colour
ranges, at most 0.0007 levels of it over the frame, and no 12x12 window averaging more than
0.7 levels in one direction of what the best quarter-pixel shift per 8x8 tile leaves. Measured
margins between driver-like noise and real changes are in docs/diff-margins.md;
tests/test_golden.py shows each plausible regression failing.
"""
from __future__ import annotations

from pathlib import Path

GOLDEN_DIR = Path(__file__).resolve().parent / "golden"
SCENES = Path(__file__).resolve().parent.parent / "scenes"

SIZE = "render.size=[160, 120]"

# name -> (scene file, frame, extra overrides)
CASES = {
    "showcase": ("showcase.yaml", 45, []),
    "garden": ("garden.yaml", 30, []),
    "island": ("island.yaml", 130, []),
    "foggy_road": ("foggy_road.yaml", 72, []),
    "foggy_road@wireframe": ("foggy_road.yaml", 0, ["render.mode=wireframe"]),
    "foggy_road@points": ("foggy_road.yaml", 0, ["render.mode=points"]),
    "foggy_road@light_depth": ("foggy_road.yaml", 0, ["render.mode=light_depth"]),
    "viewer_modes": ("viewer_modes.yaml", 0, []),
    "viewer_modes@depth": ("viewer_modes.yaml", 0, ["render.mode=depth"]),
    "viewer_modes@normals": ("viewer_modes.yaml", 0, ["render.mode=normals"]),
    "viewer_modes@shadow": ("viewer_modes.yaml", 0, ["render.mode=shadow"]),
    "viewer_modes@ambient_occlusion": ("viewer_modes.yaml", 0, ["render.mode=ambient_occlusion"]),
    "viewer_modes@wireframe": ("viewer_modes.yaml", 0, ["render.mode=wireframe"]),
    "primitives": ("primitives.yaml", 30, []),
    "primitives@phong": ("primitives.yaml", 30, ["render.shading=phong"]),
    # a transparent prism and an outlined cylinder: as edges and points like every other surface
    "primitives@wireframe": ("primitives.yaml", 30, ["render.mode=wireframe"]),
    "primitives@points": ("primitives.yaml", 30, ["render.mode=points"]),
    "gltf_pbr": ("gltf_pbr.yaml", 36, []),
    "film": ("film.yaml", 32, []),
    # the studio environment not blocked by the scene: what gltf_pbr drew before visibility
    "gltf_pbr@visibility_off": ("gltf_pbr.yaml", 36, ["lights[2].visibility=false"]),
    # every pixel looking up every direction: what gltf_pbr drew before the directions were
    # shared out over pixel blocks
    "gltf_pbr@visibility_exact": ("gltf_pbr.yaml", 36, ["lights[2].visibility_interleave=1"]),
}


def reference_path(name: str) -> Path:
    return GOLDEN_DIR / f"{name}.png"


def render_case(gl, name: str, extra=()):
    """Render golden case ``name`` (plus ``extra`` overrides) -> (H, W, 3) uint8."""
    from conftest import render_one

    scene, frame, overrides = CASES[name]
    return render_one(gl, SCENES / scene, [SIZE, *overrides, *extra], frame)
