"""Comparing two frames in scene terms, from the object ids rendered with them.

A frame rendered with ``--object-ids`` carries a map of which object each pixel shows (the
object's index in the scene's ``objects`` + 1, 0 for none; one sample at each pixel's
centre) and the objects' names. With both sides' maps, a difference can be named (which
objects the changed pixels belong to) and judged by what happened to each object, which
image statistics alone cannot see (docs/diff-margins.md, "Object ids"):

*Attribution.* Every pixel off by ``CHANGED_LEVELS`` or more on some channel is counted
for the object either side shows there (once when both show the same one).

*Appeared and gone.* An object that covers pixels on one side and none on the other.

*Moved.* Each object present on both sides is registered: the sub-pixel displacement ``d``
that makes the reference, resampled (bilinear) at ``p - d``, best match the output over
the object's pixels and a pixel around them, in least squares (Gauss-Newton from no shift
and from the shift of the object's id centroid, the better of the two). The frame's
common displacement is the median of the objects' displacements weighted by their pixel
counts: a camera moved by a fraction of a pixel moves every object alike, a moved object
only itself. An object's score is the length of its displacement less the common one.
The colour image carries the sub-pixel detail the id map lacks (4x MSAA edges): the id
centroid of a thin or small object jumps by half a pixel under a quarter-pixel camera
move (a row of pixel centres crosses an edge), the registration by a tenth.

*Interior change.* An object's interior is where it shows on both sides with every pixel
within two of it (its 5x5 neighbourhood) showing it too; objects with at least
``MIN_INTERIOR`` interior pixels are judged. Per channel, the output less the reference
moved by the object's own displacement, less the rounding tolerance, is summed: the score
is the signed mean times the share of the change that has its sign, (sum r)^2 / (n sum |r|),
the largest channel. A recolour or a wider highlight changes the interior one way; a
sub-pixel move of a textured surface leaves residuals of both signs, which cancel.
"""
from __future__ import annotations

import dataclasses
import math
from collections import Counter
from dataclasses import dataclass

import numpy as np

from scenerender.compare.metrics import channel_max

CHANGED_LEVELS = 5       # a pixel off by this many levels on some channel counts as changed
INTERIOR_RADIUS = 2      # interior pixels: the object's own within this many pixels, both sides
MIN_INTERIOR = 32        # objects with fewer interior pixels are not judged by their interior
MAX_REGISTERED = 2048    # pixels a registration reads at most (the strongest edges of a large object)
MAX_INTERIOR_READ = 65536  # interior pixels read at most per object (evenly spaced)
WHOLE_FRAME_PIXELS = 640 * 480  # frames up to this size keep their gradients in one table (11 MB)
CONTESTED_RATIO = 10.0   # how much better an object's own pixels must fit their own displacement
CONTESTED_LEVELS = 2.0   # ... and by how many levels rms at least
MIN_OWN_PIXELS = 32      # pixels away from other objects an object needs to be registered by them alone
RECHECK_SHIFT = 0.2      # px from the common displacement past which an object is registered again
BACKGROUND = "background"
SHOWN_OBJECTS = 5        # objects named in a summary line, the most changed first


@dataclass(frozen=True)
class IdMap:
    """One side's object ids: ``ids`` (H, W) uint16 (0: no object), ``names`` id -> name;
    ``behind``: the ids of the nearest opaque surfaces (what shows through a transparent
    one), or None where the render kept no such layer."""

    ids: np.ndarray
    names: dict
    behind: np.ndarray | None = None

    def seen_through(self) -> np.ndarray | None:
        """(H, W) bool: where a transparent surface is nearest and another object shows
        through it; None without the layer behind."""
        if self.behind is None:
            return None
        return (self.behind != self.ids) & (self.behind != 0)

    def layer_behind(self) -> "IdMap":
        return IdMap(self.behind, self.names)

    def label(self, object_id: int, duplicated: set) -> str:
        name = self.names.get(object_id)
        if name is None:
            return f"objects[{object_id - 1}]"
        return f"{name} (objects[{object_id - 1}])" if name in duplicated else name


@dataclass(frozen=True)
class ObjectScore:
    """One object of a frame pair. ``shift`` (pixels, against the frame's common displacement)
    and ``displacement`` ((dy, dx), pixels) are None unless both sides show it; ``interior``
    (levels, signed: + brighter) is None below MIN_INTERIOR interior pixels."""

    name: str
    reference_pixels: int
    output_pixels: int
    changed_pixels: int
    shift: float | None = None
    displacement: tuple | None = None
    interior: float | None = None
    interior_pixels: int = 0

    @property
    def status(self) -> str:
        if self.reference_pixels == 0:
            return "new"
        if self.output_pixels == 0:
            return "gone"
        return "both"

    @property
    def coverage(self) -> int:
        """The pixels it covers on the side that shows more of it."""
        return max(self.reference_pixels, self.output_pixels)

    def to_json(self) -> dict:
        return {"name": self.name, "status": self.status, "reference_pixels": self.reference_pixels,
                "output_pixels": self.output_pixels, "changed_pixels": self.changed_pixels,
                "shift": None if self.shift is None else round(self.shift, 4),
                "displacement": None if self.displacement is None else [round(v, 4) for v in self.displacement],
                "interior": None if self.interior is None else round(self.interior, 4),
                "interior_pixels": self.interior_pixels}


@dataclass(frozen=True)
class ObjectMetrics:
    """The id-based scores of a frame pair (see the module notes). ``objects``: every object
    either side shows, the most changed pixels first; ``background_changed``: changed pixels
    where neither side shows an object. The three scores the rule judges are the largest over
    the objects: ``one_side_pixels`` (coverage of an object only one side shows), ``shift``
    and ``interior`` (its magnitude); ``*_object`` name whose they are ("" for none)."""

    objects: tuple = ()
    background_changed: int = 0
    common_shift: tuple = (0.0, 0.0)
    one_side_pixels: int = 0
    one_side_object: str = ""
    shift: float = 0.0
    shift_object: str = ""
    interior: float = 0.0
    interior_object: str = ""

    def attribution(self, limit: int = SHOWN_OBJECTS) -> str:
        """The changed pixels in scene terms: 'bunny: 482 px; new: thin_pole 111 px; gone:
        lantern_pole 40 px' (new and gone objects with the pixels they cover), the most
        first; '' when nothing changed."""
        parts = []
        for score in self.objects:
            if score.status == "both" and score.changed_pixels == 0:
                continue
            if score.status == "both":
                parts.append((score.changed_pixels, f"{score.name}: {score.changed_pixels} px"))
            else:
                parts.append((score.coverage, f"{score.status}: {score.name} {score.coverage} px"))
        if self.background_changed:
            parts.append((self.background_changed, f"{BACKGROUND}: {self.background_changed} px"))
        parts.sort(key=lambda item: -item[0])
        shown = [text for _, text in parts[:limit]]
        if len(parts) > limit:
            shown.append(f"{len(parts) - limit} more")
        return "; ".join(shown)

    def to_json(self) -> dict:
        return {"one_side_pixels": self.one_side_pixels, "one_side_object": self.one_side_object,
                "shift": round(self.shift, 4), "shift_object": self.shift_object,
                "interior": round(self.interior, 4), "interior_object": self.interior_object,
                "common_shift": [round(v, 4) for v in self.common_shift],
                "background_changed": self.background_changed,
                "attribution": self.attribution(),
                "objects": [score.to_json() for score in self.objects]}


def measure_objects(reference: np.ndarray, output: np.ndarray, reference_ids: IdMap, output_ids: IdMap,
                    tolerance: int = 1, register: bool = True, magnitude: np.ndarray | None = None) -> ObjectMetrics:
    """The id-based scores of two (H, W, 3) uint8 frames of one shape and their id maps
    ((H, W) each). Objects are matched by name (by index where a side has no names), so a
    reordered ``objects`` list still pairs them. Where both sides kept the layer behind
    transparent surfaces and something shows through one, the objects seen through are
    judged on that layer too, named "... (behind glass)". Without ``register`` (a verdict
    already failed by its colours, no report asked) only the attribution and the objects on
    one side are worked out: no moves, no interiors. ``magnitude``: the largest channel
    |difference| (H, W), where the caller has it."""
    pair = _Pair(reference, output, magnitude)
    scores, background, common = _scores(pair, reference_ids, output_ids, tolerance, register=register)
    scores += _seen_through(pair, reference_ids, output_ids, tolerance, register)
    scores.sort(key=lambda s: (-s.changed_pixels, -s.coverage, s.name))
    one_side = max((s for s in scores if s.status != "both"), key=lambda s: s.coverage, default=None)
    moved = max((s for s in scores if s.shift is not None), key=lambda s: s.shift, default=None)
    inside = max((s for s in scores if s.interior is not None), key=lambda s: abs(s.interior), default=None)
    return ObjectMetrics(
        objects=tuple(scores), background_changed=background,
        common_shift=(float(common[0]), float(common[1])),
        one_side_pixels=one_side.coverage if one_side else 0, one_side_object=one_side.name if one_side else "",
        shift=moved.shift if moved else 0.0, shift_object=moved.name if moved and moved.shift > 0 else "",
        interior=abs(inside.interior) if inside else 0.0,
        interior_object=inside.name if inside and inside.interior else "")


BEHIND_GLASS = " (behind glass)"


class _Pair:
    """The two frames, and what both id layers read of them, each worked out once when first
    asked: the pixels off by CHANGED_LEVELS or more (H, W) bool, whether the frames are
    identical, and what registering reads (_Images, 0.15 s at 1080p)."""

    def __init__(self, reference: np.ndarray, output: np.ndarray, magnitude: np.ndarray | None = None):
        self.reference, self.output = reference, output
        self._images = None
        if magnitude is None:
            magnitude = channel_max(np.abs(reference.astype(np.int16) - output.astype(np.int16)))
        self.changed = magnitude >= CHANGED_LEVELS
        self.identical = not self.changed.any() and np.array_equal(reference, output)

    @property
    def images(self) -> "_Images":
        if self._images is None:
            self._images = _Images.of(self.reference, self.output)
        return self._images


def _seen_through(pair: _Pair, reference_ids: IdMap, output_ids: IdMap, tolerance: int, register: bool = True
                  ) -> list:
    """The scores, on the layer behind, of the objects either side shows through a
    transparent surface ([] unless both sides kept that layer and one shows something
    through). Their colour is the glass's blend of them, the same on both sides unless
    something changed, so they are registered and judged like any other object."""
    through = [side.seen_through() for side in (reference_ids, output_ids)]
    if any(mask is None for mask in through) or not (through[0].any() or through[1].any()):
        return []
    behind = reference_ids.layer_behind(), output_ids.layer_behind()
    scores, _, _ = _scores(pair, *behind, tolerance, keep=through, register=register)
    return [dataclasses.replace(score, name=score.name + BEHIND_GLASS) for score in scores]


def _scores(pair: _Pair, reference_ids: IdMap, output_ids: IdMap,
            tolerance: int, keep: list | None = None, register: bool = True) -> tuple[list, int, np.ndarray]:
    """Every object's ``ObjectScore`` (with ``keep``, two (H, W) bool masks: only those
    shown under the mask of one side or the other), the changed pixels of the background,
    and the frame's common displacement (dy, dx)."""
    labels, ref_map, out_map = _unified_labels(reference_ids, output_ids)
    count = len(labels)
    kept = None if keep is None else set(_present(ref_map[keep[0]])) | set(_present(out_map[keep[1]]))
    ref_counts = np.bincount(ref_map.ravel(), minlength=count)
    out_counts = np.bincount(out_map.ravel(), minlength=count)
    changed = pair.changed
    counted = changed if keep is None else changed & (keep[0] | keep[1])  # behind glass: what shows through
    changed_counts = (np.bincount(ref_map[counted], minlength=count)
                      + np.bincount(out_map[counted & (out_map != ref_map)], minlength=count))
    identical = not register or pair.identical  # nothing to register
    weights = {label: int(min(ref_counts[label], out_counts[label])) for label in range(1, count)
               if ref_counts[label] and out_counts[label]}
    images = None if identical else pair.images
    boxes = None if identical else (bounding_boxes(ref_map), bounding_boxes(out_map))
    displacement = {} if identical else _displacements(images, ref_map, out_map, weights, boxes=boxes)
    for label in weights if register else ():  # unregistered objects have no move (None), not no move (0)
        displacement.setdefault(label, np.zeros(2))
    common = _common_shift(displacement, weights)
    # an object found away from the rest is registered again from the common displacement:
    # a thin or small object's fit can stop short of a move of a third of a pixel
    away = [label for label, d in displacement.items() if math.hypot(*(d - common)) > RECHECK_SHIFT]
    if away and not identical:
        displacement.update(_displacements(images, ref_map, out_map, away, common, boxes))
        common = _common_shift(displacement, weights)
    interiors = {} if identical else _interior_changes(images, ref_map, out_map, displacement, tolerance)
    scores = []
    for label in range(1, count):
        if not ref_counts[label] and not out_counts[label] or kept is not None and label not in kept:
            continue
        d = displacement.get(label)
        interior, interior_pixels = interiors.get(label, (None, 0))
        scores.append(ObjectScore(
            labels[label], int(ref_counts[label]), int(out_counts[label]), int(changed_counts[label]),
            shift=None if d is None else float(math.hypot(*(d - common))),
            displacement=None if d is None else (float(d[0]), float(d[1])),
            interior=interior, interior_pixels=interior_pixels))
    return scores, int(changed_counts[0]), common


def picture(reference: np.ndarray, reference_ids: IdMap, output_ids: IdMap, names: list[str]) -> np.ndarray:
    """(H, W, 3) uint8 for a report: the reference dimmed to grey, and the pixels either side
    shows each of ``names`` on (the objects a limit failed) in a colour of its own: a gone
    object where it was, a new one where it is, a moved one at both places."""
    labels, ref_map, out_map = _unified_labels(reference_ids, output_ids)
    by_name = {name: label for label, name in enumerate(labels) if label}
    grey = (reference.mean(axis=2) * 0.35).astype(np.uint8)
    out = np.stack([grey, grey, grey], axis=2)
    for rank, name in enumerate(names):
        label = by_name.get(name)
        if label is not None:
            out[(ref_map == label) | (out_map == label)] = PICTURE_COLOURS[rank % len(PICTURE_COLOURS)]
    return out


PICTURE_COLOURS = ((255, 60, 60), (255, 200, 40), (60, 200, 255), (120, 255, 90), (255, 90, 230), (255, 140, 40))


# -- matching the two sides ------------------------------------------------------------------

def _unified_labels(reference: IdMap, output: IdMap) -> tuple[list, np.ndarray, np.ndarray]:
    """Both sides' ids mapped to one label space: 0 the background, then every object by
    name (a name two objects of one side share is told apart by index) -> (label names,
    reference labels (H, W), output labels (H, W))."""
    labels = [BACKGROUND]
    index = {}
    lookups = []
    for side in (reference, output):
        present = [i for i in _present(side.ids) if i]
        duplicated = {name for name, times in Counter(side.names.values()).items() if times > 1}
        lookup = np.zeros(int(side.ids.max(initial=0)) + 1, np.int32)
        for object_id in present:
            label = side.label(object_id, duplicated)
            if label not in index:
                index[label] = len(labels)
                labels.append(label)
            lookup[object_id] = index[label]
        lookups.append(lookup)
    # the narrowest type that holds every label: the square filters and counts over whole
    # frames that read these maps move a quarter of the bytes in uint8
    narrow = np.uint8 if len(labels) <= 1 << 8 else np.uint16 if len(labels) <= 1 << 16 else np.int32
    ref_map, out_map = (lookup.astype(narrow)[side.ids] for lookup, side in zip(lookups, (reference, output)))
    return labels, ref_map, out_map


def _present(ids: np.ndarray) -> list[int]:
    """The values (ids or labels, non-negative ints) ``ids`` holds, ascending: ``np.unique``
    by a count, without the sort."""
    if not ids.size:
        return []
    return [int(v) for v in np.flatnonzero(np.bincount(ids.ravel()))]


# -- where each object moved ------------------------------------------------------------------

class _Images:
    """What registering reads of a frame pair: the reference, sampled (bilinear) alone or
    after its gradients down and across (one lookup, (N, 9)), the output's pixels, and the
    strongest gradient of each pixel (H, W). Up to WHOLE_FRAME_PIXELS (or as ``whole_frame``
    says) the gradients are worked out over the frame once, in one (H * W, 9) float32 table
    the samples read; a larger frame works them out at the pixels a sample reads (a
    registration reads a few thousand of them; the table is 75 MB of fresh memory at 1080p).
    Both give the same numbers."""

    def __init__(self, reference: np.ndarray, output: np.ndarray, whole_frame: bool | None = None):
        self.height, self.width, self.channels = reference.shape
        self.reference, self.output = reference, output
        self._flat = reference.reshape(-1, self.channels)
        self.strength = _strongest_gradient(reference)
        if whole_frame is None:
            whole_frame = self.height * self.width <= WHOLE_FRAME_PIXELS
        self._table = _gradient_table(reference) if whole_frame else None

    @classmethod
    def of(cls, reference: np.ndarray, output: np.ndarray) -> "_Images":
        return cls(reference, output)

    def _colours(self, index: np.ndarray) -> np.ndarray:
        return self._flat.take(index, axis=0).astype(np.float32)

    def _with_gradients(self, index: np.ndarray) -> np.ndarray:
        """(N, 9) float32 at flat pixel indices: the colour, then the central differences
        down and across (edges repeated: a one-sided half difference at the border)."""
        width = self.width
        y, x = np.divmod(index, width)
        around = np.stack([index, np.where(y > 0, index - width, index),  # itself, up, down, left, right
                           np.where(y < self.height - 1, index + width, index),
                           np.where(x > 0, index - 1, index), np.where(x < width - 1, index + 1, index)], axis=1)
        values = self._colours(around.ravel()).reshape(len(index), 5, self.channels)
        half = np.float32(0.5)
        return np.concatenate([values[:, 0], (values[:, 2] - values[:, 1]) * half,
                               (values[:, 4] - values[:, 3]) * half], axis=1)

    def reference_at(self, ys: np.ndarray, xs: np.ndarray) -> np.ndarray:
        """The reference sampled (bilinear) at float positions -> (N, 3) float32."""
        return _bilinear_by(self._colours, self.height, self.width, ys, xs)

    def sampled(self, ys: np.ndarray, xs: np.ndarray) -> np.ndarray:
        """The reference and its gradients down and across sampled at float positions -> (N, 9)."""
        if self._table is not None:
            return _bilinear_by(self._from_table, self.height, self.width, ys, xs)
        return _bilinear_by(self._with_gradients, self.height, self.width, ys, xs)

    def _from_table(self, index: np.ndarray) -> np.ndarray:
        return self._table.take(index, axis=0)

    def reference_pixels(self, ys: np.ndarray, xs: np.ndarray) -> np.ndarray:
        return self.reference[ys, xs].astype(np.float32)

    def output_at(self, ys: np.ndarray, xs: np.ndarray) -> np.ndarray:
        """The output's pixels at integer positions -> (N, 3) float32."""
        return self.output[ys, xs].astype(np.float32)


def _gradient_table(image: np.ndarray) -> np.ndarray:
    """(H * W, 3 C) float32: what ``_Images._with_gradients`` gives at every pixel, the
    colour then the central differences down and across (edges repeated), worked out over
    the whole frame at once: the same float32 operations on the same values."""
    values = np.pad(image.astype(np.float32), ((1, 1), (1, 1), (0, 0)), mode="edge")
    half = np.float32(0.5)
    down = (values[2:, 1:-1] - values[:-2, 1:-1]) * half
    across = (values[1:-1, 2:] - values[1:-1, :-2]) * half
    return np.concatenate([values[1:-1, 1:-1], down, across], axis=2).reshape(-1, 3 * image.shape[2])


def _strongest_gradient(image: np.ndarray) -> np.ndarray:
    """(H, W) float32: per pixel, the largest |central difference| down or across over the
    channels (edges repeated), from (H, W, C) uint8 in int16: exact, halves of whole levels."""
    values = image.astype(np.int16)
    strongest = np.zeros(image.shape[:2], np.int16)
    for axis in (0, 1):
        size = image.shape[axis]
        if size < 2:
            continue
        def part(start, stop):
            return (slice(None),) * axis + (slice(start, stop),)
        difference = np.empty_like(values)
        np.subtract(values[part(2, None)], values[part(None, -2)], out=difference[part(1, -1)])
        np.subtract(values[part(1, 2)], values[part(0, 1)], out=difference[part(0, 1)])
        np.subtract(values[part(-1, None)], values[part(-2, -1)], out=difference[part(-1, None)])
        np.maximum(strongest, channel_max(np.abs(difference, out=difference)), out=strongest)
    strength = strongest.astype(np.float32)
    strength *= np.float32(0.5)
    return strength


def _displacements(images: _Images, ref_map, out_map, labels, start=None, boxes=None) -> dict:
    """label -> (dy, dx) pixels, for the objects ``labels`` (both sides show them) whose
    pixels differ; ``start``: a displacement to start from besides no shift and the id
    centroids' shift; ``boxes``: both maps' ``bounding_boxes``, where the caller has them."""
    height, width = ref_map.shape
    found = {}
    ref_boxes, out_boxes = boxes or (bounding_boxes(ref_map), bounding_boxes(out_map))
    for label in labels:
        a, b = ref_boxes[label], out_boxes[label]
        y0 = max(min(a[0].start, b[0].start) - 3, 0)
        y1 = min(max(a[0].stop, b[0].stop) + 3, height)
        x0 = max(min(a[1].start, b[1].start) - 3, 0)
        x1 = min(max(a[1].stop, b[1].stop) + 3, width)
        window = (slice(y0, y1), slice(x0, x1))
        ref_labels, out_labels = ref_map[window], out_map[window]
        others = ((ref_labels != label) & (ref_labels > 0)) | ((out_labels != label) & (out_labels > 0))
        found[label] = _register(images, (y0, x0), ref_labels == label, out_labels == label, others, start)
    return found


def bounding_boxes(label_map: np.ndarray) -> dict:
    """label -> (rows, columns) slices of the smallest box holding its pixels, for every
    label > 0 of ``label_map`` (H, W) ints."""
    if label_map.size and 0 <= label_map.min() and label_map.max() < 64:
        return _bounding_boxes_by_bits(label_map)
    ys, xs = np.nonzero(label_map > 0)
    labels = label_map[ys, xs]
    boxes = {}
    if not len(labels):
        return boxes
    count = int(labels.max()) + 1
    height, width = label_map.shape
    present = np.unique(labels)
    extents = []
    for places, side in ((ys, height), (xs, width)):
        if count * side <= 1 << 25:  # which rows (columns) hold each label: a count, not ufunc.at
            held = np.bincount(labels.astype(np.int64) * side + places, minlength=count * side).reshape(count, side) > 0
            low, high = held.argmax(axis=1), side - 1 - held[:, ::-1].argmax(axis=1)
        else:
            low, high = np.full(count, side), np.full(count, -1)
            np.minimum.at(low, labels, places)
            np.maximum.at(high, labels, places)
        extents.append((low, high))
    (low_y, high_y), (low_x, high_x) = extents
    for label in present:
        boxes[int(label)] = (slice(int(low_y[label]), int(high_y[label]) + 1),
                             slice(int(low_x[label]), int(high_x[label]) + 1))
    return boxes


_LABEL_BITS = np.left_shift(np.uint64(1), np.arange(64, dtype=np.uint64))


def _bounding_boxes_by_bits(label_map: np.ndarray) -> dict:
    """``bounding_boxes`` of a map whose labels are under 64 (a frame's objects, nearly
    always): each pixel's label as one bit, or-ed along the rows and along the columns, say
    which rows and columns hold each label: two reductions of the map, no list of its pixels."""
    bits = _LABEL_BITS[label_map]
    rows, cols = np.bitwise_or.reduce(bits, axis=1), np.bitwise_or.reduce(bits, axis=0)
    present = int(np.bitwise_or.reduce(rows))
    boxes = {}
    for label in range(1, 64):
        if not present >> label & 1:
            continue
        held_rows = np.flatnonzero(rows & _LABEL_BITS[label])
        held_cols = np.flatnonzero(cols & _LABEL_BITS[label])
        boxes[label] = (slice(int(held_rows[0]), int(held_rows[-1]) + 1),
                        slice(int(held_cols[0]), int(held_cols[-1]) + 1))
    return boxes


def square_filter(image: np.ndarray, side: int, reduce, pad: str) -> np.ndarray:
    """``reduce`` (np.min or np.max) over the side x side square around each pixel of
    ``image`` (H, W), in two passes (a square's extremum is that of its rows' extrema);
    outside the image is ``pad``: "edge" (the nearest pixel) or "constant" (zero, False)."""
    half = side // 2
    padded = np.pad(image, half, mode=pad)
    pairwise = np.minimum if reduce is np.min else np.maximum  # elementwise over shifted views: no strided reduce
    height, width = image.shape
    rows = padded[0:height]
    for offset in range(1, side):
        rows = pairwise(rows, padded[offset:offset + height])
    out = rows[:, 0:width]
    for offset in range(1, side):
        out = pairwise(out, rows[:, offset:offset + width])
    return out


def _register(images: _Images, origin: tuple, in_ref: np.ndarray, in_out: np.ndarray, others: np.ndarray,
              start=None) -> np.ndarray:
    """The displacement (dy, dx) of an object: ``in_ref`` and ``in_out`` its pixels on each
    side, ``others`` where either side shows another object, all three over a window of the
    frame whose top left pixel is ``origin``.

    Its pixels and those next to them are registered. Where it touches another object the
    edge belongs to whichever is in front, which the ids do not say: a plain wall would
    follow a ball moving in front of it. So the object's pixels away from other objects are
    registered too, from the displacement found, and where they are explained ten times
    better (CONTESTED_RATIO) than by it, theirs is taken: the wall's own silhouette did not
    move. Only with MIN_OWN_PIXELS such pixels, and an improvement of CONTESTED_LEVELS rms
    or more: a few pixels fit anything about as well."""
    region = square_filter(in_ref | in_out, 3, np.max, "constant")
    points, target = _points(images, region, origin)
    if np.array_equal(target, images.reference_pixels(points[0].astype(np.int64), points[1].astype(np.int64))):
        return np.zeros(2)
    extra = [np.asarray(start, np.float64)] if start is not None else []
    starts = [np.zeros(2), *extra]
    moved = _centroid(in_out) - _centroid(in_ref)
    if np.abs(moved).max() > 0.5:
        starts.append(moved)
    found = _best(images, points, target, starts)
    clean = region & ~square_filter(others, 3, np.max, "constant")
    if np.count_nonzero(clean) >= MIN_OWN_PIXELS and not np.array_equal(clean, region):
        own_points, own_target = _points(images, clean, origin)
        own = _best(images, own_points, own_target, [found, *extra])
        with_found = _energy(images, own_points, own_target, found)
        with_own = _energy(images, own_points, own_target, own)
        if with_found > CONTESTED_RATIO * with_own and with_found - with_own > CONTESTED_LEVELS ** 2 * own_target.size:
            return own
    return found


def _points(images: _Images, region: np.ndarray, origin: tuple):
    """The pixels of ``region`` (a window at ``origin``) a registration reads, the
    MAX_REGISTERED strongest edges of a large one -> ((ys, xs) float64 in the frame, their
    output colours)."""
    ys, xs = np.nonzero(region)
    ys, xs = ys + origin[0], xs + origin[1]
    if len(ys) > MAX_REGISTERED:  # the strongest edges carry the displacement
        keep = np.argpartition(-images.strength[ys, xs], MAX_REGISTERED)[:MAX_REGISTERED]
        keep.sort()
        ys, xs = ys[keep], xs[keep]
    return (ys.astype(np.float64), xs.astype(np.float64)), images.output_at(ys, xs)


def _best(images: _Images, points, target, starts) -> np.ndarray:
    """The displacement Gauss-Newton reaches from the best of ``starts``."""
    best = None
    for start in starts:
        d, energy = _gauss_newton(images, points, target, np.array(start, np.float64))
        if best is None or energy < best[1]:
            best = (d, energy)
    return best[0]


def _energy(images: _Images, points, target, d) -> float:
    """The squared residual of ``target`` against the reference moved by ``d``, the best
    offset per channel taken out."""
    residual = target - images.reference_at(points[0] - d[0], points[1] - d[1])
    residual -= residual.mean(axis=0)
    return float(np.square(residual, dtype=np.float64).sum())


def _gauss_newton(images: _Images, points, target, d, iterations: int = 12):
    """Least-squares displacement of the reference from ``d``, with an offset per channel (a
    brightness change is not taken for a move): steps of at most half a pixel, damped by a
    thousandth of the mean curvature (a direction without edges stays put) -> (d, energy)."""
    ys, xs = points
    count, channels = target.shape
    offsets = np.zeros(channels)
    ones = np.repeat(np.eye(channels)[None], count, axis=0).reshape(-1, channels)  # d(sample)/d(offset)
    for _ in range(iterations):
        sampled = images.sampled(ys - d[0], xs - d[1])
        residual = (target - sampled[:, :channels] - offsets).reshape(-1)
        jacobian = np.concatenate([-np.stack([sampled[:, channels:2 * channels].reshape(-1),
                                              sampled[:, 2 * channels:].reshape(-1)], axis=1), ones], axis=1)
        normal = jacobian.T @ jacobian
        damping = np.diag([1e-3 * (normal[0, 0] + normal[1, 1]) + 1e-9] * 2 + [1e-9] * channels)
        step = np.linalg.solve(normal + damping, jacobian.T @ residual)
        move = np.clip(step[:2], -0.5, 0.5)
        d, offsets = d + move, offsets + step[2:]
        if np.abs(move).max() < 1e-3:
            break
    residual = target - images.reference_at(ys - d[0], xs - d[1]) - offsets
    return d, float(np.square(residual, dtype=np.float64).sum())


def _bilinear(image: np.ndarray, ys: np.ndarray, xs: np.ndarray) -> np.ndarray:
    """(H, W, C) sampled at float positions (edges repeated) -> (N, C): the plain form of
    what _Images samples without whole-frame arrays (the tests hold the two to each other)."""
    height, width, channels = image.shape
    flat = image.reshape(-1, channels)
    return _bilinear_by(lambda index: flat.take(index, axis=0), height, width, ys, xs, image.dtype)


def _bilinear_by(pixels, height: int, width: int, ys: np.ndarray, xs: np.ndarray, dtype=np.float32) -> np.ndarray:
    """Bilinear samples at float positions (edges repeated) of an (H, W) image whose pixels
    ``pixels`` gives at flat indices -> (N, C) in ``dtype``."""
    ys = np.clip(ys, 0, height - 1)
    xs = np.clip(xs, 0, width - 1)
    y0 = np.minimum(ys.astype(np.int64), max(height - 2, 0))
    x0 = np.minimum(xs.astype(np.int64), max(width - 2, 0))
    fy, fx = (ys - y0).astype(dtype)[:, None], (xs - x0).astype(dtype)[:, None]
    corner = y0 * width + x0
    down, across = (width if height > 1 else 0), (1 if width > 1 else 0)
    count = len(corner)
    corners = pixels(np.concatenate([corner, corner + across, corner + down, corner + down + across]))
    top_left, top_right = corners[:count], corners[count:2 * count]
    bottom_left, bottom_right = corners[2 * count:3 * count], corners[3 * count:]
    top = top_left + fx * (top_right - top_left)
    bottom = bottom_left + fx * (bottom_right - bottom_left)
    return top + fy * (bottom - top)


def _centroid(mask: np.ndarray) -> np.ndarray:
    ys, xs = np.nonzero(mask)
    return np.array([ys.mean(), xs.mean()])


def _common_shift(displacement: dict, weights: dict) -> np.ndarray:
    """The median of the objects' displacements, each axis apart, weighted by pixel count."""
    labels = [label for label in displacement if label in weights]
    if not labels:
        return np.zeros(2)
    values = np.array([displacement[label] for label in labels])
    counts = np.array([weights[label] for label in labels], np.float64)
    return np.array([_weighted_median(values[:, axis], counts) for axis in range(2)])


def _weighted_median(values: np.ndarray, weights: np.ndarray) -> float:
    order = np.argsort(values, kind="stable")
    cumulative = np.cumsum(weights[order])
    return float(values[order][np.searchsorted(cumulative, cumulative[-1] / 2)])


# -- what changed inside each object ----------------------------------------------------------

def _interior_changes(images: _Images, ref_map, out_map, displacement: dict, tolerance: int) -> dict:
    """label -> (signed score in levels, interior pixels) for objects with MIN_INTERIOR
    interior pixels or more (see the module notes). A large interior is read at an even
    spacing, MAX_INTERIOR_READ pixels at most: its mean needs no more."""
    side = 2 * INTERIOR_RADIUS + 1

    def uniform(labels):
        return square_filter(labels, side, np.min, "edge") == square_filter(labels, side, np.max, "edge")

    inside = uniform(ref_map) & uniform(out_map) & (ref_map == out_map) & (ref_map > 0)
    labels = ref_map[inside]
    sizes = np.bincount(labels)
    judged = [label for label in np.nonzero(sizes >= MIN_INTERIOR)[0] if label > 0]
    if not judged:
        return {}
    ys, xs = np.nonzero(inside)
    found = {}
    for label in judged:
        where = np.flatnonzero(labels == label)
        n = len(where)
        where = where[::-(-n // MAX_INTERIOR_READ)]
        d = displacement.get(label, np.zeros(2))
        moved = images.reference_at(ys[where] - d[0], xs[where] - d[1])
        residual = images.output_at(ys[where], xs[where]) - moved
        residual = np.sign(residual) * np.maximum(np.abs(residual) - tolerance, 0)
        total = residual.sum(axis=0, dtype=np.float64)
        spread = np.abs(residual).sum(axis=0, dtype=np.float64)
        scores = np.where(spread > 0, total * np.abs(total) / np.maximum(len(where) * spread, 1e-12), 0.0)
        strongest = int(np.abs(scores).argmax())
        found[int(label)] = (float(scores[strongest]), n)
    return found
