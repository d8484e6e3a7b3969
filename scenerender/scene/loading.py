"""Read a scene file, apply ``--set`` overrides, validate, check the files it names: the
scene model's front door."""
from __future__ import annotations

import copy
from dataclasses import dataclass, field
from pathlib import Path

from pydantic import ValidationError

from scenerender.errors import SourceLocation, UserError
from scenerender.limits import Limits
from scenerender.scene.assets import AssetPolicy
from scenerender.scene.bounds import check_document, check_scene
from scenerender.scene.file_checks import check_files
from scenerender.scene.messages import to_user_errors
from scenerender.scene.model.scene import SceneSpec
from scenerender.scene.overrides import apply_overrides
from scenerender.scene.yaml_source import SourceMap, load_yaml, parse_yaml_text


@dataclass(frozen=True)
class LoadedScene:
    """A validated scene and where it came from.

    spec:     the validated ``SceneSpec`` (animatable values are ``Track`` objects, paths
              resolved ``Path`` objects).
    path:     the scene file (absolute); assets resolve against ``path.parent``.
    source:   key path -> file position, for messages about assets found later.
    data:     the raw data after overrides (for ``graph``/debug output).
    limits:   the size limits in force (``--limit``); asset loading checks triangles and
              texture pixels against it.
    assets:   the AssetPolicy every asset is resolved through; ``assets.files_read`` lists
              each file the scene read (after ``build_world``, every file the run reads).
    """

    spec: SceneSpec
    path: Path
    source: SourceMap
    data: dict
    limits: Limits = field(default_factory=Limits)
    assets: AssetPolicy | None = None

    def __post_init__(self):
        if self.assets is None:  # built by hand (tests): the scene's folder is the only root
            object.__setattr__(self, "assets", AssetPolicy(self.path.parent))

    @property
    def base_dir(self) -> Path:
        return self.path.parent

    @property
    def name(self) -> str:
        return self.path.stem


def load_scene(path, overrides: list[str] | tuple = (), limits: Limits | None = None,
               asset_roots=()) -> LoadedScene:
    """Load and validate ``path``; ``overrides`` are ``key.path=value`` strings (YAML values);
    ``asset_roots`` are folders besides the scene's own that assets may come from.

    Raises ``SceneErrors`` (a ``UserError``) naming file, line, column and key on bad input.
    """
    limits = limits or Limits()
    if "\0" in str(path):  # os functions raise ValueError for it; no file can have such a name
        raise UserError("a file name cannot contain a NUL character", SourceLocation(repr(str(path))))
    path = Path(path).resolve()
    data, source = load_yaml(path, limits)
    return _validate(data, source, path, overrides, limits, asset_roots)


def load_scene_text(text: str, base_dir, overrides=(), name: str = "scene.yaml",
                    limits: Limits | None = None, asset_roots=()) -> LoadedScene:
    """Like ``load_scene`` for YAML text (tests, stdin); paths resolve against ``base_dir``."""
    limits = limits or Limits()
    data, source = parse_yaml_text(text, name, limits)
    return _validate(data, source, Path(base_dir).resolve() / name, overrides, limits, asset_roots)


def load_scene_data(data, base_dir, overrides=(), name: str = "scene", limits: Limits | None = None,
                    asset_roots=(), mesh_types: tuple = ()) -> LoadedScene:
    """Like ``load_scene`` for a mapping built in code. ``name`` names its outputs (videos);
    messages say "NAME (built in code)" and the key path. A ``mesh`` may hold an object of
    one of ``mesh_types`` (meshes made in code) as it is."""
    return _validate(copy.deepcopy(dict(data)), SourceMap(f"{name} (built in code)"), Path(base_dir).resolve() / name,
                     overrides, limits or Limits(), asset_roots, mesh_types)


def load_scene_mapping(data, path, label: str, overrides=(), limits: Limits | None = None,
                       asset_roots=()) -> LoadedScene:
    """Like ``load_scene`` for a mapping made from the file ``path`` (a model rendered as it
    stands): assets resolve beside it, outputs take its name, messages name ``label``."""
    return _validate(copy.deepcopy(dict(data)), SourceMap(label), Path(path).resolve(), overrides,
                     limits or Limits(), asset_roots)


def _validate(data, source: SourceMap, path: Path, overrides, limits: Limits, asset_roots=(),
              mesh_types: tuple = ()) -> LoadedScene:
    data = check_document(data, source, limits)
    data = apply_overrides(data, overrides, source)
    check_document(data, source, limits)  # --set may have added objects
    assets = AssetPolicy(path.parent, asset_roots)
    try:
        spec = SceneSpec.model_validate(data, context={"mesh_types": tuple(mesh_types)})
    except ValidationError as exc:
        raise to_user_errors(exc, data, source) from None
    spec = check_files(spec, data, source, assets, limits)
    check_scene(spec, source, limits)
    return LoadedScene(spec=spec, path=path, source=source, data=data, limits=limits, assets=assets)

