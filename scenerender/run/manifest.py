"""The run manifest: a JSON sidecar beside every output that records what made each frame.

A re-run keeps a frame only when the manifest says it was made from the same inputs (the
scene's settings after overrides, the bytes of every asset it read, the scenerender
version) and the file on disk is the one that run wrote (same size and SHA-256). Anything
else is rendered again, and frames an earlier, different run left behind are removed, so
an output folder never mixes frames of two versions of a scene.

Where it lives: ``<folder>/.scenerender.json`` for an image sequence, and
``<parent>/.<file name>.scenerender.json`` for a video or a single image. Besides the
fingerprints it records provenance: the scenerender version and the GL renderer that made
the frames (and whether it drew on the CPU: ``gl.software``), which ``scenerender diff`` shows.

A manifest is read through the JSON guard (json_input: bounded size and depth)
and validated into ``ManifestFile``; one that fails (cut short, edited, written by another
format) is treated as absent, with one warning: nothing is reused and every frame is
rendered again.
"""
from __future__ import annotations

import hashlib
import json
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, ValidationError

from scenerender.errors import UserError, display_path
from scenerender.gpu.gl_context import is_software
from scenerender.json_input import MANIFEST_MAX_BYTES, JsonProblem, parse_json
from scenerender.mesh.data import MeshData
from scenerender.scene.files import read_json_file
from scenerender.scene.messages import json_file_error
from scenerender.sinks.base import atomic_path, write_file
from scenerender.sinks.cameras import cameras_path, write_cameras
from scenerender.version import __version__

FORMAT_VERSION = 1
SAVE_INTERVAL = 1.0  # seconds between saves during a run: a killed run loses at most this much
SIDECAR_SUFFIX = ".scenerender.json"
FOLDER_SIDECAR = ".scenerender.json"


class _Record(BaseModel):
    # strict: what a run wrote comes back with the same types. Keys a newer run adds are
    # kept, and keys an older one left out are absent: each has the default its reader uses.
    model_config = ConfigDict(strict=True, extra="allow")


class FileRecord(_Record):
    bytes: int | None = None
    sha256: str | None = None


class FrameRecord(FileRecord):
    """A frame file (or a video, a single image) written completely; ``cameras``: the
    camera record of each frame it holds, each as JSON text."""

    index: int | None = None
    scene: str | None = None
    run: str | None = None
    object_ids: FileRecord | None = None
    cameras: list[str] | None = None


class RunRecord(_Record):
    """A scene's last run into the output: its fingerprint digest and parts."""

    run: str | None = None
    inputs: dict[str, str] = {}


class GlRecord(_Record):
    renderer: str | None = None
    vendor: str | None = None
    version: str | None = None
    software: bool | None = None


class ManifestFile(_Record):
    """What a manifest file holds."""

    format: Literal[FORMAT_VERSION]
    scenerender: str | None = None
    frames: dict[str, FrameRecord] = {}
    runs: dict[str, RunRecord] = {}
    gl: GlRecord | None = None


def sidecar_for(target: Path, is_folder: bool) -> Path:
    """Where the manifest of ``target`` lives."""
    target = Path(target)
    return target / FOLDER_SIDECAR if is_folder else target.parent / f".{target.name}{SIDECAR_SUFFIX}"


def read_sidecar(path: Path) -> tuple[dict, str | None]:
    """(the manifest at ``path`` as plain JSON values, None), or ({}, why it is unusable):
    ({}, None) where there is none. An unusable one is as good as absent: nothing is reused."""
    path = Path(path)
    if not path.exists() and not path.is_symlink():
        return {}, None
    try:
        data = read_json_file(path, "run manifest", MANIFEST_MAX_BYTES)
        ManifestFile.model_validate(data)
    except UserError as exc:
        return {}, str(exc)
    except ValidationError as exc:
        return {}, str(json_file_error(exc, data, display_path(path)))
    return data, None


def file_digest(path: Path) -> str:
    """SHA-256 of a file's bytes, hex."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


# ---------------------------------------------------------------------------------------
# what a run is made from


@dataclass(frozen=True)
class Fingerprint:
    """The inputs of a run. ``parts`` names each input (``settings``, ``version``,
    ``asset:models/duck.obj``...) with its digest; ``digest`` covers them all."""

    parts: dict

    @property
    def digest(self) -> str:
        text = json.dumps(self.parts, sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()

    def changes_since(self, old_parts: dict) -> list[str]:
        """Human-readable names of what differs from an earlier run's ``parts``."""
        changed = []
        if old_parts.get("version") != self.parts["version"]:
            changed.append(f"scenerender {old_parts.get('version', 'unknown')} -> {self.parts['version']}")
        if old_parts.get("overrides") != self.parts["overrides"]:
            changed.append("the --set/--size/--samples/--format options")
        if old_parts.get("object_ids") != self.parts.get("object_ids"):
            changed.append("the --object-ids option")
        if old_parts.get("scene_file") != self.parts.get("scene_file"):
            changed.append("the scene file")
        elif old_parts.get("settings") != self.parts["settings"] and not changed:
            changed.append("the scene's settings")
        for key in sorted(set(old_parts) | set(self.parts)):
            if key.startswith("asset:") and old_parts.get(key) != self.parts.get(key):
                verb = "is new" if key not in old_parts else ("is no longer used" if key not in self.parts else "changed")
                changed.append(f"{key[len('asset:'):]} {verb}")
        return changed


def fingerprint(loaded, overrides=(), object_ids: bool = False) -> Fingerprint:
    """The fingerprint of a loaded scene whose world has been built (so every asset it
    reads has been resolved and is listed in ``loaded.assets.files_read``). A run that
    keeps object ids (``object_ids``) has a part of its own, so its frames are not taken
    for a run's without, nor the other way round."""
    parts = {
        "version": __version__,
        "overrides": _digest_text(json.dumps(list(overrides))),
        "settings": _digest_text(json.dumps(loaded.data, sort_keys=True, default=_encode_value)),
    }
    if object_ids:
        parts["object_ids"] = "kept"
    if loaded.path.is_file():  # a comment edit re-renders too: cheap, and never wrong
        parts["scene_file"] = file_digest(loaded.path)
    for path in loaded.assets.files_read:
        parts[f"asset:{_asset_name(path, loaded.base_dir)}"] = file_digest(path)
    return Fingerprint(parts)


def _digest_text(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()


def _encode_value(value):
    """JSON for what scene data may hold besides plain values: meshes made in code, arrays."""
    if isinstance(value, MeshData):
        arrays = (value.positions, value.indices, value.normals, value.uvs)
        digest = hashlib.sha256()
        for array in arrays:
            digest.update(b"-" if array is None else np.ascontiguousarray(array).tobytes())
        return {"mesh": digest.hexdigest()}
    if isinstance(value, np.ndarray):
        return value.tolist()
    return str(value)


def _asset_name(path: Path, base_dir: Path) -> str:
    try:
        return Path(path).relative_to(base_dir).as_posix()
    except ValueError:
        return display_path(path)


# ---------------------------------------------------------------------------------------
# one output's manifest


@dataclass
class Manifest:
    """The manifest of one output (a frame folder, a video or one image) during a run."""

    path: Path
    run: Fingerprint
    scene: str            # which scene's frames these are: several scenes may share a folder
    data: dict = field(default_factory=dict)
    cameras_file: Path | None = None  # the output's cameras.json (sinks/cameras.py)
    unusable: str | None = None       # why the manifest found there was treated as absent
    _last_save: float = 0.0

    @classmethod
    def open(cls, target: Path, is_folder: bool, run: Fingerprint, scene: str, cameras: bool = True) -> "Manifest":
        """``cameras``: keep a cameras.json beside the output (not beside one image)."""
        path = sidecar_for(target, is_folder)
        data, unusable = read_sidecar(path)
        data.setdefault("frames", {})
        data.setdefault("runs", {})
        return cls(path=path, run=run, scene=scene, data=data,
                   cameras_file=cameras_path(target, is_folder) if cameras else None, unusable=unusable)

    @property
    def previous_run(self) -> str | None:
        """The digest of this scene's last run into this output, if any."""
        return self.data["runs"].get(self.scene, {}).get("run")

    @property
    def previous_inputs(self) -> dict:
        return self.data["runs"].get(self.scene, {}).get("inputs", {})

    def is_current(self, name: str, file: Path, ids: Path | None = None) -> bool:
        """True when ``file`` is the frame ``name`` this same run would write, unaltered,
        and so are its object ids ``ids`` when the run keeps them."""
        entry = self.data["frames"].get(name)
        if not entry or entry.get("run") != self.run.digest:
            return False
        if ids is not None and not _unaltered(ids, entry.get("object_ids") or {}):
            return False
        return _unaltered(file, entry)

    def stale_frames(self) -> list[str]:
        """Names of this scene's frames recorded by a run with other inputs (out of date).
        Frames of other scenes sharing the folder are theirs and left alone."""
        return [name for name, entry in self.data["frames"].items()
                if entry.get("scene") == self.scene and entry.get("run") != self.run.digest]

    def forget(self, name: str) -> None:
        self.data["frames"].pop(name, None)

    def start(self, gl_info: dict | None) -> None:
        """A run begins writing: record what it is made of and the GL renderer."""
        self.data.update(format=FORMAT_VERSION, scenerender=__version__)
        self.data["runs"][self.scene] = {"run": self.run.digest, "inputs": self.run.parts}
        if gl_info:
            renderer = gl_info.get("GL_RENDERER")
            self.data["gl"] = {"renderer": renderer, "vendor": gl_info.get("GL_VENDOR"),
                               "version": gl_info.get("GL_VERSION"),
                               "software": renderer is not None and is_software(str(renderer))}
        self.save()

    def record(self, name: str, index: int, file: Path, ids: Path | None = None, cameras: list | None = None) -> None:
        """``file`` (frame ``index``) was written completely, and its object ids ``ids``;
        ``cameras``: the camera record of each frame it holds (world/camera_data.py)."""
        entry = {"index": int(index), "scene": self.scene, "run": self.run.digest,
                 "bytes": file.stat().st_size, "sha256": file_digest(file)}
        if ids is not None:
            entry["object_ids"] = {"bytes": ids.stat().st_size, "sha256": file_digest(ids)}
        if cameras:  # as JSON text: a record's 40 numbers would be 40 lines of the indented manifest
            entry["cameras"] = [json.dumps(camera) for camera in cameras]
        self.data["frames"][name] = entry
        if time.monotonic() - self._last_save >= SAVE_INTERVAL:
            self.save()

    def finish(self) -> None:
        """Save the manifest and write the output's cameras.json from it."""
        self.save()
        self.write_cameras()

    def write_cameras(self) -> None:
        """cameras.json from the frames the manifest vouches for: the cameras of every
        frame file there, in file order, each named by its file and scene."""
        records = []
        for name, entry in sorted(self.data["frames"].items()):
            for text in entry.get("cameras") or ():
                file = {"file": name} if self.path.name == FOLDER_SIDECAR else {}
                records.append({**file, "scene": entry.get("scene"), **_camera(text)})
        if self.cameras_file is not None:
            write_cameras(self.cameras_file, records)

    def save(self) -> None:
        """Write the manifest whole (temporary file + rename)."""
        self._last_save = time.monotonic()
        # the frames' own helper: a full or read-only disk is a UserError naming the
        # manifest, and no temporary file is left behind
        with atomic_path(self.path) as temp:
            write_file(temp, (json.dumps(self.data, indent=1, sort_keys=True) + "\n").encode("utf-8"))


def _camera(text: str) -> dict:
    """A camera record the manifest keeps as JSON text (read through the same guard); {}
    where it is unreadable."""
    try:
        record = parse_json(text.encode("utf-8", "surrogatepass"))
    except JsonProblem:
        return {}
    return record if isinstance(record, dict) else {}


def _unaltered(file: Path, entry: dict) -> bool:
    """Whether ``file`` has the size and digest ``entry`` recorded."""
    try:
        return file.stat().st_size == entry.get("bytes") and file_digest(file) == entry.get("sha256")
    except OSError:
        return False


class RecordingSink:
    """Wraps a frame sink: every frame it finishes is recorded in the manifest.

    An image sequence records each frame file as it is written (``frame_names``: index ->
    manifest name); a single-file output, a video or ``-o still.png`` (``file_entry``), is
    recorded once the file is finished, so a cut-off video never counts as done.
    """

    def __init__(self, sink, manifest: Manifest, frame_names: dict | None = None, file_entry: str | None = None):
        self.sink = sink
        self.manifest = manifest
        self.frame_names = frame_names or {}
        self.file_entry = file_entry
        self.needs_linear = sink.needs_linear
        self._first_index: int | None = None
        self.cameras: dict = {}  # frame index -> its camera record, for a single-file output

    def write(self, frame) -> None:
        self.sink.write(frame)
        camera = getattr(frame, "camera", None)
        if self.file_entry is None:
            self.manifest.record(self.frame_names[frame.index], frame.index, self.sink.path_for(frame.index),
                                 self._ids(frame.index), [camera] if camera else None)
            return
        if self._first_index is None:
            self._first_index = frame.index
        if camera:
            self.cameras[frame.index] = camera

    def close(self) -> None:
        self.sink.close()
        if self.file_entry is not None and self._first_index is not None:
            self.manifest.record(self.file_entry, self._first_index, self.sink.path, self._ids(self._first_index),
                                 [self.cameras[i] for i in sorted(self.cameras)])
        self.manifest.finish()

    def _ids(self, index: int) -> Path | None:
        ids_path_for = getattr(self.sink, "ids_path_for", None)
        return ids_path_for(index) if ids_path_for is not None else None

    def abort(self) -> None:
        self.sink.abort()
        try:  # keep what finished; a failure here must not hide why the run stopped
            self.manifest.finish()
        except (OSError, UserError):
            pass

    def describe(self) -> str:
        return self.sink.describe()
