"""The preview's HTTP side: a Starlette app served by uvicorn on 127.0.0.1.

Routes (nothing else answers but 404; no route maps a request path to a file):
  GET /                    the page
  GET /static/NAME         a file of the page, by exact name from a fixed list
  GET /state?since=N       the preview's state as JSON, once its version is past N (long poll)
  GET /frame?frame=I&mode=M&camera=px,py,pz,tx,ty,tz,fov   a preview frame (PNG)
  GET /reference?frame=I   with --check: the reference frame (PNG)
  GET /check?frame=I       with --check: frame I at the scene's own quality judged against it (JSON)
"""
from __future__ import annotations

import asyncio
import contextlib
import json
import threading
from importlib import resources
from pathlib import Path

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route

from scenerender.compare import read_image
from scenerender.errors import UserError
from scenerender.scene.model.render import MODES
from scenerender.preview.scene_info import ReferenceFrames, scene_facts
from scenerender.preview.views import PlacedCamera, PreviewQuality, View, camera_yaml
from scenerender.preview.watcher import SaveThrottle, SceneWatcher
from scenerender.preview.worker import RenderWorker, Superseded, error_lines
from scenerender.sinks.images import encode_png

STATIC_TYPES = {".html": "text/html; charset=utf-8", ".js": "text/javascript; charset=utf-8",
                ".css": "text/css; charset=utf-8", ".svg": "image/svg+xml"}
LONG_POLL_SECONDS = 15.0  # a /state request waits at most this long for news
NO_STORE = {"Cache-Control": "no-store"}


def static_files() -> dict[str, tuple[bytes, str]]:
    """The page's files, read once from the package: name -> (bytes, content type)."""
    folder = resources.files("scenerender.preview") / "static"
    return {item.name: (item.read_bytes(), STATIC_TYPES[Path(item.name).suffix])
            for item in folder.iterdir() if Path(item.name).suffix in STATIC_TYPES}


class PreviewState:
    """What the page polls for, changed from the worker's and the watcher's threads and
    announced to the waiting /state requests on the event loop."""

    def __init__(self):
        self.lock = threading.Lock()
        self.version = 0
        self.generation = 0          # bumped by every save of a watched file
        self.errors: list[str] = []  # the last render's one-line messages ([] once one succeeds)
        self.scene: dict | None = None
        self.path: dict | None = None
        self.closing = False         # the server is stopping: pollers answer at once
        self.loop: asyncio.AbstractEventLoop | None = None
        self._news: asyncio.Event | None = None

    def bind(self, loop: asyncio.AbstractEventLoop) -> None:
        self.loop = loop
        self._news = asyncio.Event()

    def changed(self, **values) -> None:
        """Set ``values`` (attributes) and wake the waiting pollers; any thread."""
        with self.lock:
            for name, value in values.items():
                setattr(self, name, value)
            self.version += 1
        if self.loop is not None:
            self.loop.call_soon_threadsafe(self._announce)

    def _announce(self) -> None:
        news, self._news = self._news, asyncio.Event()
        news.set()

    def next_generation(self) -> int:
        """A save: the generation one on (announced), returned; any thread."""
        with self.lock:
            self.generation += 1
            generation = self.generation
        self.changed()
        return generation

    def close(self) -> None:
        """Answer every waiting poller now (the server is stopping); any thread."""
        self.closing = True
        self.changed()

    async def wait_past(self, version: int, timeout: float) -> None:
        if self.version > version or self.closing:
            return
        try:
            await asyncio.wait_for(self._news.wait(), timeout)
        except asyncio.TimeoutError:
            pass


class Preview:
    """The worker, the watcher and the state of one previewed scene."""

    def __init__(self, scene_path: Path, overrides: list[str], quality: PreviewQuality = PreviewQuality(), *,
                 references: Path | None = None, asset_roots=(), limits=None):
        self.scene_path = Path(scene_path).resolve()
        self.overrides = list(overrides)
        self.quality = quality
        self.asset_roots = tuple(asset_roots)
        self.references = None if references is None else ReferenceFrames(Path(references))
        self.state = PreviewState()
        self.last_view = View()
        self.worker = RenderWorker(self.scene_path, self.overrides, quality, asset_roots=asset_roots,
                                   limits=limits, on_files=self._files_read, on_result=self._rendered)
        self.watcher = SceneWatcher({self.scene_path}, self._saved)
        self.throttle = SaveThrottle(self._new_generation)
        self._summary_generation = -1

    def start(self) -> None:
        self.worker.start()
        self.watcher.start()

    def stop(self) -> None:
        self.watcher.stop()
        self.throttle.stop()
        self.worker.stop()

    # -- from the worker's and the watcher's threads

    def _files_read(self, files) -> None:
        self.watcher.watch(files)

    def _saved(self, paths) -> None:
        self.throttle.saved()

    def _new_generation(self) -> None:
        """The files as saved now are a new generation; the page's view is rendered for it
        at once (coalesced with whatever else is asked meanwhile)."""
        self.worker.submit(self.state.next_generation(), self.last_view)

    def _rendered(self, generation: int, errors: list[str] | None) -> None:
        if generation < self.state.generation and generation != -1:
            return  # an older file's result: the newer one decides what the page shows
        if errors is not None:
            self.state.changed(errors=errors)
            return
        news = {"errors": []}
        if generation != self._summary_generation:
            self._summary_generation = generation
            news.update(self.scene_facts())
        self.state.changed(**news)

    def scene_facts(self) -> dict:
        """The summary and camera path of the scene as saved (its own camera and mode)."""
        try:
            summary, path = scene_facts(self.scene_path, self.overrides, self.asset_roots)
        except UserError:  # the file changed again meanwhile; its own render reports it
            return {}
        summary["check"] = self.references is not None
        summary["preview_size"] = list(self.quality.size_for(tuple(summary["size"])) or summary["size"])
        return {"scene": summary, "path": path}

    # -- on the event loop

    async def frame(self, view: View):
        """(Rendered, None) or (None, error lines), or Superseded raised."""
        self.last_view = view
        future = self.worker.submit(self.state.generation, view)
        try:
            return await asyncio.wrap_future(future), None
        except Superseded:
            raise
        except Exception as exc:
            return None, error_lines(exc)


def create_app(preview: Preview) -> Starlette:
    files = static_files()

    async def page(request: Request) -> Response:
        return _file(files, "index.html")

    async def static(request: Request) -> Response:
        return _file(files, request.path_params["name"])

    async def state(request: Request) -> Response:
        since = _int(request.query_params.get("since"), -1)
        await preview.state.wait_past(since, LONG_POLL_SECONDS)
        return JSONResponse(_state_json(preview), headers=NO_STORE)

    async def frame(request: Request) -> Response:
        try:
            view = _view(request)
        except ValueError as exc:
            return JSONResponse({"errors": [f"bad request: {exc}"]}, status_code=400)
        try:
            rendered, errors = await preview.frame(view)
        except Superseded:
            return JSONResponse({"superseded": True}, status_code=409, headers=NO_STORE)
        if rendered is None:
            return JSONResponse({"errors": errors}, status_code=422, headers=NO_STORE)
        camera = dict(rendered.camera, yaml=camera_yaml(rendered.camera))
        headers = {**NO_STORE, "X-Camera": json.dumps(camera), "X-Generation": str(rendered.generation),
                   "X-Render-Seconds": f"{rendered.seconds:.4f}", "X-Frame": str(view.frame)}
        return Response(rendered.png, media_type="image/png", headers=headers)

    async def reference(request: Request) -> Response:
        path = _reference_path(preview, _int(request.query_params.get("frame"), 0))
        if path is None:
            return Response(status_code=404)
        try:
            pixels = await asyncio.to_thread(read_image, path)
        except UserError as exc:
            return JSONResponse({"errors": [str(exc)]}, status_code=422)
        return Response(encode_png(pixels), media_type="image/png", headers=NO_STORE)

    async def check(request: Request) -> Response:
        index = _int(request.query_params.get("frame"), 0)
        path = _reference_path(preview, index)
        if path is None:
            return JSONResponse({"reference": False, "line": f"no reference frame {index} in {preview.references.root}"
                                 if preview.references else "no --check folder"}, headers=NO_STORE)
        future = preview.worker.submit(preview.state.generation, View(frame=index), full_quality=True)
        try:
            rendered = await asyncio.wrap_future(future)
            verdict = await asyncio.to_thread(ReferenceFrames.verdict, path, rendered.pixels)
        except Superseded:
            return JSONResponse({"superseded": True}, status_code=409, headers=NO_STORE)
        except Exception as exc:
            return JSONResponse({"reference": True, "errors": error_lines(exc)}, status_code=422, headers=NO_STORE)
        return JSONResponse({"reference": True, "frame": index, **verdict}, headers=NO_STORE)

    async def not_found(request: Request, exc: Exception) -> Response:
        return Response("not found", status_code=404, media_type="text/plain")

    @contextlib.asynccontextmanager
    async def lifespan(app):
        preview.state.bind(asyncio.get_running_loop())
        yield

    routes = [Route("/", page), Route("/static/{name}", static), Route("/state", state), Route("/frame", frame),
              Route("/reference", reference), Route("/check", check)]
    return Starlette(routes=routes, lifespan=lifespan, exception_handlers={404: not_found, 405: not_found})


def _file(files: dict, name: str) -> Response:
    if name not in files:
        return Response("not found", status_code=404, media_type="text/plain")
    content, media_type = files[name]
    return Response(content, media_type=media_type, headers=NO_STORE)


def _int(text: str | None, default: int) -> int:
    try:
        return int(text)
    except (TypeError, ValueError):
        return default


def _view(request: Request) -> View:
    """The view a /frame request asks for; ValueError for a malformed one."""
    params = request.query_params
    frame = int(params.get("frame", "0"))
    if frame < 0:
        raise ValueError(f"frame must be >= 0, got {frame}")
    mode = params.get("mode") or None
    if mode is not None and mode not in MODES:
        raise ValueError(f"mode must be one of {', '.join(MODES)}, got {mode!r}")
    camera = params.get("camera")
    return View(frame, mode, PlacedCamera.parse(camera) if camera else None)


def _reference_path(preview: Preview, index: int) -> Path | None:
    if preview.references is None:
        return None
    scene = preview.state.scene or preview.scene_facts().get("scene")  # asked before the first frame was out
    if scene is None:
        return None
    return preview.references.frame_path(index, scene.get("name_pattern"), scene["frame_count"],
                                         preview.worker.gl_renderer)


def _state_json(preview: Preview) -> dict:
    state = preview.state
    with state.lock:
        return {"version": state.version, "generation": state.generation, "errors": state.errors,
                "scene": state.scene, "path": state.path, "renders": preview.worker.renders}
