"""A frame graph: passes declare the resources they read and write; compiling culls what
no output needs and marks what can be cached across frames. No GL in here."""
from scenerender.graph.framegraph import CompiledGraph, FrameGraph, Handle, PassBuilder, RenderPass, ResourceDesc

__all__ = ["CompiledGraph", "FrameGraph", "Handle", "PassBuilder", "RenderPass", "ResourceDesc"]
