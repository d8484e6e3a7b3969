"""The OpenGL layer: context creation, shader assembly, uploads and resource allocation.
Everything that imports moderngl lives here or in ``scenerender.rendering``."""
