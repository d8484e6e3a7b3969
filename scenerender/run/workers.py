"""One scene's frames rendered by several processes: local workers (``--workers N``) or the
workers of a Dask cluster (``--scheduler tcp://host:port``).

The parent plans the run exactly as a single process does (the run manifest decides which
frames are due), cuts the due frames into chunks and hands each chunk to a worker as a
``ChunkTask``. A worker loads the scene once, keeps one GL context and renderer for every
chunk it gets, and writes each frame file whole into the output folder; a video's frames
are staged as PNG files and encoded in order by the parent. Every frame is a pure function
of the scene and its index, so the files are byte-identical to a single-process run.

A chunk may run twice (Dask retries a chunk whose worker died): a frame file already
written by the earlier attempt is kept, never written again. The parent deletes the due
frames' old files before it starts, so an existing file can only be such a fresh one.
"""
from __future__ import annotations

import math
import multiprocessing
import os
import shutil
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

from scenerender.compare.sources import read_image
from scenerender.errors import EnvironmentProblem, SourceLocation, UserError
from scenerender.gpu.gl_context import gl_info
from scenerender.rendering.renderer import FrameResult
from scenerender.run.interrupts import Interrupted, interruptible_chunk, worker_signals
from scenerender.run.loop import render_into
from scenerender.run.session import Renderer, load
from scenerender.sinks import ImageSequenceSink
from scenerender.sinks.object_ids import behind_path, ids_path

CHUNKS_PER_WORKER = 4  # small enough to balance uneven frames, large enough to amortise start-up
STAGED_PATTERN = "frame_{frame:08d}"


@dataclass(frozen=True)
class ChunkTask:
    """What a worker needs to render some frames; plain data, so it pickles to any machine.
    Paths are absolute and must mean the same on every worker (shared storage)."""

    scene: str
    overrides: tuple
    asset_roots: tuple
    limits: object
    folder: str          # where the frame files go
    fmt: str             # png | jpg | tga | exr
    pattern: str         # file stem pattern with {frame}
    quality: int
    indices: tuple
    object_names: tuple | None = None  # (id, name) pairs: keep each frame's object ids too
    scene_key: str = ""               # the scene as objects.json names it
    require_gpu: bool | None = None   # RenderOptions.require_gpu, checked on each worker's own context


@dataclass
class ChunkResult:
    """What a worker did: the GL renderer it used and the files now complete."""

    gl: dict = field(default_factory=dict)
    written: list = field(default_factory=list)   # (index, file name)
    cameras: dict = field(default_factory=dict)   # index -> camera record (world/camera_data.py)
    error: str | None = None                      # a UserError's one-line message


# ---------------------------------------------------------------------------------------
# the worker side

_worker_state: dict = {}  # one loaded scene + renderer per worker process, reused by later chunks


def render_chunk(task: ChunkTask) -> ChunkResult:
    """Render ``task.indices`` into ``task.folder`` (runs in a worker process). A signal
    the parent passes on (LocalWorkers.stop) stops it, nothing partial left."""
    try:
        renderer, gl = _renderer_for(task)
        names = dict(task.object_names) if task.object_names is not None else None
        sink = ImageSequenceSink(Path(task.folder), task.fmt, task.pattern, task.quality, names, task.scene_key)
        due = [i for i in task.indices if not _written(sink, i)]  # else an earlier try wrote it
        cameras = CameraCollector(sink)
        with interruptible_chunk():
            render_into(renderer, cameras, due)
        for index in task.indices:
            if index not in cameras.records:  # written by an earlier try
                cameras.records[index] = renderer.camera_record(index)
        return ChunkResult(gl=gl, written=[(i, sink.path_for(i).name) for i in task.indices], cameras=cameras.records)
    except UserError as exc:
        return ChunkResult(error=str(exc))


class CameraCollector:
    """Passes frames on to ``sink`` and keeps each frame's camera record."""

    def __init__(self, sink):
        self.sink = sink
        self.needs_linear = sink.needs_linear
        self.records: dict = {}

    def write(self, frame) -> None:
        self.sink.write(frame)
        if frame.camera is not None:
            self.records[frame.index] = frame.camera

    def close(self) -> None:
        self.sink.close()

    def abort(self) -> None:
        self.sink.abort()


def _written(sink: ImageSequenceSink, index: int) -> bool:
    """Whether frame ``index`` is in the folder, with its object ids where they are kept."""
    ids = sink.ids_path_for(index)
    return sink.path_for(index).is_file() and (ids is None or ids.is_file())


def _renderer_for(task: ChunkTask):
    object_ids = task.object_names is not None
    key = (task.scene, task.overrides, task.asset_roots, repr(task.limits), task.fmt, object_ids)
    if _worker_state.get("key") != key:
        if "renderer" in _worker_state:
            _worker_state.pop("renderer").close()
        scene = load(task.scene, list(task.overrides), asset_roots=task.asset_roots, limits=task.limits)
        renderer = Renderer(scene, want_linear=task.fmt == "exr", object_ids=object_ids,
                            require_gpu=task.require_gpu)
        _worker_state.update(key=key, renderer=renderer, gl=gl_info(renderer.gl))
    return _worker_state["renderer"], {k: str(v) for k, v in _worker_state["gl"].items()}


# ---------------------------------------------------------------------------------------
# the parent side


def chunk_tasks(base: ChunkTask, todo: list, workers: int) -> list[ChunkTask]:
    """``todo`` cut into about CHUNKS_PER_WORKER chunks per worker, in frame order."""
    size = max(1, math.ceil(len(todo) / (workers * CHUNKS_PER_WORKER)))
    return [ChunkTask(**{**base.__dict__, "indices": tuple(todo[i:i + size])}) for i in range(0, len(todo), size)]


class LocalWorkers:
    """``count`` worker processes on this machine, each with its own GL context."""

    def __init__(self, count: int):
        self.count = count
        # spawn, not fork: a forked child would share the parent's driver state
        self._pool = ProcessPoolExecutor(max_workers=count, mp_context=multiprocessing.get_context("spawn"),
                                         initializer=worker_signals)
        self._not_ours = {child.pid for child in multiprocessing.active_children()}  # made before the pool

    def results(self, tasks: list[ChunkTask]):
        futures = [self._pool.submit(render_chunk, task) for task in tasks]
        for future in as_completed(futures):
            yield future.result()

    def stop(self, signum: int) -> None:
        """Pass the signal that stops this process on to the workers: a busy one stops its
        chunk within a step of its GPU work (rendering.steps), where closing the pool would
        wait for the chunk to end (a prefilter at its largest: minutes); an idle one ignores
        it (run.interrupts.worker_signals)."""
        for child in multiprocessing.active_children():
            if child.pid not in self._not_ours:
                os.kill(child.pid, signum)

    def close(self) -> None:
        self._pool.shutdown(wait=True, cancel_futures=True)


class DaskWorkers:
    """The workers of a Dask distributed cluster. A chunk whose worker dies is retried."""

    RETRIES = 3
    CONNECT_TIMEOUT = "10s"

    def __init__(self, address: str):
        try:
            from distributed import Client
        except ImportError:
            raise EnvironmentProblem("--scheduler needs Dask distributed: pip install 'scenerender[distributed]'") from None
        try:
            self._client = Client(address, timeout=self.CONNECT_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as exc:
            raise UserError(f"cannot reach the Dask scheduler at {address} ({exc})",
                            SourceLocation("--scheduler")) from None
        self.count = max(1, len(self._client.scheduler_info().get("workers", {})))
        self._futures: list = []

    def results(self, tasks: list[ChunkTask]):
        from distributed import as_completed as dask_completed

        self._futures = [self._client.submit(render_chunk, task, retries=self.RETRIES, pure=False)
                         for task in tasks]
        for future in dask_completed(self._futures):  # completion events come from the scheduler
            yield future.result()

    def stop(self, signum: int) -> None:
        """Nothing to signal: the workers are the cluster's; ``close`` cancels the chunks
        (one already running ends on its worker)."""

    def close(self) -> None:
        for future in self._futures:
            future.cancel()
        self._client.close()


def open_workers(count: int, scheduler: str | None):
    return DaskWorkers(scheduler) if scheduler else LocalWorkers(count)


def render_with_workers(scene, options, plan, progress) -> None:
    """Render ``plan.todo`` of ``scene`` (a ``Scene`` loaded from a file) on workers;
    frames enter ``plan.manifest`` as chunks finish, and a video is encoded in frame order
    at the end."""
    sequence = plan.sink.is_sequence
    folder = plan.sink.target if sequence else _staging_folder(plan.sink.target)
    for index in plan.todo:  # old files of due frames are not vouched for: start clean
        if sequence:
            plan.sink.path_for(index).unlink(missing_ok=True)
            ids_path(plan.sink.path_for(index)).unlink(missing_ok=True)
            behind_path(plan.sink.path_for(index)).unlink(missing_ok=True)
    source = scene.source
    if source is None:
        raise UserError("rendering on several workers needs a scene file (workers load it themselves); "
                        "this scene was built in code", SourceLocation("--workers"))
    base = ChunkTask(scene=str(source.path), overrides=tuple(source.overrides),
                     asset_roots=tuple(str(Path(r).resolve()) for r in source.asset_roots), limits=source.limits,
                     folder=str(folder.resolve()), fmt=plan.sink.fmt if sequence else "png",
                     pattern=plan.sink.pattern if sequence else STAGED_PATTERN,
                     quality=plan.sink.quality, indices=(),
                     object_names=_pairs(plan.sink.object_names) if sequence else None,
                     scene_key=plan.sink.scene if sequence else "", require_gpu=options.require_gpu)
    workers = open_workers(options.workers, options.scheduler)
    try:
        started = False
        for result in workers.results(chunk_tasks(base, plan.todo, workers.count)):
            if result.error:
                raise UserError(result.error)
            if not started:
                progress.renderer(result.gl.get("GL_RENDERER", "unknown"))
                plan.manifest.start(result.gl)
                started = True
            for index, name in result.written:
                camera = result.cameras.get(index)
                if sequence:
                    plan.manifest.record(name, index, folder / name, plan.sink.ids_path_for(index),
                                         [camera] if camera else None)
                elif camera:
                    plan.recording.cameras[index] = camera
                progress.advance()
    except Interrupted as stop:
        workers.stop(stop.signum)
        raise
    finally:
        workers.close()
    if sequence:
        plan.manifest.finish()
    else:
        _encode_staged(plan, folder)


def _pairs(names: dict | None) -> tuple | None:
    return None if names is None else tuple(sorted(names.items()))


def _staging_folder(video: Path) -> Path:
    return Path(video).parent / f".{Path(video).name}.frames"


class StagedFrames:
    """Reads the PNG frames workers staged in ``folder`` back as frames, in the renderer's
    shape (``render(index)``), so a video is encoded by the same loop as a render."""

    def __init__(self, folder: Path):
        self.folder = folder

    def render(self, index: int) -> FrameResult:
        return FrameResult(index, 0.0, read_image(self.folder / (STAGED_PATTERN.format(frame=index) + ".png")))


def _encode_staged(plan, folder: Path) -> None:
    """Feed the staged PNG frames to the video sink in frame order, then remove them."""
    try:
        render_into(StagedFrames(folder), plan.recording, plan.todo)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
