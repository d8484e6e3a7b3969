"""A scene loaded and a renderer on one GL context: what every run path is made of.

    scene = load("scenes/garden.yaml", overrides=["render.size=[320,240]"])
    with Renderer(scene) as renderer:
        frame = renderer.render(0)          # frame.pixels: (240, 320, 3) uint8, top row first

The run code (``scenerender.run.job``, ``scenerender.run.workers``) is built on these
objects; ``scenerender.api`` re-exports them as the public API.
"""
from __future__ import annotations

import copy
import os
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scenerender.errors import UserError, Warnings
from scenerender.gpu.gl_context import create_context, refuse_software, renderer_name
from scenerender.mesh.data import MeshData
from scenerender.option_rules import MSAA_SAMPLES
from scenerender.rendering.profile import profile_report
from scenerender.rendering.renderer import FrameResult
from scenerender.rendering.renderer import GraphRenderer
from scenerender.run.model_scene import load_scene_or_model
from scenerender.scene.loading import load_scene_data, load_scene_text
from scenerender.world.build import build_world

REQUIRE_GPU_VARIABLE = "SCENERENDER_REQUIRE_GPU"  # =1: as --require-gpu, for every render of the process

# A rendered frame: ``index``, ``time`` (seconds, float64), ``pixels`` ((H, W, 3) uint8,
# top row first, display-encoded), ``linear`` ((H, W, 3) float32 linear light, or None) and
# ``object_ids`` ((H, W) uint16, each pixel's object index + 1, 0 for none; or None).
Frame = FrameResult

# Bad input: a scene, an asset or an option. ``str(error)`` is the one-line message;
# ``error.location`` has ``file``, ``line`` and ``column``; ``error.key`` is the key path
# (``objects[2].mesh``). Several problems at once arrive as one error whose ``errors`` lists them.
SceneError = UserError


class Scene:
    """A validated scene with its meshes loaded and materials resolved (no GL yet).

    Make one with ``scenerender.load(path)`` or ``Scene.from_dict(mapping)``.

    path:        the scene file (absolute), or ``base_dir / name`` for scenes made in code
    name:        the file stem: names videos (``out/<name>.mp4``)
    size:        (width, height) in pixels
    fps:         frames per second of the animation
    frame_count: how many frames the scene's output has
    warnings:    warning lines raised while loading (missing MTL textures...)
    loaded:      the validated scene model (scenerender.scene.loading.LoadedScene: ``spec``, the
                 file's path and the source positions its messages name)
    world:       what a renderer draws from it (scenerender.world.build.World: objects, lights
                 and materials, evaluated at any time); tools and benchmarks read it
    """

    def __init__(self, loaded, world, source: "SceneSource | None" = None):
        self.loaded = loaded
        self.world = world
        self.source = source  # how to load it again (workers do); None when built in code

    @classmethod
    def from_dict(cls, mapping: Mapping, base_dir=".", overrides: Iterable[str] = (), *, name: str = "scene",
                  strict: bool = False, asset_roots: Iterable = (), limits=None, on_warning=None) -> "Scene":
        """Validate a scene written in code, with the same rules and messages as a file.

        Relative paths resolve against ``base_dir``; ``name`` names videos (``NAME.mp4``). Where a mesh is expected, code may
        also pass a ``trimesh.Trimesh`` or a ``(vertices, faces)`` pair: vertices (N, 3)
        float, faces (M, 3) int, counter-clockwise seen from outside.
        """
        data = _with_in_memory_meshes(mapping)
        warnings = Warnings(strict=strict, echo=on_warning)
        loaded = load_scene_data(data, base_dir, list(overrides), name=name, asset_roots=tuple(asset_roots), limits=limits,
                                 mesh_types=(MeshData,))
        return cls._built(loaded, warnings)

    @classmethod
    def from_yaml(cls, text: str, base_dir=".", overrides: Iterable[str] = (), *, name: str = "scene",
                  strict: bool = False, asset_roots: Iterable = (), limits=None, on_warning=None) -> "Scene":
        """Like ``load`` for YAML text in memory; relative paths resolve against ``base_dir``
        and messages name ``NAME.yaml``."""
        loaded = load_scene_text(text, base_dir, list(overrides), name=f"{name}.yaml", limits=limits,
                                 asset_roots=tuple(asset_roots))
        return cls._built(loaded, Warnings(strict=strict, echo=on_warning))

    @classmethod
    def _built(cls, loaded, warnings: Warnings) -> "Scene":
        return cls(loaded, build_world(loaded, warnings))

    @property
    def path(self) -> Path:
        return self.loaded.path

    @property
    def name(self) -> str:
        return self.loaded.name

    @property
    def size(self) -> tuple[int, int]:
        width, height = self.loaded.spec.render.size
        return int(width), int(height)

    @property
    def fps(self) -> float:
        return float(self.loaded.spec.output.fps)

    @property
    def frame_count(self) -> int:
        return self.loaded.spec.output.frame_count

    @property
    def warnings(self) -> list[str]:
        return list(self.world.warnings.items)

    def __repr__(self) -> str:
        width, height = self.size
        return f"Scene({self.name!r}, {width}x{height}, {self.frame_count} frame(s) at {self.fps:g} fps)"


def load(path, overrides: Iterable[str] = (), *, strict: bool = False, asset_roots: Iterable = (),
         limits=None, on_warning=None) -> Scene:
    """Read, override and validate a scene file and load what it names; a glTF file
    (.glb, .gltf) is the scene a viewer would make of it (run.model_scene).

    ``overrides`` are ``key.path=value`` strings like the CLI's ``--set``
    (``"render.size=[320,240]"``). ``asset_roots`` are folders besides the scene's own
    that assets may come from; ``limits`` a ``scenerender.limits.Limits``. ``on_warning``
    is called with each warning line ("warning: ...") as it is raised; ``strict`` makes warnings errors.
    Raises ``SceneError`` naming file, line and key.
    """
    loaded = load_scene_or_model(path, list(overrides), asset_roots=tuple(asset_roots), limits=limits)
    scene = Scene._built(loaded, Warnings(strict=strict, echo=on_warning))
    scene.source = SceneSource(loaded.path, tuple(overrides), tuple(asset_roots), limits)
    return scene


@dataclass(frozen=True)
class SceneSource:
    """What ``load`` was given: enough for another process to load the same scene."""

    path: Path
    overrides: tuple = ()
    asset_roots: tuple = ()
    limits: object = None


class Renderer:
    """Renders frames of one scene on its own OpenGL context (EGL), or on ``gl``, a
    moderngl context the caller owns and keeps.

        with Renderer(scene, size=(320, 240), samples=1) as renderer:
            frames = [renderer.render(i) for i in range(3)]

    size:    (width, height), default the scene's ``render.size``
    samples: MSAA samples, default the scene's ``render.samples``: 1 (off), 2, 4 ... 64, the
             scene file's rule (``option_rules.MSAA_SAMPLES``; ValueError otherwise), lowered
             with a warning to the largest count the device offers
    want_linear: also return each frame's linear colours (``Frame.linear``; a float target, slower)
    object_ids: also return which object each pixel shows (``Frame.object_ids``: (H, W) uint16,
             the object's index in the scene's ``objects`` + 1, 0 for none; one sample at each
             pixel's centre, the nearest surface)
    profile: time every pass (GPU-synchronised); see ``timings``
    cache_static_passes: False renders every pass every frame (to measure what caching saves)
    require_gpu: a software GL renderer (llvmpipe, softpipe, swrast) is an EnvironmentProblem
             (exit 3 on the command line); default: the SCENERENDER_REQUIRE_GPU variable
    report_work: called (what, share done in [0, 1]) as long GPU work (the environment's
             prefilter) goes on, e.g. ``Progress.work``
    """

    def __init__(self, scene: Scene, size: tuple[int, int] | None = None, samples: int | None = None,
                 *, gl=None, want_linear: bool = False, profile: bool = False, cache_static_passes: bool = True,
                 object_ids: bool = False, require_gpu: bool | None = None, report_work=None):
        if samples is not None:
            samples = MSAA_SAMPLES.check(samples)  # before a context is made for nothing
        self.scene = scene
        self._owns_gl = gl is None
        self.gl = create_context() if gl is None else gl
        try:
            if gpu_required(require_gpu):
                refuse_software(self.gl)
            self._renderer = GraphRenderer(scene.world, self.gl, size=size, samples=samples,
                                           warn=scene.world.warnings.warn, want_linear=want_linear,
                                           profile=profile, cache_static_passes=cache_static_passes,
                                           object_ids=object_ids, report_work=report_work)
        except BaseException:
            self._release_gl()
            raise

    @property
    def size(self) -> tuple[int, int]:
        return self._renderer.size

    @property
    def gl_renderer(self) -> str:
        """The GL renderer drawing the frames, e.g. 'llvmpipe (LLVM 15.0.6, 256 bits)'."""
        return renderer_name(self.gl)

    @property
    def samples(self) -> int:
        return self._renderer.samples

    @property
    def timings(self) -> dict | None:
        """With ``profile=True``: pass name -> list of seconds, one per run of the pass."""
        return self._renderer.timings

    def take_notes(self) -> list[str]:
        """Lines about the frames rendered since the last call, for a progress output: how
        long a bake took (render.indirect's probes), once per bake."""
        notes, self._renderer.notes = self._renderer.notes, []
        return notes

    def profile_report(self, frames: int) -> str:
        """With ``profile=True``: the table of ms per pass over ``frames`` rendered frames."""
        return profile_report(self._renderer, frames)

    def render(self, index: int) -> Frame:
        """Frame ``index`` (time ``index / fps``). Any index >= 0 works, also past the
        scene's last frame (animations hold their last key or loop)."""
        if index < 0:
            raise ValueError(f"frame index must be >= 0, got {index}")
        return self._renderer.render(int(index))

    def camera_record(self, index: int) -> dict:
        """Frame ``index``'s camera as cameras.json records it (K, poses, near, far),
        without rendering the frame."""
        return self._renderer.camera_record(int(index))

    def close(self) -> None:
        """Free the GL objects (and the context, when this renderer made it). Idempotent."""
        if self._renderer is not None:
            self._renderer.release()
            self._renderer = None
        self._release_gl()

    def _release_gl(self) -> None:
        if self._owns_gl and self.gl is not None:
            self.gl.release()
        self.gl = None

    def __enter__(self) -> "Renderer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def gpu_required(require_gpu: bool | None = None) -> bool:
    """``require_gpu``, or where None whether SCENERENDER_REQUIRE_GPU is set (not 0 or empty)."""
    if require_gpu is not None:
        return require_gpu
    return os.environ.get(REQUIRE_GPU_VARIABLE, "").strip().lower() not in ("", "0", "false", "no")


def render(scene: Scene, frames: Iterable[int] | None = None, size=None, samples=None, *,
           object_ids: bool = False) -> Iterator[Frame]:
    """Render ``frames`` (default: every frame of the scene) one by one on one context;
    ``object_ids``: each frame's ``object_ids`` too (see ``Renderer``)."""
    indices = range(scene.frame_count) if frames is None else frames
    with Renderer(scene, size=size, samples=samples, object_ids=object_ids) as renderer:
        for index in indices:
            yield renderer.render(index)


def _with_in_memory_meshes(mapping: Mapping) -> dict:
    """A copy of ``mapping`` whose trimesh meshes and (vertices, faces) pairs are MeshData."""
    data = copy.copy(dict(mapping))
    objects = data.get("objects")
    if isinstance(objects, list):
        data["objects"] = [_object_with_mesh(obj) for obj in objects]
    return data


def _object_with_mesh(obj):
    if not isinstance(obj, Mapping) or "mesh" not in obj:
        return obj
    mesh = _as_mesh_data(obj["mesh"])
    return obj if mesh is None else {**obj, "mesh": mesh}


def _as_mesh_data(value):
    """MeshData for a trimesh.Trimesh or a (vertices, faces) pair; None for anything else."""
    if isinstance(value, MeshData):
        return value
    if type(value).__name__ == "Trimesh" and hasattr(value, "faces"):
        uv = getattr(getattr(value, "visual", None), "uv", None)
        return _mesh_from_arrays(value.vertices, value.faces, uv=uv, source="trimesh mesh")
    if isinstance(value, (tuple, list)) and len(value) == 2 and all(hasattr(v, "__len__") for v in value):
        try:
            vertices, faces = np.asarray(value[0]), np.asarray(value[1])
        except (ValueError, TypeError):
            return None
        if vertices.ndim == 2 and faces.ndim == 2:
            return _mesh_from_arrays(vertices, faces, source="(vertices, faces) arrays")
    return None


def _mesh_from_arrays(vertices, faces, uv=None, source: str = "arrays"):
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or not np.isfinite(vertices).all():
        raise UserError(f"{source}: vertices must be a finite (N, 3) array, got shape {vertices.shape}")
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0 or not np.issubdtype(faces.dtype, np.integer):
        raise UserError(f"{source}: faces must be a non-empty (M, 3) integer array, got shape {faces.shape}")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise UserError(f"{source}: a face index is outside 0..{len(vertices) - 1}")
    uvs = None
    if uv is not None and len(uv) == len(vertices):
        uvs = np.asarray(uv, dtype=np.float32)[:, :2]
    return MeshData(positions=vertices.astype(np.float32), normals=None, uvs=uvs,
                    indices=faces.astype(np.uint32), source=source)
