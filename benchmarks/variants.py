"""Where a scene's frame time goes under variants of its settings, measured in one process.

Each variant is a renderer of its own on one GL context; frames are rendered by the
variants in turn (A B C A B C ...), so a busy machine slows them alike, and each pass is
timed GPU-synchronised (the --profile timings). Prints one Markdown row per variant: the
median ms per pass, and of the whole frame (``frame``: the render call, readback included),
and the median ratio of a variant's frame to the default's frame of the same round.

    python benchmarks/variants.py scenes/foggy_road.yaml --set "render.size=[640,360]" \\
        --variant no-msaa=render.samples=1 --variant unlit=render.shading=unlit --variant no-footprint
    python benchmarks/variants.py benchmarks/scenes/bench/bench.yaml --variant no-msaa=render.samples=1

A variant is NAME=KEY=VALUE[;KEY=VALUE...] (scene overrides, as --set), NAME@FOLDER
(the GLSL files from another folder, such as a copy of shaders/ taken before an edit), or
one of:
  no-footprint     shadow visibility taken once per pixel, not averaged over its MSAA samples
  no-face-culling  every face of closed surfaces drawn, also those the camera cannot see
  no-visible-samples  shadows over all of a pixel's MSAA samples, with no depth prepass to
                   tell which ones the surface shows in (pipeline.visible_samples_pay)
  full-prepass     visible samples with every opaque object through the depth prepass, as
                   before rendering/visible_samples.py left out what cannot hide anything
  empty-prepass    visible samples with no object through the depth prepass: the prepass's
                   cost alone, against the default (the shadows are wrong where a surface
                   is drawn before what hides it)
  device-srgb      the multisampled 8-bit target encoded by the device, sample by sample,
                   not by the opaque pass's shaders (pipeline.shader_encoding_pays)

    cp -r shaders /tmp/shaders-before   # then edit shaders/
    python benchmarks/variants.py scenes/showcase.yaml --variant before@/tmp/shaders-before
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from contextlib import contextmanager
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import scenerender  # noqa: E402
from scenerender.gpu import shaders  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.rendering import features  # noqa: E402
from scenerender.rendering.passes import forward  # noqa: E402
from scenerender.rendering.renderer import GraphRenderer  # noqa: E402
from scenerender.rendering.visible_samples import VisibleSamplesPlan  # noqa: E402
from scenerender.world import frame  # noqa: E402


class NoFaceCulling(GraphRenderer):
    """Draws the faces the camera cannot see too."""

    def render(self, index: int):
        original = frame.hidden_faces
        frame.hidden_faces = lambda winding, bounds, camera: None
        try:
            return super().render(index)
        finally:
            frame.hidden_faces = original


class ReplannedPrepass(GraphRenderer):
    """Visible samples with the depth prepass that ``replan(plan, items)`` makes of the
    usual plan (rendering/visible_samples.py) and the frame's opaque items."""

    def __init__(self, world, gl, replan, **kwargs):
        super().__init__(world, gl, **kwargs)
        self.replan = replan

    def render(self, index: int):
        original = forward.plan_visible_samples
        forward.plan_visible_samples = lambda objects, camera, items, last=None: self.replan(
            original(objects, camera, items, last), items)
        try:
            return super().render(index)
        finally:
            forward.plan_visible_samples = original


PREPASS_PLANS = {
    # every opaque object, nearest first
    "full-prepass": lambda plan, items: VisibleSamplesPlan(items, frozenset(item.object_index for item in items)),
    # none: the shading draw writes every depth itself (wrong shadows where a surface is
    # drawn before what hides it; for timing the prepass alone)
    "empty-prepass": lambda plan, items: VisibleSamplesPlan(plan.order, frozenset()),
}


@contextmanager
def shaders_from(folder: str):
    """Renderers made inside compile their programs from ``folder``."""
    original = shaders.shader_dir
    shaders.shader_dir = lambda: Path(folder)
    try:
        yield
    finally:
        shaders.shader_dir = original


@contextmanager
def footprint_off():
    """Renderers made inside take shadow visibility at one point per pixel."""
    original = features._footprint_samples
    features._footprint_samples = lambda samples: 1
    try:
        yield
    finally:
        features._footprint_samples = original


def make_renderer(gl, scene_path: str, base_overrides: list, variant: str) -> tuple[str, GraphRenderer]:
    if variant == "no-footprint":
        with footprint_off():
            return variant, GraphRenderer(scenerender.load(scene_path, base_overrides).world, gl, profile=True)
    if variant == "no-visible-samples":
        world = scenerender.load(scene_path, base_overrides).world
        return variant, GraphRenderer(world, gl, profile=True, tuning={"visible_samples": False})
    if variant == "device-srgb":
        world = scenerender.load(scene_path, base_overrides).world
        return variant, GraphRenderer(world, gl, profile=True, tuning={"shader_srgb_encoding": False})
    if variant in PREPASS_PLANS:
        world = scenerender.load(scene_path, base_overrides).world
        return variant, ReplannedPrepass(world, gl, PREPASS_PLANS[variant], profile=True)
    if variant == "no-face-culling":
        return variant, NoFaceCulling(scenerender.load(scene_path, base_overrides).world, gl, profile=True)
    if "@" in variant and "=" not in variant:
        name, _, folder = variant.partition("@")
        with shaders_from(folder):
            return name, GraphRenderer(scenerender.load(scene_path, base_overrides).world, gl, profile=True)
    name, _, overrides = variant.partition("=")
    extra = [o for o in overrides.split(";") if o] if overrides else []
    return name, GraphRenderer(scenerender.load(scene_path, base_overrides + extra).world, gl, profile=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--set", dest="sets", action="append", default=[], help="override for every variant")
    parser.add_argument("--variant", dest="variants", action="append", default=[])
    parser.add_argument("--frames", type=int, default=10, help="frames per variant after the first (default 10)")
    args = parser.parse_args()
    gl = create_context()
    renderers = [make_renderer(gl, args.scene, args.sets, "default=")]
    renderers += [make_renderer(gl, args.scene, args.sets, v) for v in args.variants]
    for _, renderer in renderers:
        renderer.render(0)  # shaders compiled, static passes drawn
        renderer.timings.clear()
    frames = {name: [] for name, _ in renderers}
    for index in range(1, args.frames + 1):
        for name, renderer in renderers:
            started = time.perf_counter()
            renderer.render(index)
            frames[name].append(time.perf_counter() - started)
    passes = list(dict.fromkeys(name for _, r in renderers for name in r.timings)) + ["frame"]
    for name, renderer in renderers:
        renderer.timings["frame"] = frames[name]
    print("| variant | " + " | ".join(passes) + " | frame vs default |")
    print("|---" * (len(passes) + 2) + "|")
    baseline = frames["default"]
    for name, renderer in renderers:
        cells = [f"{statistics.median(renderer.timings[p]) * 1000:.1f}" if p in renderer.timings else "-"
                 for p in passes]
        # each frame against the default's frame of the same round: steadier than two medians
        # on a machine whose load drifts
        ratio = statistics.median(t / b for t, b in zip(frames[name], baseline))
        print(f"| {name} | " + " | ".join(cells) + f" | {ratio:.3f} |")


if __name__ == "__main__":
    main()
