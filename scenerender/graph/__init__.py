"""A frame graph: passes declare the resources they read and write; compiling culls what
no output needs and marks what can be cached across frames. No GL in here."""
from scenerender.graph.framegraph import (
    COLOR_FORMATS, DEPTH_FORMATS, CompiledGraph, FrameGraph, Handle, InputDesc, PassBuilder, PassNode, RenderPass,
    ResourceDesc, UndeclaredResource,
)

__all__ = ["COLOR_FORMATS", "DEPTH_FORMATS", "CompiledGraph", "FrameGraph", "Handle", "InputDesc", "PassBuilder",
           "PassNode", "RenderPass", "ResourceDesc", "UndeclaredResource"]
