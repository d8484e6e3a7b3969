"""Where a run writes: what ``-o`` means, and the sink that writes there."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.scene.model.output import VIDEO_FORMATS
from scenerender.sinks import (
    IMAGE_SUFFIX_FORMATS,
    ImageSequenceSink,
    SingleImageSink,
    VideoSink,
    frame_name_pattern,
    output_errors,
    remove_stale_partials,
)
from scenerender.sinks.base import make_folders
from scenerender.sinks.object_ids import BEHIND
from scenerender.sinks.object_ids import FOLDER as OBJECT_IDS_FOLDER


def make_sink(loaded, fmt: str, output: Path, size: tuple, frames: range | None = None,
              object_names: dict | None = None, ids_required: bool = True):
    """The sink ``-o output`` asks for (see ``resolve_output``): a video file, one image
    file, or an image sequence in a folder. Temporary files a killed run left in the
    target folder are removed here, before anything is decided about resuming.
    ``object_names`` (id -> name): keep each frame's object ids too (``--object-ids``),
    which a video cannot: a UserError naming the fix when ``ids_required`` (``--object-ids``
    given), else the video is written without them (its frames are judged by colour)."""
    out = loaded.spec.output
    count = len(frames) if frames is not None else out.frame_count
    with output_errors(output):  # e.g. a name too long to even look up
        target = resolve_output(Path(output), fmt, "format" in out.model_fields_set, count, loaded.name)
    if object_names is not None and target.kind == "video" and ids_required:
        raise UserError(f"--object-ids keeps each frame's ids in a PNG beside the frame, which a {target.fmt.upper()} "
                        "video cannot hold; render an image sequence instead (e.g. -o out/ --format png)",
                        SourceLocation("--object-ids"))
    _create_folder(target.folder)  # a read-only or full disk is reported here, before rendering
    remove_stale_partials(target.folder)
    remove_stale_partials(target.folder / OBJECT_IDS_FOLDER)
    remove_stale_partials(target.folder / OBJECT_IDS_FOLDER / BEHIND)
    if target.kind == "video":
        return VideoSink(target.file, target.fmt, out.fps, size, out.quality)
    scene = loaded.path.name  # objects.json names the scene file, which references carry elsewhere
    if target.kind == "image":
        return SingleImageSink(target.file, target.fmt, out.quality, object_names, scene)
    pattern = frame_name_pattern(out.name, out.frame_count)
    return ImageSequenceSink(target.folder, target.fmt, pattern, out.quality, object_names, scene)


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
