"""One render run: scene file -> world -> renderer -> sink, with resume and progress.

This is what ``scenerender render`` does, without the command-line parsing.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

from scenerender.api import Scene, load
from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.gpu.context import create_context, gl_info
from scenerender.interrupts import signals_as_exceptions
from scenerender.manifest import Manifest, RecordingSink, fingerprint
from scenerender.progress import Progress
from scenerender.references import check_output, require_apart_before_rendering
from scenerender.rendering.profile import profile_report
from scenerender.rendering.renderer import Renderer
from scenerender.scene.model.output import VIDEO_FORMATS
from scenerender.sinks import (
    IMAGE_SUFFIX_FORMATS, ImageSequenceSink, SingleImageSink, ThreadedSink, VideoSink, frame_name_pattern, output_errors,
    remove_stale_partials,
)
from scenerender.sinks.base import make_folders


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


def parse_frame_range(text: str | None, total: int) -> range:
    """'A:B' or 'A:B:STEP' (end exclusive, parts optional, negatives count from the end,
    exactly like a Python slice), or 'N' for one frame -> the frame indices."""
    if text is None:
        return range(total)
    where = SourceLocation("--frames")
    parts = text.split(":")
    try:
        numbers = [int(p) if p.strip() else None for p in parts]
    except ValueError:
        raise UserError(f"expected A:B or A:B:STEP with whole numbers (end exclusive), got '{text}'", where) from None
    if len(parts) == 1:
        if numbers[0] is None:
            raise UserError("expected a frame number or A:B", where)
        numbers = [numbers[0], numbers[0] + 1 if numbers[0] != -1 else None]
    if len(numbers) > 3:
        raise UserError(f"expected A:B or A:B:STEP, got '{text}'", where)
    if len(numbers) == 3 and numbers[2] is not None and numbers[2] <= 0:
        raise UserError(f"the step must be positive, got '{text}'", where)
    selected = range(total)[slice(*numbers)]
    if len(selected) == 0:
        raise UserError(f"'{text}' selects no frames; the scene has frames 0..{total - 1}", where)
    return selected


def make_sink(loaded, fmt: str, output: Path, size: tuple, frames: range | None = None):
    """The sink ``-o output`` asks for (see ``resolve_output``): a video file, one image
    file, or an image sequence in a folder. Temporary files a killed run left in the
    target folder are removed here, before anything is decided about resuming."""
    out = loaded.spec.output
    count = len(frames) if frames is not None else out.frame_count
    with output_errors(output):  # e.g. a name too long to even look up
        target = resolve_output(Path(output), fmt, "format" in out.model_fields_set, count, loaded.name)
    _create_folder(target.folder)  # a read-only or full disk is reported here, before rendering
    remove_stale_partials(target.folder)
    if target.kind == "video":
        return VideoSink(target.file, target.fmt, out.fps, size, out.quality)
    if target.kind == "image":
        return SingleImageSink(target.file, target.fmt, out.quality)
    pattern = frame_name_pattern(out.name, out.frame_count)
    return ImageSequenceSink(target.folder, target.fmt, pattern, out.quality)


@dataclass(frozen=True)
class OutputTarget:
    """Where a run writes: ``kind`` "video" (``file``), "image" (one ``file``) or
    "sequence" (files in ``folder``); ``folder`` always holds the output."""

    kind: str
    fmt: str
    folder: Path
    file: Path | None = None


def resolve_output(output: Path, fmt: str, fmt_explicit: bool, frame_count: int, scene_name: str) -> OutputTarget:
    """What ``-o output`` means (docs/scene-format.md, "What -o means"): a name
    ending in an image suffix is that one image (one-frame renders only), a video suffix
    that video, anything else a folder (for frames, or for ``<scene>.<fmt>``). The format
    comes from the suffix unless ``fmt_explicit`` (--format or output.format) disagrees.
    Raises UserError (at ``-o``) for every combination that cannot be honoured."""
    suffix = output.suffix.lower()
    named = IMAGE_SUFFIX_FORMATS.get(suffix) or (suffix[1:] if suffix[1:] in VIDEO_FORMATS else None)
    if named is None:
        _require_folder(output)
        if fmt in VIDEO_FORMATS:
            return OutputTarget("video", fmt, output, output / f"{scene_name}.{fmt}")
        return OutputTarget("sequence", fmt, output)
    if fmt_explicit and fmt != named:
        raise UserError(f"{display_path(output)} ends in {output.suffix}, which means {named}, but --format or "
                        f"output.format says {fmt}; make them agree (e.g. add --format {named})", _OUTPUT_OPTION)
    _require_file(output)
    if named in VIDEO_FORMATS:
        return OutputTarget("video", named, output.parent, output)
    if frame_count > 1:
        raise UserError(f"{display_path(output)} names one image but the render has {frame_count} frames; "
                        "give a folder (-o out/) or one frame (--frames N)", _OUTPUT_OPTION)
    return OutputTarget("image", named, output.parent, output)


_OUTPUT_OPTION = SourceLocation("-o")


def _require_folder(path: Path) -> None:
    """``path`` will be a folder: it and its existing ancestors must not be files."""
    if path.exists() and not path.is_dir():
        raise UserError(f"{display_path(path)} is a file, not a folder; frames and videos go into a folder "
                        "(or give a file name ending in .png, .jpg, .tga, .exr, .mp4 or .gif)", _OUTPUT_OPTION)
    _require_folder_ancestors(path)


def _require_file(path: Path) -> None:
    """``path`` will be a file: it must not be a folder, and its parent must be one."""
    if path.is_dir():
        raise UserError(f"{display_path(path)} is a folder, but its name ends in {path.suffix}, so a file is "
                        f"expected; give another file name, or the folder without the suffix", _OUTPUT_OPTION)
    _require_folder_ancestors(path)


def _require_folder_ancestors(path: Path) -> None:
    for parent in path.absolute().parents:
        if parent.exists():
            if not parent.is_dir():
                raise UserError(f"{display_path(parent)} is a file, so nothing can be written under it",
                                _OUTPUT_OPTION)
            return


def missing_folders(output: Path) -> list[Path]:
    """``output`` and those of its parents that do not exist yet, deepest first: what a run
    may create and should take away again if it fails before writing anything."""
    path = Path(output).absolute()
    return [p for p in (path, *path.parents) if not p.exists()]


def remove_if_empty(folders: list[Path]) -> None:
    """Remove the ``folders`` (deepest first) that exist and are empty, so a run that
    failed (no OpenGL context, say) leaves no empty output folder behind; anything with a
    file in it stays."""
    for folder in folders:
        try:
            folder.rmdir()
        except OSError:  # not there, not a folder, or not empty: leave it
            pass


def _create_folder(folder: Path) -> None:
    with output_errors(folder):
        make_folders(folder)


def render_to(scene, output, **options) -> "RenderSummary":
    """Exactly what ``scenerender render`` does: frames or a video into ``output``, with
    resume, the run manifest and atomic files. ``scene`` is a ``scenerender.Scene`` or a
    path (``scenerender.render_to`` is this function).

    Options are the CLI's (see ``RenderOptions``): ``overrides``, ``frames`` ("A:B"),
    ``overwrite``, ``strict``, ``format``, ``check`` (a reference folder),
    ``update_references``, ``quiet`` (default True: no progress here).
    Returns a ``RenderSummary``.
    """
    options.setdefault("quiet", True)
    return run_render(scene, RenderOptions(output=Path(output), **options), echo=lambda text: None)


def run_render(scene, options: RenderOptions, echo=print) -> RenderSummary:
    """Render ``scene`` (a path, or an ``api.Scene`` already loaded) as ``options`` say.

    Frames are reused only when the run manifest shows they were made from the same
    inputs; with ``options.check`` the output is then compared with references.
    Raises UserError on bad input.
    """
    overrides = list(options.overrides) + ([f"output.format={options.format}"] if options.format else [])
    if isinstance(scene, Scene):
        if overrides:
            raise ValueError("overrides and format apply when a scene is loaded: pass them to scenerender.load")
    else:
        scene = load(scene, overrides, strict=options.strict, asset_roots=options.asset_roots,
                     limits=options.limits, on_warning=echo)
    new_folders = missing_folders(Path(options.output))
    try:
        return _run_loaded(scene, overrides, options, echo)
    except BaseException:
        remove_if_empty(new_folders)
        raise


def _run_loaded(scene, overrides: list, options: RenderOptions, echo) -> RenderSummary:
    loaded, world = scene.loaded, scene.world
    spec = loaded.spec
    frames = parse_frame_range(options.frames, spec.output.frame_count)
    sink = make_sink(loaded, spec.output.format, Path(options.output), spec.render.size, frames)
    if options.check is not None:  # before planning, which may delete out-of-date frames
        require_apart_before_rendering(*sink_target(sink), Path(options.check))
    plan = plan_frames(sink, frames, fingerprint(loaded, overrides), loaded.path.as_posix(), options.overwrite, echo)
    if plan.todo and _distributed(options, plan):
        summary = _render_on_workers(scene, plan, options)
    elif plan.todo:
        summary = _render_frames(world, plan, options, world.warnings)
    else:
        summary = RenderSummary(0, len(frames), 0.0, sink.describe())
    echo(summary.line())
    if options.check is not None:
        summary.check = check_output(plan.target, Path(options.check), update=options.update_references, echo=echo)
    return summary


@dataclass
class FramePlan:
    """What a run writes: the sink, its manifest, and the frame indices still to render."""

    sink: object
    manifest: object
    target: Path          # the frame folder, or the video / single image file
    todo: list
    skipped: int
    recording: object     # the sink wrapped so that finished frames enter the manifest


def sink_target(sink) -> tuple[Path, bool]:
    """What ``sink`` writes: (its folder, True) for an image sequence, (the file, False) for
    a video or one image (-o still.png)."""
    is_sequence = not hasattr(sink, "path")
    return Path(sink.folder if is_sequence else sink.path), is_sequence


def plan_frames(sink, frames: range, run, scene: str, overwrite: bool, echo) -> FramePlan:
    """Decide which of ``frames`` to render: those the manifest does not vouch for.

    Frames an earlier run made from other inputs are deleted first (they are out of date),
    and one line says what changed.
    """
    target, is_sequence = sink_target(sink)
    manifest = Manifest.open(target, is_sequence, run, scene)
    _say_what_changed(manifest, run, target, echo)
    if is_sequence:
        _remove_stale_frames(manifest, target)
        names = {i: sink.path_for(i).name for i in frames}
        todo = [i for i in frames if overwrite or not manifest.is_current(names[i], sink.path_for(i))]
        recording = RecordingSink(sink, manifest, frame_names=names)
    else:
        name = f"frames {frames.start}:{frames.stop}:{frames.step}"
        current = not overwrite and manifest.is_current(name, target)
        todo = [] if current else list(frames)
        recording = RecordingSink(sink, manifest, file_entry=name)
    return FramePlan(sink, manifest, target, todo, len(frames) - len(todo), recording)


def _say_what_changed(manifest, run, target: Path, echo) -> None:
    previous = manifest.previous_run
    if previous is None or previous == run.digest:
        return
    changes = run.changes_since(manifest.previous_inputs)
    listed = ", ".join(changes[:3]) + (f" and {len(changes) - 3} more" if len(changes) > 3 else "")
    echo(f"{display_path(target)}: inputs changed since the last render ({listed or 'unknown'}); "
         "its frames are rendered again")


def _remove_stale_frames(manifest, folder: Path) -> None:
    """Delete frame files an earlier run with other inputs wrote: they no longer match the scene."""
    for name in manifest.stale_frames():
        candidate = folder / name
        if candidate.parent == folder and candidate.is_file():
            candidate.unlink()
        manifest.forget(name)


def _distributed(options: RenderOptions, plan: FramePlan) -> bool:
    """Workers pay for their start-up only with several frames (and a single image is one)."""
    return (options.scheduler is not None or options.workers > 1) and len(plan.todo) > 1


@signals_as_exceptions()
def _render_on_workers(scene, plan: FramePlan, options: RenderOptions) -> RenderSummary:
    # imported here: multiprocessing and the pool cost 20-70 ms, which a one-process render
    # (the default) would otherwise pay
    from scenerender.distribute import render_with_workers

    started = time.perf_counter()
    progress = Progress(len(plan.todo), quiet=options.quiet)
    try:
        render_with_workers(scene, options, plan, progress)
    finally:
        progress.close()
    return RenderSummary(len(plan.todo), plan.skipped, time.perf_counter() - started, plan.sink.describe(),
                         list(plan.todo))


@signals_as_exceptions()  # SIGTERM and SIGHUP stop the render as cleanly as Ctrl-C does
def _render_frames(world, plan: FramePlan, options: RenderOptions, warnings) -> RenderSummary:
    started = time.perf_counter()
    todo = plan.todo
    gl = create_context()
    try:
        renderer = Renderer(world, gl, warn=warnings.warn, want_linear=plan.sink.needs_linear,
                            profile=options.profile)
        plan.manifest.start(gl_info(gl))
        writer = ThreadedSink(plan.recording)
        progress = Progress(len(todo), quiet=options.quiet)
        try:
            for index in todo:
                writer.write(renderer.render(index))
                progress.advance()
            writer.close()
        except BaseException:
            writer.abort()
            raise
        finally:
            progress.close()
        summary = RenderSummary(len(todo), plan.skipped, time.perf_counter() - started, plan.sink.describe(),
                                list(todo))
        if options.profile:
            summary.profile = profile_report(renderer, len(todo))
        renderer.release()
    finally:
        gl.release()
    return summary
