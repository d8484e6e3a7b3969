"""Rendering a World: the passes, the graph built from a scene, and the GPU scene state."""
