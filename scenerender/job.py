"""One render run: scene file -> world -> renderer -> sink, with resume and progress.

This is what ``scenerender render`` does, without the command-line parsing.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

from scenerender.errors import SourceLocation, UserError, Warnings
from scenerender.scene.schema import VIDEO_FORMATS


@dataclass
class RenderOptions:
    output: Path
    overrides: list = field(default_factory=list)
    frames: str | None = None        # "A:B", end exclusive
    overwrite: bool = False
    strict: bool = False
    quiet: bool = False
    format: str | None = None


@dataclass
class RenderSummary:
    rendered: int
    skipped: int
    seconds: float
    target: str
    frames: list = field(default_factory=list)  # indices rendered

    @property
    def fps(self) -> float:
        return self.rendered / self.seconds if self.seconds > 0 else 0.0

    def line(self) -> str:
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


def make_sink(loaded, fmt: str, output: Path, size: tuple):
    """The sink for ``fmt``: a video file, or an image sequence in a folder."""
    from scenerender.sinks import ImageSequenceSink, VideoSink, frame_name_pattern

    out = loaded.spec.output
    if fmt in VIDEO_FORMATS:
        target = output if output.suffix.lower() == f".{fmt}" else output / f"{loaded.name}.{fmt}"
        return VideoSink(target, fmt, out.fps, size, out.quality)
    pattern = frame_name_pattern(out.name, out.frame_count)
    return ImageSequenceSink(output, fmt, pattern, out.quality)


def run_render(scene_path, options: RenderOptions, echo=print) -> RenderSummary:
    """Render ``scene_path`` as ``options`` say. Raises UserError on bad input."""
    from scenerender.scene import load_scene
    from scenerender.world.build import build_world

    warnings = Warnings(strict=options.strict, echo=echo)
    overrides = list(options.overrides) + ([f"output.format={options.format}"] if options.format else [])
    loaded = load_scene(scene_path, overrides)
    spec = loaded.spec
    fmt = spec.output.format
    frames = parse_frame_range(options.frames, spec.output.frame_count)
    world = build_world(loaded, warnings)
    sink = make_sink(loaded, fmt, Path(options.output), spec.render.size)
    if fmt in VIDEO_FORMATS:
        todo = list(frames) if options.overwrite or not sink.path.exists() else []
    else:
        todo = [i for i in frames if options.overwrite or not sink.is_complete(i)]
    skipped = len(frames) - len(todo)
    if not todo:
        return RenderSummary(0, skipped, 0.0, sink.describe())
    return _render_frames(world, sink, todo, skipped, options, warnings)


def _render_frames(world, sink, todo: list, skipped: int, options: RenderOptions, warnings) -> RenderSummary:
    from scenerender.gpu.context import create_context
    from scenerender.progress import Progress
    from scenerender.render.renderer import Renderer
    from scenerender.sinks import ThreadedSink

    started = time.perf_counter()
    gl = create_context()
    renderer = Renderer(world, gl, warn=warnings.warn, want_linear=sink.needs_linear)
    writer = ThreadedSink(sink)
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
    return RenderSummary(len(todo), skipped, time.perf_counter() - started, sink.describe(), list(todo))
