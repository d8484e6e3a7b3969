"""The scene model: a YAML file read, overridden, validated and typed, without any GL.

``load_scene(path)`` is the entry point; it returns a ``LoadedScene`` whose ``spec`` is the
validated ``SceneSpec`` (``scene/model/``, files looked up by ``scene/file_checks.py``) and
whose ``source`` maps key paths back to file positions.
"""
from scenerender.scene.loading import LoadedScene, load_scene

__all__ = ["LoadedScene", "load_scene"]
