"""The golden-image cases: which scene, frame and settings each reference image shows.

References live in tests/golden/ and are made by `make goldens` (tests/golden_update.py)
on Mesa llvmpipe; look at every image you commit. Each keeps its object ids beside it, as
`render --check` does (tests/golden/.object_ids/: NAME.png, behind/NAME.png, NAME.json),
so the goldens are judged by object too.

Tolerance: the default rule of `scenerender diff` (scenerender.compare.DEFAULT_RULE): no
8x8 block averaging more than 1 level of difference outside the other image's 3x3 colour
ranges, at most 0.0007 levels of it over the frame, and no 12x12 window averaging more than
0.7 levels in one direction of what the best quarter-pixel shift per 8x8 tile leaves. Measured
margins between driver-like noise and real changes are in docs/diff-margins.md;
tests/test_golden.py shows each plausible regression failing.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

GOLDEN_DIR = Path(__file__).resolve().parent / "golden"
SCENES = Path(__file__).resolve().parent.parent / "scenes"

SIZE = "render.size=[160, 120]"
# The views these goldens were made from, before the scenes' cameras were placed anew with
# `scenerender preview`: the references stay comparable (and their error against the CPU
# reference as measured), whatever view the example scene itself shows.
GARDEN_VIEW = ["camera.position=[0, 2.2, 7.5]", "camera.target=[0, 0.2, 0]"]
SOFT_LIGHT_VIEW = ["camera.position=[0.4, 3.6, 5.6]", "camera.target=[0, 0.5, 0]"]

# name -> (scene file, frame, extra overrides)
CASES = {
    "showcase": ("showcase.yaml", 45, []),
    "garden": ("garden.yaml", 30, GARDEN_VIEW),
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
    "soft_light": ("soft_light.yaml", 0, SOFT_LIGHT_VIEW),
    # the sun through a window and the light that bounces (render.indirect's probe grid)
    "interior": ("interior.yaml", 0, []),
    # every pixel looking up every direction: the exact sum the default's blocks approximate
    "gltf_pbr@visibility_exact": ("gltf_pbr.yaml", 36, ["lights[2].visibility_interleave=1"]),
    # 3x3 blocks, what 'auto' takes from 240 pixels up (the golden size takes 2x2): five
    # places look up 4 directions, four look up 3
    "gltf_pbr@visibility_3x3": ("gltf_pbr.yaml", 36, ["lights[2].visibility_interleave=3"]),
}


# -- "renders the bytes it drew before": within the CPU's rounding -------------------------
# A golden is drawn once, on one CPU, and llvmpipe compiles every shader for the CPU it runs
# on: vendors' approximate reciprocal and square-root instructions round a few values
# differently (the goldens were drawn on an Intel Xeon; on an AMD EPYC, also AVX-512,
# gltf_pbr@visibility_off comes out one level off in 60 of its 19,200 pixels and
# gltf_pbr@visibility_exact in 43). So a claim that a setting renders what an older version
# drew is checked against that version's golden within this bound; where the path it
# replaces still exists, the two are compared byte for byte in the same run instead.
CPU_ROUNDING_LEVELS = 1      # no channel of any pixel further apart than this
CPU_ROUNDING_SHARE = 0.02    # nor more than this share of pixels apart at all (EPYC: 0.3 %)


def beyond_cpu_rounding(rendered, golden) -> str | None:
    """What puts ``rendered`` further from ``golden`` (both (H, W, 3) uint8) than two CPUs'
    rounding can, in words; None where it is within the bound."""
    apart = np.abs(rendered.astype(np.int16) - golden.astype(np.int16)).max(axis=2)
    share = float(np.count_nonzero(apart)) / apart.size
    if apart.max() > CPU_ROUNDING_LEVELS:
        over = np.count_nonzero(apart > CPU_ROUNDING_LEVELS)
        return f"{over} pixels more than {CPU_ROUNDING_LEVELS} level apart (up to {apart.max()})"
    if share > CPU_ROUNDING_SHARE:
        return f"{share:.1%} of the pixels a level apart, more than {CPU_ROUNDING_SHARE:.0%}"
    return None


IDS_DIR = GOLDEN_DIR / ".object_ids"


def reference_path(name: str) -> Path:
    return GOLDEN_DIR / f"{name}.png"


def render_case(gl, name: str, extra=()):
    """Render golden case ``name`` (plus ``extra`` overrides) -> (H, W, 3) uint8."""
    return render_case_with_ids(gl, name, extra)[0]


def render_case_with_ids(gl, name: str, extra=()):
    """Render golden case ``name`` (plus ``extra`` overrides) with its object ids ->
    ((H, W, 3) uint8, compare.objects.IdMap), as `render --check` keeps them."""
    import scenerender
    from conftest import scene
    from scenerender.compare.objects import IdMap
    from scenerender.world.id_names import id_names

    scene_file, frame, overrides = CASES[name]
    with scenerender.Renderer(scene(SCENES / scene_file, [SIZE, *overrides, *extra]), gl=gl,
                              object_ids=True) as renderer:
        result = renderer.render(frame)
        return result.pixels, IdMap(result.object_ids, id_names(renderer.scene.world), result.object_ids_behind)


def reference_ids(name: str):
    """The object ids kept with golden case ``name`` (compare.objects.IdMap), or None."""
    from scenerender.compare.objects import IdMap
    from scenerender.sinks.object_ids import read_ids

    ids, behind = read_ids(IDS_DIR / f"{name}.png"), read_ids(IDS_DIR / "behind" / f"{name}.png")
    if ids is None:
        return None
    names = json.loads((IDS_DIR / f"{name}.json").read_text(encoding="utf-8"))
    return IdMap(ids, {int(k): v for k, v in names.items()}, behind)


def write_reference_ids(name: str, ids) -> None:
    """Keep ``ids`` (an IdMap) with golden case ``name``: 16-bit PNGs and the names."""
    from scenerender.sinks.images import encode_grey16_png

    (IDS_DIR / "behind").mkdir(parents=True, exist_ok=True)
    (IDS_DIR / f"{name}.png").write_bytes(encode_grey16_png(ids.ids))
    (IDS_DIR / "behind" / f"{name}.png").write_bytes(encode_grey16_png(ids.behind))
    (IDS_DIR / f"{name}.json").write_text(json.dumps({str(k): v for k, v in sorted(ids.names.items())}, indent=1)
                                          + "\n", encoding="utf-8")
