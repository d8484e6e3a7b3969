"""scenerender: a declarative offscreen batch renderer.

A YAML scene file becomes a validated scene model (``scenerender.scene``), then a render
graph of passes pruned to what the scene uses (``scenerender.graph``), executed on one
OpenGL context (``scenerender.gpu``) and written by frame sinks (``scenerender.sinks``).

The public API (see ``scenerender.api``)::

    import scenerender
    scene = scenerender.load("scene.yaml")
    with scenerender.Renderer(scene) as renderer:
        pixels = renderer.render(0).pixels      # (H, W, 3) uint8
"""

from scenerender.version import __version__

__all__ = ["Frame", "Renderer", "Scene", "SceneError", "load", "render", "render_to", "__version__"]


def __getattr__(name: str):
    # The API pulls in numpy, pydantic and the render graph; `scenerender --version` and
    # the CLI's fast paths should not pay for that, so it is imported on first use.
    if name in __all__:
        from scenerender import api

        return getattr(api, name)
    raise AttributeError(f"module 'scenerender' has no attribute {name!r}")
