"""scenerender's version: what the run manifest, the mesh cache and ``diff`` record as the
maker of their files (kept equal to pyproject.toml's, which a test checks)."""

__version__ = "0.8.0"
