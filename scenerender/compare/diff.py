"""Compare a reference with an output: two images, two folders of frames, or two videos.

Folders are matched by file name; videos by frame index (decoded side by side, so memory
stays flat however long they are), also inside folders (frames named
``clip.mp4/frame_0003``). A frame both sides rendered with ``--object-ids`` is also judged
by object (scenerender.compare.objects). Frames only one side has are listed as missing or extra. A frame
whose size differs is a changed frame (the render changed), not bad input; bad
input (a path that does not exist, an unreadable file, a folder against a video, nothing
to compare) is a UserError.
"""
from __future__ import annotations

import dataclasses
import itertools
from pathlib import Path

import numpy as np

from scenerender.compare.ignore import read_ignore
from scenerender.compare.metrics import DiffMaps, FrameMetrics, flip_error, measure, ssim, tile_means, window_sums
from scenerender.compare.objects import CHANGED_LEVELS, IdMap, measure_objects, picture
from scenerender.compare.result import Box, CompareResult, Forgiven, FrameComparison, FrameImages
from scenerender.compare.rule import DEFAULT_RULE, SHIFT_WINDOW, TILE, DiffRule
from scenerender.compare.sources import Side, is_video_name, open_side, video_frames
from scenerender.errors import SourceLocation, UserError, display_path

# Frames that differ whose pictures are kept for the report; past this only numbers are kept
# (a long video that changed everywhere would otherwise fill memory).
MAX_KEPT_IMAGES = 24
# A pass says in words (and the report boxes) each group of this many excused pixels off by
# more than this many levels: the outline of a sphere moved 5 cm, 16 px over 50, up to 115.
FORGIVEN_LEVELS = 50
FORGIVEN_PIXELS = 8
SHOWN_FORGIVEN = 3


def compare_images(name: str, reference: np.ndarray, output: np.ndarray, rule: DiffRule = DEFAULT_RULE,
                   keep_images: bool = True, object_ids: tuple[IdMap | None, IdMap | None] | None = None
                   ) -> FrameComparison:
    """Judge one frame pair, each (H, W, 3) uint8. Pictures are kept (when ``keep_images``)
    for every frame that differs at all, passing or not, so a report can show what a pass
    excused. SSIM and FLIP (slow: 0.6 s and 0.4 s at 1080p and 640x480) only for failing
    frames whose pictures are kept, the ones a person looks at: without a report, neither.
    ``object_ids``: both sides' object ids (compare.objects.IdMap, or None); where both
    sides have them for the frame, the difference is named by object and the rule's object
    limits apply too; else the frame is judged by its colours alone."""
    size = (reference.shape[1], reference.shape[0])
    if reference.shape != output.shape:
        reason = f"size differs: {size[0]}x{size[1]} vs {output.shape[1]}x{output.shape[0]}"
        images = FrameImages(reference, output, None, None) if keep_images else None
        return FrameComparison(name, False, reason, size=size, images=images)
    metrics, maps = measure(reference, output, rule.aa_tolerance, with_flip=False, with_ssim=False)
    objects = None
    colour_only = why_colour_only(object_ids, reference.shape[:2])
    if not colour_only:  # a frame its colours fail needs its objects registered only for a report
        register = keep_images or not rule.failures(metrics)
        objects = measure_objects(reference, output, *object_ids, tolerance=rule.aa_tolerance, register=register,
                                  magnitude=maps.magnitude)
    failures = rule.failures(metrics, objects)
    passed = not failures
    regions = [] if passed else changed_regions(maps)  # a pass outlines what it forgave instead
    forgiven = forgiven_regions(maps) if passed and metrics.max_abs > FORGIVEN_LEVELS else []
    images = None
    offenders = [] if objects is None else list(dict.fromkeys(s.name for kind in rule.offenders(objects) for s in kind))
    if keep_images and (metrics.max_abs > 0 or offenders):
        shown = picture(reference, *object_ids, offenders) if offenders else None
        focus = focus_window(maps, metrics, rule, passed)
        if forgiven:  # a pass's close-up shows the largest difference it forgave
            focus = forgiven[0].box, f"the largest difference this pass excused: {forgiven[0].text()}"
        images = FrameImages(reference, output, heatmap(reference, maps), shift_map(maps), shown, *focus)
    if not passed and images is not None:  # numbers only a report shows, for the frames it shows
        metrics = dataclasses.replace(metrics, ssim=ssim(reference, output), flip=flip_error(reference, output))
    return FrameComparison(name, passed, "; ".join(failures), metrics, regions, size, images, objects,
                           colour_only, forgiven)


def forgiven_regions(maps: DiffMaps) -> list[Forgiven]:
    """What a pass forgave that a reader must see: the groups (the largest first, at most
    SHOWN_FORGIVEN) of FORGIVEN_PIXELS or more excused pixels off by more than
    FORGIVEN_LEVELS in touching TILE x TILE tiles (an outline moved, a thin thing shifted;
    the strong part of an outline is broken where the background matches, tiles join it),
    each with its box and the excused pixels off by CHANGED_LEVELS or more in it. A
    sub-pixel camera move leaves such outlines too: the words and the box say what was
    excused, not that it is wrong."""
    large = maps.excused & (maps.magnitude > FORGIVEN_LEVELS)
    if large.sum() < FORGIVEN_PIXELS:
        return []
    per_tile = tile_means(large.astype(np.float32)) * TILE * TILE
    groups = []
    for cells in _connected_groups(per_tile > 0):
        count = round(sum(per_tile[cell] for cell in cells))
        if count >= FORGIVEN_PIXELS:
            groups.append((count, cells))
    found = []
    for count, cells in sorted(groups, key=lambda group: -group[0])[:SHOWN_FORGIVEN]:
        in_group = np.zeros(per_tile.shape, bool)
        in_group[tuple(np.array(cells).T)] = True
        ys, xs = np.nonzero(large & np.repeat(np.repeat(in_group, TILE, 0), TILE, 1)[:large.shape[0], :large.shape[1]])
        x, y = int(xs.min()), int(ys.min())
        w, h = int(xs.max()) - x + 1, int(ys.max()) - y + 1
        inside = maps.excused[y:y + h, x:x + w] & (maps.magnitude[y:y + h, x:x + w] >= CHANGED_LEVELS)
        found.append(Forgiven((x, y, w, h), int(inside.sum()), int(count), int(maps.magnitude[ys, xs].max())))
    return found


def why_colour_only(object_ids: tuple | None, shape: tuple[int, int]) -> str:
    """Why a frame pair is judged by its colours alone, in words, or "" when both sides
    have object ids of its size (then it is judged by object too)."""
    if object_ids is None:
        return "a video frame carries no object ids"
    reference, output = object_ids
    if reference is None and output is None:
        return "neither side has object ids"
    if reference is None:
        return ("the reference has no object ids (made without them, e.g. by scenerender 0.5.0 or with "
                "--no-object-ids; --update-references adds them)")
    if output is None:
        return "the output has no object ids (rendered with --no-object-ids or as a video)"
    if reference.ids.shape != shape or output.ids.shape != shape:
        return "the object ids are not the size of the frames"
    return ""


def heatmap(reference: np.ndarray, maps: DiffMaps) -> np.ndarray:
    """(H, W, 3) uint8: the reference dimmed to grey, differences excused as edge shifts in
    blue, the rest in red (brighter = larger)."""
    grey = (reference.mean(axis=2) * 0.4).astype(np.uint8)
    out = np.stack([grey, grey, grey], axis=2)
    strength = np.clip(96 + maps.magnitude.astype(np.int32) * 6, 0, 255).astype(np.uint8)
    excused, changed = maps.excused, maps.changed
    out[excused, 0] = 0
    out[excused, 1] = strength[excused] // 3
    out[excused, 2] = strength[excused]
    out[changed, 0] = strength[changed]
    out[changed, 1:] = 0
    return out


def focus_window(maps: DiffMaps, metrics: FrameMetrics, rule: DiffRule, passed: bool
                 ) -> tuple[tuple[int, int, int, int], str]:
    """The window a report shows close up, (x, y, w, h) in pixels, and what it holds in
    words: for a failing frame the worst window of the colour limit that failed (the shift
    window first: the thinnest changes fail only it), for a passing one the window holding
    the most excused pixels (where none is, the largest differences, all within the rounding)."""
    if passed and not maps.excused.any():
        box = _worst_window(maps.magnitude.astype(np.float32), SHIFT_WINDOW)
        return box, f"the largest differences, all within the {rule.aa_tolerance} level(s) of rounding forgiven"
    if passed:
        x, y, w, h = _worst_window(maps.excused.astype(np.float32), SHIFT_WINDOW)
        count = int(maps.excused[y:y + h, x:x + w].sum())
        return (x, y, w, h), f"the most excused pixels: {count} of this {w}x{h} window, blue in the heatmap"
    if metrics.shift_tile > rule.max_shift_tile or not (metrics.worst_tile_aa > rule.max_tile):
        box = _worst_window(maps.residual, SHIFT_WINDOW)
        return box, (f"the worst {SHIFT_WINDOW}x{SHIFT_WINDOW} window after the best shift: "
                     f"{metrics.shift_tile:.2f} levels (limit {rule.max_shift_tile:g})")
    box = _worst_window(maps.unexplained, TILE)
    return box, (f"the worst {TILE}x{TILE} tile outside the 3x3 ranges: {metrics.worst_tile_aa:.2f} levels "
                 f"(limit {rule.max_tile:g})")


def _worst_window(per_pixel: np.ndarray, side: int) -> tuple[int, int, int, int]:
    """(x, y, w, h) of the side x side window whose sum of ``per_pixel`` (H, W) lies farthest
    from 0 (clipped to the image; the first of equals)."""
    sums = np.abs(window_sums(per_pixel, side))
    row, col = np.unravel_index(int(np.argmax(sums)), sums.shape)
    return int(col), int(row), min(side, per_pixel.shape[1]), min(side, per_pixel.shape[0])


def shift_map(maps: DiffMaps) -> np.ndarray:
    """(H, W, 3) uint8: each tile that differs, coloured by the shift that explained it best
    (red: to the right, green: down, both scaled so a quarter pixel is full; grey: no shift),
    black where nothing differs."""
    height, width = maps.magnitude.shape
    differs = tile_means((maps.magnitude > maps.tolerance).astype(np.float32)) > 0
    dy, dx = maps.shifts[..., 0], maps.shifts[..., 1]
    tiles = np.zeros(differs.shape + (3,), np.uint8)
    tiles[..., 0] = np.clip(128 + dx * 508, 0, 255)
    tiles[..., 1] = np.clip(128 + dy * 508, 0, 255)
    tiles[..., 2] = 128
    tiles[~differs] = 0
    return np.repeat(np.repeat(tiles, TILE, axis=0), TILE, axis=1)[:height, :width]


def changed_tiles(maps: DiffMaps) -> np.ndarray:
    """(rows, cols) bool: tiles holding an unexplained difference."""
    return tile_means(maps.changed.astype(np.float32)) > 0


def changed_regions(maps: DiffMaps) -> list[Box]:
    """Boxes (x, y, w, h in pixels) around the groups of touching changed tiles, largest first."""
    tiles = changed_tiles(maps)
    height, width = maps.magnitude.shape
    boxes = []
    for cells in _connected_groups(tiles):
        rows = [r for r, _ in cells]
        cols = [c for _, c in cells]
        x0, y0 = min(cols) * TILE, min(rows) * TILE
        x1, y1 = min((max(cols) + 1) * TILE, width), min((max(rows) + 1) * TILE, height)
        boxes.append((x0, y0, x1 - x0, y1 - y0))
    return sorted(boxes, key=lambda box: -box[2] * box[3])


def _connected_groups(mask: np.ndarray) -> list[list[tuple[int, int]]]:
    """The 8-connected groups of True cells of a small (rows, cols) bool grid."""
    seen = np.zeros_like(mask)
    groups = []
    for start in zip(*np.nonzero(mask)):
        if seen[start]:
            continue
        seen[start] = True
        group, stack = [], [start]
        while stack:
            r, c = stack.pop()
            group.append((int(r), int(c)))
            for dr, dc in itertools.product((-1, 0, 1), repeat=2):
                nr, nc = r + dr, c + dc
                if 0 <= nr < mask.shape[0] and 0 <= nc < mask.shape[1] and mask[nr, nc] and not seen[nr, nc]:
                    seen[nr, nc] = True
                    stack.append((nr, nc))
        groups.append(group)
    return groups


# -- paths ----------------------------------------------------------------------------------

def compare_paths(reference: Path, output: Path, rule: DiffRule = DEFAULT_RULE, pictures: bool = True
                  ) -> CompareResult:
    """Compare two images, two folders of frames or two videos (MP4/GIF) under ``rule``.
    ``pictures``: keep what a report shows (the pictures, SSIM, FLIP); without, only the verdict."""
    ref_side, out_side = open_side(Path(reference)), open_side(Path(output))
    if ref_side.kind != out_side.kind:
        raise UserError(f"cannot compare {_kind_phrase(out_side)} with {_kind_phrase(ref_side)} "
                        f"{display_path(ref_side.path)}", SourceLocation(display_path(out_side.path)))
    result = CompareResult(ref_side, out_side, rule, pictures=pictures,
                           ignore=read_ignore(ref_side.path if ref_side.kind == "folder" else ref_side.path.parent))
    if ref_side.kind == "video":
        _compare_videos(result)
    elif ref_side.kind == "folder":
        _compare_folders(result)
    else:
        _add(result, out_side.path.name, ref_side.load(ref_side.names[0]), out_side.load(out_side.names[0]),
             (ref_side.object_ids(ref_side.names[0]), out_side.object_ids(out_side.names[0])))
    if not result.frames and not result.missing and not result.extra:
        raise UserError("no frames to compare on either side (frames are .png, .jpg, .tga or .exr files, "
                        "videos .mp4 or .gif)",
                        SourceLocation(display_path(ref_side.path)))
    return result


def _kind_phrase(side: Side) -> str:
    return {"folder": "a folder", "video": "a video", "image": "an image"}[side.kind]


def _add(result: CompareResult, name: str, reference: np.ndarray, output: np.ndarray,
         object_ids: tuple | None = None) -> None:
    keep = result.pictures and result.images_kept < MAX_KEPT_IMAGES
    ignored = result.ignore.mask_for(name, reference.shape[:2]) if result.ignore else None
    if ignored is not None and output.shape == reference.shape:
        output, object_ids = _ignoring(ignored, reference, output, object_ids)
    frame = compare_images(name, reference, output, result.rule, keep_images=keep, object_ids=object_ids)
    frame.ignored = 0 if ignored is None else int(ignored.sum())
    if frame.images is not None:
        result.images_kept += 1
    elif not frame.passed and result.pictures:
        result.images_dropped += 1
    result.frames.append(frame)


def _ignoring(ignored: np.ndarray, reference: np.ndarray, output: np.ndarray, object_ids: tuple | None):
    """The output with its ``ignored`` pixels (H, W bool) taken from the reference, its
    object ids too where both sides have them of that size."""
    output = output.copy()
    output[ignored] = reference[ignored]
    if object_ids is not None and all(side is not None and side.ids.shape == ignored.shape for side in object_ids):
        ref_ids, out_ids = object_ids
        ids = out_ids.ids.copy()
        ids[ignored] = ref_ids.ids[ignored]
        behind = None
        if ref_ids.behind is not None and out_ids.behind is not None:
            behind = out_ids.behind.copy()
            behind[ignored] = ref_ids.behind[ignored]
        object_ids = (ref_ids, IdMap(ids, out_ids.names, behind))
    return output, object_ids


def _compare_folders(result: CompareResult) -> None:
    ref_side, out_side = result.reference, result.output
    present = set(out_side.names)
    result.missing = [name for name in ref_side.names if name not in present]
    result.extra = [name for name in out_side.names if name not in set(ref_side.names)]
    for name in ref_side.names:
        if name not in present:
            continue
        if is_video_name(name):
            _compare_videos(result, ref_side.path / name, out_side.path / name, prefix=f"{name}/")
        else:
            _add(result, name, ref_side.load(name), out_side.load(name),
                 (ref_side.object_ids(name), out_side.object_ids(name)))


def _compare_videos(result: CompareResult, reference: Path | None = None, output: Path | None = None,
                    prefix: str = "") -> None:
    """Decode two videos (by default the two sides) in step; frames past the shorter one
    are missing or extra."""
    ref_frames = video_frames(reference or result.reference.path)
    out_frames = video_frames(output or result.output.path)
    for index, (ref, out) in enumerate(itertools.zip_longest(ref_frames, out_frames)):
        name = f"{prefix}frame_{index:04d}"
        if out is None:
            result.missing.append(name)
        elif ref is None:
            result.extra.append(name)
        else:
            _add(result, name, ref, out)
