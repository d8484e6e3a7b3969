"""The render passes. Each is a frozen dataclass of its configuration and input handles:
``setup`` declares its reads and writes and returns frozen data, ``execute`` draws with
only what was declared; ``scenerender.rendering.pipeline`` decides which ones a scene gets."""
