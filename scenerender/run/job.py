"""One render run: scene file -> world -> renderer -> sink, with resume and progress.

This is what ``scenerender render`` does, without the command-line parsing.
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from pathlib import Path

from scenerender.gpu.gl_context import gl_info
from scenerender.run.collection import startup_done
from scenerender.run.interrupts import signals_as_exceptions
from scenerender.run.loop import render_into
from scenerender.run.manifest import fingerprint
from scenerender.run.output import make_sink, missing_folders, remove_if_empty
from scenerender.run.plan import FramePlan, parse_frame_range, plan_frames
from scenerender.run.progress import Progress
from scenerender.run.session import Renderer, Scene, load
from scenerender.world.id_names import id_names


WHERE_POSSIBLE = "where possible"  # RenderOptions.object_ids: keep them unless the output is a video


@dataclass
class RenderOptions:
    output: Path
    overrides: list = field(default_factory=list)
    frames: str | None = None        # "A:B", end exclusive
    overwrite: bool = False
    strict: bool = False
    quiet: bool = False
    format: str | None = None
    profile: bool = False            # time every pass (GPU-synchronised) and report it
    asset_roots: tuple = ()          # folders besides the scene's own that assets may come from
    limits: object = None            # scenerender.limits.Limits; None: the defaults
    check: Path | None = None        # compare the output with the references in this folder
    workers: int = 1                 # local worker processes, each with its own GL context
    scheduler: str | None = None     # a Dask scheduler address: render on that cluster's workers
    update_references: bool = False  # with check: rewrite the references from this output
    # keep each frame's object ids beside it (sinks/object_ids.py): True (a video is a UserError),
    # False, WHERE_POSSIBLE (not in a video), or None: WHERE_POSSIBLE with ``check``, else False
    object_ids: bool | str | None = None
    require_gpu: bool | None = None  # a software GL renderer is exit 3; None: SCENERENDER_REQUIRE_GPU decides


@dataclass
class RenderSummary:
    rendered: int
    skipped: int
    seconds: float
    target: str
    frames: list = field(default_factory=list)  # indices rendered
    profile: str | None = None  # the per-pass table, when options.profile
    check: object = None        # references.CheckResult, when options.check

    @property
    def fps(self) -> float:
        return self.rendered / self.seconds if self.seconds > 0 else 0.0

    def line(self) -> str:
        if self.rendered == 0:
            return (f"nothing to do: all {self.skipped} frame(s) already up to date in {self.target} "
                    "(--overwrite renders them again)")
        skipped = f", {self.skipped} already there" if self.skipped else ""
        return (f"rendered {self.rendered} frame{'s' if self.rendered != 1 else ''} in {self.seconds:.2f} s "
                f"({self.fps:.1f} fps){skipped} -> {self.target}")


def render_to(scene, output, **options) -> "RenderSummary":
    """Exactly what ``scenerender render`` does: frames or a video into ``output``, with
    resume, the run manifest and atomic files. ``scene`` is a ``scenerender.Scene`` or a
    path (``scenerender.render_to`` is this function).

    Options are the CLI's (see ``RenderOptions``): ``overrides``, ``frames`` ("A:B"),
    ``overwrite``, ``strict``, ``format``, ``check`` (a reference folder),
    ``update_references``, ``object_ids`` (keep each frame's object ids for ``diff``),
    ``require_gpu`` (a software GL renderer is an EnvironmentProblem),
    ``quiet`` (default True: no progress here).
    Returns a ``RenderSummary``.
    """
    options.setdefault("quiet", True)
    return run_render(scene, RenderOptions(output=Path(output), **options), echo=_silent)


def object_names(world) -> dict:
    """id -> name of every object of ``world``: the object's index + 1 (its id in the
    object-id pass) -> its name, or for an unnamed object one made from its mesh, material
    and position (world.id_names), which inserting another object does not change."""
    return id_names(world)


def ids_wanted(options: RenderOptions) -> bool:
    """Whether a run asks for object ids: on request, and by default wherever a verdict is
    asked (``check``), so a change colours alone cannot see is judged by object too."""
    return bool(options.object_ids) if options.object_ids is not None else options.check is not None


def _silent(text: str) -> None:
    """Where ``render_to``'s lines go: the caller reads the summary instead."""


def run_render(scene, options: RenderOptions, echo=print, notice=None) -> RenderSummary:
    """Render ``scene`` (a path, or a ``Scene`` already loaded) as ``options`` say.

    Frames are reused only when the run manifest shows they were made from the same
    inputs; with ``options.check`` the output is then compared with references.
    ``echo`` gets the lines ``-q`` silences (what changed since the last run, the summary
    line, a passing check); ``notice`` the lines it keeps (warnings, a failing check, the
    report's path, references updated); it defaults to ``echo``.
    Raises UserError on bad input.
    """
    notice = echo if notice is None else notice
    overrides = list(options.overrides) + ([f"output.format={options.format}"] if options.format else [])
    if isinstance(scene, Scene):
        if overrides:
            raise ValueError("overrides and format apply when a scene is loaded: pass them to scenerender.load")
    else:
        scene = load(scene, overrides, strict=options.strict, asset_roots=options.asset_roots,
                     limits=options.limits, on_warning=notice)
    new_folders = missing_folders(Path(options.output))
    try:
        return _run_loaded(scene, overrides, options, echo, notice)
    except BaseException:
        remove_if_empty(new_folders)
        raise


def _run_loaded(scene: Scene, overrides: list, options: RenderOptions, echo, notice) -> RenderSummary:
    loaded = scene.loaded
    spec = loaded.spec
    frames = parse_frame_range(options.frames, spec.output.frame_count)
    names = object_names(scene.world) if ids_wanted(options) else None
    sink = make_sink(loaded, spec.output.format, Path(options.output), spec.render.size, frames, names,
                     ids_required=options.object_ids is True)
    keeps_ids = getattr(sink, "object_ids", False)
    if options.check is not None:  # before planning, which may delete out-of-date frames
        _references().require_apart_before_rendering(sink.target, sink.is_sequence, Path(options.check))
    plan = plan_frames(sink, frames, fingerprint(loaded, overrides, keeps_ids), loaded.path.as_posix(),
                       options.overwrite, echo, notice)
    if plan.todo:
        summary = _render_due(scene, plan, dataclasses.replace(options, object_ids=keeps_ids))
    else:
        summary = RenderSummary(0, len(frames), 0.0, sink.describe())
    echo(summary.line())
    if options.check is not None:
        summary.check = _references().check_output(plan.target, Path(options.check),
                                                   update=options.update_references, echo=echo, notice=notice)
    return summary


@signals_as_exceptions()  # SIGTERM and SIGHUP stop the render as cleanly as Ctrl-C does
def _render_due(scene: Scene, plan: FramePlan, options: RenderOptions) -> RenderSummary:
    """Render ``plan.todo`` here or on workers, with progress on stderr."""
    started = time.perf_counter()
    progress = Progress(len(plan.todo), quiet=options.quiet)
    try:
        if _distributed(options, plan):
            startup_done()  # this process waits on the workers: its start-up is over
            _workers().render_with_workers(scene, options, plan, progress)
            profile = None
        else:
            profile = _render_here(scene, plan, options, progress)
    finally:
        progress.close()
    return RenderSummary(len(plan.todo), plan.skipped, time.perf_counter() - started, plan.sink.describe(),
                         list(plan.todo), profile=profile)


# Imported by the runs that use them, not by every render: a one-frame render is mostly
# start-up, and --check brings the image comparison (compare/, its metrics, the HTML report)
# and --workers multiprocessing and Dask; tests/test_startup.py holds the list.
def _references():
    from scenerender.run import references

    return references


def _workers():
    from scenerender.run import workers

    return workers


def _distributed(options: RenderOptions, plan: FramePlan) -> bool:
    """Workers pay for their start-up only with several frames (and a single image is one)."""
    return (options.scheduler is not None or options.workers > 1) and len(plan.todo) > 1


def _render_here(scene: Scene, plan: FramePlan, options: RenderOptions, progress) -> str | None:
    """Render ``plan.todo`` in this process -> the per-pass table with ``options.profile``."""
    with Renderer(scene, want_linear=plan.sink.needs_linear, profile=options.profile,
                  object_ids=options.object_ids, require_gpu=options.require_gpu,
                  report_work=progress.work) as renderer:
        progress.renderer(renderer.gl_renderer)
        plan.manifest.start(gl_info(renderer.gl))
        render_into(renderer, plan.recording, plan.todo, progress)
        return renderer.profile_report(len(plan.todo)) if options.profile else None
