"""What a run renders: the frames ``--frames`` selects, less those the run manifest
vouches for (a resumed or repeated run renders only what is due)."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.run.manifest import Manifest, RecordingSink
from scenerender.sinks.object_ids import ids_path


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


@dataclass
class FramePlan:
    """What a run writes: the sink, its manifest, and the frame indices still to render."""

    sink: object
    manifest: object
    target: Path          # the frame folder, or the video / single image file
    todo: list
    skipped: int
    recording: object     # the sink wrapped so that finished frames enter the manifest


def plan_frames(sink, frames: range, run, scene: str, overwrite: bool, echo, notice=None) -> FramePlan:
    """Decide which of ``frames`` to render: those the manifest does not vouch for.

    Frames an earlier run made from other inputs are deleted first (they are out of date),
    and one line says what changed (to ``echo``). A manifest that cannot be used is one
    warning (to ``notice``, by default ``echo``), and every frame is rendered again.
    """
    target = sink.target
    manifest = Manifest.open(target, sink.is_sequence, run, scene, getattr(sink, "keeps_cameras", True))
    if manifest.unusable is not None:
        (notice or echo)(f"warning: {manifest.unusable}; it is treated as absent and every frame is rendered again")
    _say_what_changed(manifest, run, target, echo)
    if sink.is_sequence:
        _remove_stale_frames(manifest, target)
        names = {i: sink.path_for(i).name for i in frames}
        todo = [i for i in frames if overwrite or not manifest.is_current(names[i], sink.path_for(i), _ids(sink, i))]
        recording = RecordingSink(sink, manifest, frame_names=names)
    else:
        name = f"frames {frames.start}:{frames.stop}:{frames.step}"
        current = not overwrite and manifest.is_current(name, target, _ids(sink, frames.start))
        todo = [] if current else list(frames)
        recording = RecordingSink(sink, manifest, file_entry=name)
    manifest.write_cameras()  # what the output holds now: stale frames' cameras go with them
    return FramePlan(sink, manifest, target, todo, len(frames) - len(todo), recording)


def _ids(sink, index: int) -> Path | None:
    """Where the sink keeps frame ``index``'s object ids, when it keeps them."""
    ids_path_for = getattr(sink, "ids_path_for", None)
    return ids_path_for(index) if ids_path_for is not None else None


def _say_what_changed(manifest, run, target: Path, echo) -> None:
    previous = manifest.previous_run
    if previous is None or previous == run.digest:
        return
    changes = run.changes_since(manifest.previous_inputs)
    listed = ", ".join(changes[:3]) + (f" and {len(changes) - 3} more" if len(changes) > 3 else "")
    echo(f"{display_path(target)}: inputs changed since the last render ({listed or 'unknown'}); "
         "its frames are rendered again")


def _remove_stale_frames(manifest, folder: Path) -> None:
    """Delete frame files an earlier run with other inputs wrote, and their object ids:
    they no longer match the scene."""
    for name in manifest.stale_frames():
        candidate = folder / name
        if candidate.parent == folder:
            for stale in (candidate, ids_path(candidate)):  # the frame, and its ids if a run kept them
                if stale.is_file():
                    stale.unlink()
        manifest.forget(name)
