"""The render worker: one thread that owns the preview's only OpenGL context (a moderngl
context belongs to the thread that made it) and renders one view at a time.

Requests coalesce: there is one waiting place for a view and one for a reference check;
a request that arrives while another waits takes its place, and the one it replaced is
answered ``Superseded``. A burst of saves therefore renders at most twice: the render
already under way, then the newest.
"""
from __future__ import annotations

import threading
import time
import traceback
from collections import OrderedDict
from concurrent.futures import Future
from dataclasses import dataclass, field
from pathlib import Path

from scenerender.api import Renderer, load
from scenerender.errors import EnvironmentProblem, SceneErrors, UserError
from scenerender.gpu.gl_context import create_context
from scenerender.preview.views import PreviewQuality, View, camera_from_record
from scenerender.sinks.images import encode_png

CACHED_FRAMES = 24  # frames kept for the timeline to scrub back over


class Superseded(Exception):
    """A newer request took this one's place before it was rendered."""


@dataclass(frozen=True)
class Rendered:
    """A rendered view: ``png`` (the encoded image), ``camera`` (``views.camera_from_record``),
    ``seconds`` (loading the scene when needed, rendering and encoding; float)."""

    generation: int
    view: View
    png: bytes
    camera: dict
    seconds: float
    pixels: object = field(repr=False, default=None)  # (H, W, 3) uint8 for the reference check


@dataclass
class _Job:
    generation: int
    view: View
    full_quality: bool  # the scene's own size and samples (a reference check), else the preview's
    future: Future = field(default_factory=Future)


class RenderWorker:
    """Renders views of ``scene_path`` on its own thread.

    overrides:         the user's ``--set`` strings (``--size`` and ``--samples`` among them)
    quality:           how preview frames are lowered; reference checks render at the scene's own
    on_files:          called on the worker thread with the set of files (Path) a loaded scene read
    on_result:         called on the worker thread with (generation, error lines or None) after each
                       preview frame (generation -1: no GL context, nothing can render)
    """

    def __init__(self, scene_path: Path, overrides: list[str], quality: PreviewQuality, *,
                 asset_roots=(), limits=None, on_files=None, on_result=None):
        self.scene_path = Path(scene_path)
        self.overrides = list(overrides)
        self.quality = quality
        self.asset_roots = tuple(asset_roots)
        self.limits = limits
        self.on_files = on_files or (lambda files: None)
        self.on_result = on_result or (lambda generation, errors: None)
        self.renders = 0                 # views rendered so far (the tests count them)
        self.gl_renderer = None          # the GL renderer's name, once the context exists
        self._lock = threading.Condition()
        self._waiting = {False: None, True: None}  # full_quality -> the job waiting for the thread
        self._running: _Job | None = None          # the job the thread is rendering
        self._cache: OrderedDict = OrderedDict()   # (generation, view, full_quality) -> Rendered
        self._loaded = None                        # (generation, scene key, full_quality, Scene, Renderer)
        self._stopping = False
        self._failure: Exception | None = None      # why no frame can be rendered at all
        self._thread = threading.Thread(target=self._run, name="scenerender-preview-render", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        """Answer every waiting request Superseded, let the render under way finish, free
        the context and end the thread."""
        with self._lock:
            self._stopping = True
            for full_quality, job in self._waiting.items():
                if job is not None:
                    job.future.set_exception(Superseded())
                self._waiting[full_quality] = None
            self._lock.notify_all()
        if self._thread.is_alive():
            self._thread.join()

    def cached(self, generation: int, view: View, full_quality: bool = False) -> Rendered | None:
        with self._lock:
            return self._cache.get((generation, view, full_quality))

    def submit(self, generation: int, view: View, full_quality: bool = False) -> Future:
        """A Future for ``view`` of the scene as it was at ``generation``: a ``Rendered``,
        or the scene's ``UserError``, an ``EnvironmentProblem``, ``Superseded``."""
        with self._lock:
            done = self._cache.get((generation, view, full_quality))
            waiting = self._waiting[full_quality]
            if done is not None or self._stopping:
                future = Future()
                if done is not None:
                    future.set_result(done)
                else:  # stopping, or no GL context could be made (the reason, for every request)
                    future.set_exception(self._failure or Superseded())
                return future
            for job in (self._running, waiting):  # the same view asked again joins the render of it
                if job is not None and (job.generation, job.view, job.full_quality) == (generation, view, full_quality):
                    return job.future
            if waiting is not None:
                waiting.future.set_exception(Superseded())
            job = _Job(generation, view, full_quality)
            self._waiting[full_quality] = job
            self._lock.notify_all()
            return job.future

    # -- on the worker thread

    def _run(self) -> None:
        gl = None
        try:
            gl = create_context()
            self.gl_renderer = gl.info.get("GL_RENDERER")
            while True:
                job = self._next_job()
                if job is None:
                    return
                self._do(job, gl)
        except EnvironmentProblem as exc:  # no context at all: every request gets the reason
            self._fail_all(exc)
        finally:
            self._unload()
            if gl is not None:
                gl.release()

    def _next_job(self) -> _Job | None:
        with self._lock:
            while not self._stopping and self._waiting[False] is None and self._waiting[True] is None:
                self._lock.wait()
            if self._stopping:
                return None
            full_quality = self._waiting[False] is None  # the page's own view first
            job, self._waiting[full_quality] = self._waiting[full_quality], None
            self._running = job
            return job

    def _do(self, job: _Job, gl) -> None:
        started = time.perf_counter()
        try:
            renderer = self._renderer_for(job, gl)
            frame = renderer.render(job.view.frame)
            hint = _target_at(renderer.scene, frame.time)
            camera = camera_from_record(renderer.camera_record(job.view.frame), hint)
            result = Rendered(job.generation, job.view, encode_png(frame.pixels), camera,
                              time.perf_counter() - started, frame.pixels)
        except Exception as exc:  # a render that fails is shown, never the end of the server
            error = exc if isinstance(exc, (UserError, EnvironmentProblem)) else _internal(exc)
            with self._lock:
                self._running = None
            if not job.full_quality:  # a reference check answers its own request alone
                self.on_result(job.generation, error_lines(error))
            job.future.set_exception(error)
            return
        with self._lock:
            self.renders += 0 if job.full_quality else 1
            self._cache[(job.generation, job.view, job.full_quality)] = result
            while len(self._cache) > CACHED_FRAMES:
                self._cache.popitem(last=False)
            self._running = None
        job.future.set_result(result)  # the page's request first: the state's news can wait
        if not job.full_quality:
            self.on_result(job.generation, None)

    def _renderer_for(self, job: _Job, gl) -> Renderer:
        """The loaded scene's renderer for the job's scene key; loads the scene again (and
        frees the last renderer) when the file's generation or the view's overrides changed."""
        key = (job.generation, job.view.scene_key(), job.full_quality)
        if self._loaded is not None and self._loaded[0] == key:
            return self._loaded[1]
        self._unload()
        scene = load(self.scene_path, self.overrides + job.view.overrides(), asset_roots=self.asset_roots,
                     limits=self.limits)
        self.on_files({self.scene_path.resolve(), *scene.loaded.assets.files_read})
        if job.full_quality:
            renderer = Renderer(scene, gl=gl)
        else:
            renderer = Renderer(scene, size=self.quality.size_for(scene.size), samples=self.quality.samples, gl=gl)
        self._loaded = (key, renderer)
        return renderer

    def _unload(self) -> None:
        if self._loaded is not None:
            self._loaded[1].close()
            self._loaded = None

    def _fail_all(self, exc: Exception) -> None:
        self.on_result(-1, error_lines(exc))
        with self._lock:
            self._stopping = True
            self._failure = exc
            for full_quality, job in self._waiting.items():
                if job is not None:
                    job.future.set_exception(exc)
                self._waiting[full_quality] = None


def _target_at(scene, time_s: float):
    """The scene's own camera target at ``time_s`` ((3,) float64), or None where it has none."""
    camera = scene.loaded.spec.camera
    if camera is None or camera.target is None:
        return None
    return camera.target(time_s)


def _internal(exc: Exception) -> Exception:
    traceback.print_exception(exc)  # a bug: the terminal keeps the traceback, the page the line
    return RuntimeError(f"internal error: {type(exc).__name__}: {exc} (this is a bug in scenerender)")


def error_lines(exc: Exception) -> list[str]:
    """The one-line messages the command line prints for ``exc``, each naming file and
    line where the problem has one."""
    if isinstance(exc, SceneErrors):
        return exc.lines()
    return [str(exc)]
