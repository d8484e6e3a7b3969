"""The public Python API: load a scene, render frames, write outputs.

    import scenerender

    scene = scenerender.load("scenes/garden.yaml", overrides=["render.size=[320,240]"])
    with scenerender.Renderer(scene) as renderer:
        frame = renderer.render(0)          # frame.pixels: (240, 320, 3) uint8, top row first
    summary = scenerender.render_to(scene, "out/")   # what `scenerender render` does

Everything here is plain objects defined in the run layer (``scenerender.run``); this
module only names them. The command line, the pytest plugin and the benchmarks are built
on it.
"""
from scenerender.run.job import RenderSummary, render_to
from scenerender.run.session import (
    Frame,
    Renderer,
    Scene,
    SceneError,
    SceneSource,
    load,
    render,
)

__all__ = ["Frame", "RenderSummary", "Renderer", "Scene", "SceneError", "SceneSource", "load", "render", "render_to"]
