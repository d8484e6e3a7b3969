"""Read a scene file, apply ``--set`` overrides, validate: the scene model's front door."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from pydantic import ValidationError

from scenerender.scene.messages import to_user_errors
from scenerender.scene.overrides import apply_overrides
from scenerender.scene.schema import Scene
from scenerender.scene.yaml_source import SourceMap, load_yaml, parse_yaml_text


@dataclass(frozen=True)
class LoadedScene:
    """A validated scene and where it came from.

    spec:     the validated ``schema.Scene`` (animatable values are ``Track`` objects).
    path:     the scene file (absolute); assets resolve against ``path.parent``.
    source:   key path -> file position, for messages about assets found later.
    data:     the raw data after overrides (for ``graph``/debug output).
    """

    spec: Scene
    path: Path
    source: SourceMap
    data: dict

    @property
    def base_dir(self) -> Path:
        return self.path.parent

    @property
    def name(self) -> str:
        return self.path.stem


def load_scene(path, overrides: list[str] | tuple = ()) -> LoadedScene:
    """Load and validate ``path``; ``overrides`` are ``key.path=value`` strings (YAML values).

    Raises ``SceneErrors`` (a ``UserError``) naming file, line, column and key on bad input.
    """
    path = Path(path).resolve()
    data, source = load_yaml(path)
    return _validate(data, source, path, overrides)


def load_scene_text(text: str, base_dir, overrides=(), name: str = "scene.yaml") -> LoadedScene:
    """Like ``load_scene`` for YAML text (tests, stdin); paths resolve against ``base_dir``."""
    data, source = parse_yaml_text(text, name)
    return _validate(data, source, Path(base_dir).resolve() / name, overrides)


def _validate(data, source: SourceMap, path: Path, overrides) -> LoadedScene:
    if data is None:
        data = {}
    data = apply_overrides(data, overrides, source)
    try:
        spec = Scene.model_validate(data, context={"base_dir": path.parent})
    except ValidationError as exc:
        raise to_user_errors(exc, data, source) from None
    return LoadedScene(spec=spec, path=path, source=source, data=data)

