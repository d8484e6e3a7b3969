"""Which of render.indirect's probes to draw again, frame by frame, where the scene moves.

A probe's capture holds the scene as it was when it was drawn. Where something moves, the
probes that see it change most near it: the bake (rendering/passes/indirect.py) draws
again only the probes within TOUCH_CELLS cell diagonals of what moved (the union of its
bounds before and after, widened by that much), at most ``budget`` of them a frame, the
probes that have waited longest first. Changes that light the whole grid (a light of any
kind moving or changing, a light with a `range` too, which could bound what it
touches but does not yet; an emissive colour; the ambient light; the environment) touch
every probe. The other probes, which see what moved only
from further away, are drawn again in frames where nothing changes, so that a scene that
comes to rest ends as a full bake would leave it; then each bounce after the first is
worked out again over every probe, one bounce a frame (a partial update relights only the
probes it draws, with their neighbours' light as they last held it).

The record is the renderer's: a frame that does not follow the one it rendered last (the
first a worker renders of a chunk of frames, a frame the preview jumps to) bakes every
probe, as does the first; so a frame's image depends on the frames since its renderer
last started over, and with several workers on where the chunks begin.

Lag: a probe waits in a queue served oldest first, where each probe stands at most once,
so it is drawn at most ceil(count / budget) frames after a change first touched it; a
scene at rest ends equal to a full bake at most ceil(count / budget) + bounces - 1 frames
after it stopped. No GL here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scenerender.world.probe_grid import ProbeGrid

# How far from what moved a probe is drawn again, in cell diagonals (benchmarks/indirect_cost.py
# measures the error this leaves against a full bake, docs/performance.md).
TOUCH_CELLS = 1.0
NOT_WAITING = -1


@dataclass(frozen=True)
class ObjectState:
    """One object as the probes see it: ``bounds`` (2, 3) float64 world bounds, None where
    hidden; ``key``: bytes that differ where its placement, shape or materials differ."""

    bounds: np.ndarray | None
    key: bytes


@dataclass(frozen=True)
class SceneState:
    """What the bake draws, reduced to what tells one frame from another: ``objects``
    (ObjectState per object) and ``everywhere``, bytes that differ where what lights every
    probe differs (a light, an emissive colour, the ambient light, the environment)."""

    objects: tuple
    everywhere: bytes


def scene_state(frames: list, definitions: list, lights: list, materials: dict, ambient, environment) -> SceneState:
    """The SceneState of one frame: ``frames`` (world.frame.ObjectFrame per object of
    ``definitions``, world RenderObjects), ``lights`` (LightState each), ``materials``
    (id(Material) -> its values, world.frame), the ambient light's (3,) colour and the
    EnvironmentState or None."""
    objects = []
    for frame, definition in zip(frames, definitions):
        shown = frame.visible and frame.count > 0
        values = [materials[id(m)] for m in definition.materials]
        key = fingerprint(float(shown), frame.models if shown else None, frame.skin, frame.morph,
                          *(value for v in values for _, value in sorted(v.items())))
        objects.append(ObjectState(np.asarray(frame.bounds, dtype=np.float64) if shown else None, key))
    everywhere = fingerprint(
        *(value for light in lights for value in (light.color, light.position, light.direction,
                                                  light.cos_inner, light.cos_outer)),
        *(values["emissive"] for _, values in sorted(materials.items())),
        ambient, *((environment.scale, environment.to_image) if environment is not None else (None,)))
    return SceneState(tuple(objects), everywhere)


def fingerprint(*values) -> bytes:
    """The bytes of ``values`` (arrays, numbers or None) as float64, with their shapes."""
    parts = []
    for value in values:
        if value is None:
            parts.append(b"none")
            continue
        array = np.ascontiguousarray(value, dtype=np.float64)
        parts.append(repr(array.shape).encode() + array.tobytes())
    return b"|".join(parts)


@dataclass(frozen=True)
class UpdatePlan:
    """One frame's work: ``probes`` ((n,) int64, ascending) to draw again and relight;
    ``full``: every probe, every bounce, as a bake from nothing; ``settle``: the bounce
    (2..bounces) to work out again over every probe without drawing, or 0."""

    probes: np.ndarray
    full: bool = False
    settle: int = 0

    @property
    def idle(self) -> bool:
        return self.probes.size == 0 and self.settle == 0


class ProbeUpdates:
    """The run's record of what each probe holds (see the module's docstring): made with
    the bake's pass, one for a run; ``plan`` says a frame's work, ``done`` records it once
    the work has been sent. ``recaptured``: how many probes were drawn so far in the run;
    ``last``: (n,) int64, the probes the last frame that was done drew."""

    def __init__(self, grid: ProbeGrid, budget: int, bounces: int):
        self.grid = grid
        self.budget = budget
        self.bounces = bounces
        self.positions = grid.positions()
        self.radius = TOUCH_CELLS * float(np.linalg.norm(grid.spacing))
        self.recaptured = 0
        self.last = np.zeros(0, dtype=np.int64)
        self._state: SceneState | None = None
        self._near = np.full(grid.count, NOT_WAITING, dtype=np.int64)  # frame a change near it was seen
        self._far = np.full(grid.count, NOT_WAITING, dtype=np.int64)   # frame a change further away was seen
        self.frames_done = 0  # plans done (the stamp of a change seen now)
        self._last_index = -1  # the index of the frame last rendered
        self._settled = 0  # the highest bounce worked out over every probe since a probe was last drawn

    def plan(self, state: SceneState, index: int) -> tuple[UpdatePlan, dict]:
        """The work for frame ``index`` (a sub-frame of the last one, the next one, or any
        other: a bake from nothing) of the scene ``state``, and the record ``done`` keeps."""
        if self._state is None or index not in (self._last_index, self._last_index + 1):
            every = np.arange(self.grid.count, dtype=np.int64)
            waiting = np.full(self.grid.count, NOT_WAITING, dtype=np.int64)
            return UpdatePlan(every, full=True), self._record(state, waiting, waiting.copy(), every, self.bounces,
                                                              index)
        near, far = self._near.copy(), self._far.copy()
        touched = self.touched(self._state, state)
        changed = touched is not None
        if changed:
            near[touched & (near == NOT_WAITING)] = self.frames_done
            far[~touched & (far == NOT_WAITING)] = self.frames_done
        near_waiting, far_waiting = (near != NOT_WAITING).any(), (far != NOT_WAITING).any()
        # the probes further away only in a frame where nothing changes
        probes = self._oldest(near if near_waiting or changed else far)
        if probes.size:
            return UpdatePlan(probes), self._record(state, near, far, probes, 1, index)
        if not (changed or near_waiting or far_waiting) and self._settled < self.bounces:
            bounce = self._settled + 1
            return UpdatePlan(probes, settle=bounce), self._record(state, near, far, probes, bounce, index)
        return UpdatePlan(probes), self._record(state, near, far, probes, self._settled, index)

    def done(self, record: dict) -> None:
        """Keep what ``plan`` found, its work sent (an interrupted frame plans it again)."""
        probes = record["probes"]
        record["near"][probes] = NOT_WAITING
        record["far"][probes] = NOT_WAITING
        self._state, self._near, self._far = record["state"], record["near"], record["far"]
        self._settled, self._last_index = record["settled"], record["index"]
        self.frames_done += 1
        self.last = probes
        self.recaptured += int(probes.size)

    def touched(self, before: SceneState, after: SceneState) -> np.ndarray | None:
        """(count,) bool: the probes a change from ``before`` to ``after`` touches; None where
        nothing changed."""
        if before.everywhere != after.everywhere or len(before.objects) != len(after.objects):
            return np.ones(self.grid.count, dtype=bool)
        moved = [(old, new) for old, new in zip(before.objects, after.objects) if old.key != new.key]
        if not moved:
            return None
        found = np.zeros(self.grid.count, dtype=bool)
        for box in (box for pair in moved for box in (pair[0].bounds, pair[1].bounds) if box is not None):
            lo, hi = box[0] - self.radius, box[1] + self.radius
            found |= np.all((self.positions >= lo) & (self.positions <= hi), axis=1)
        return found

    def _oldest(self, waiting: np.ndarray) -> np.ndarray:
        """Up to ``budget`` of the probes ``waiting`` marks, those waiting longest first,
        then in index order; ascending."""
        candidates = np.flatnonzero(waiting != NOT_WAITING)
        order = np.lexsort((candidates, waiting[candidates]))
        return np.sort(candidates[order[:self.budget]])

    def _record(self, state, near, far, probes, settled, index) -> dict:
        return {"state": state, "near": near, "far": far, "probes": probes, "settled": settled, "index": index}

    def catch_up_frames(self) -> int:
        """The most frames a probe waits after a change touched it: ceil(count / budget)."""
        return math.ceil(self.grid.count / self.budget)
