"""The render passes. Each declares its reads and writes in ``setup`` and draws in
``execute``; ``scenerender.render.pipeline`` decides which ones a scene gets."""
