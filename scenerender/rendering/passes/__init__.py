"""The render passes. Each declares its reads and writes in ``setup`` and draws in
``execute``; ``scenerender.rendering.pipeline`` decides which ones a scene gets."""
