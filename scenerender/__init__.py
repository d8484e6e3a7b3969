"""scenerender: a declarative offscreen batch renderer.

A YAML scene file becomes a validated scene model (``scenerender.scene``), then a render
graph of passes pruned to what the scene uses (``scenerender.graph``), executed on one
OpenGL context (``scenerender.gpu``) and written by frame sinks (``scenerender.sinks``).
"""

__version__ = "0.1.0"
