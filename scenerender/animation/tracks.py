"""Keyframe tracks and their interpolation, evaluated in float64.

Formulas (see docs/scene-format.md, "Animatable values"): with u = (t - t1) / (t2 - t1),
linear is k1 (1 - u) + k2 u; cosine replaces u by (1 - cos(u pi)) / 2; step holds k1 until
t2; catmull_rom is a cubic Hermite curve through the keys whose tangents are the
time-weighted differences of the neighbouring keys, so uneven key spacing gives no kinks.
"""
from __future__ import annotations

import math

import numpy as np

INTERPOLATIONS = ("step", "linear", "cosine", "catmull_rom")


class Track:
    """A value over time: a constant, or keys with per-segment interpolation.

    times:  (K,) float64, strictly increasing.
    values: (K, D) float64; D = 1 for scalars (evaluation then returns a float).
    modes:  K interpolation names; ``modes[k]`` shapes the segment that starts at key k.
    loop:   time wraps modulo the last key's time.
    kind:   "float", "vector" or "bool" (bool tracks always step and return bool).
    """

    __slots__ = ("times", "values", "modes", "loop", "kind", "_scalar")

    def __init__(self, times, values, modes, loop: bool = False, kind: str = "float"):
        self.times = np.asarray(times, dtype=np.float64).reshape(-1)
        values = np.asarray(values, dtype=np.float64)
        self._scalar = values.ndim == 1
        self.values = values.reshape(len(self.times), -1)
        self.modes = tuple("step" if kind == "bool" else m for m in modes)
        self.loop = bool(loop)
        self.kind = kind
        if len(self.modes) != len(self.times):
            raise ValueError("one interpolation mode per key is needed")
        if len(self.times) > 1 and not np.all(np.diff(self.times) > 0):
            raise ValueError("key times must be strictly increasing")

    @classmethod
    def constant(cls, value, kind: str = "float") -> "Track":
        return cls([0.0], [value], ["step"], kind=kind)

    @property
    def is_constant(self) -> bool:
        """True when the value can never change over time."""
        return len(self.times) == 1 or bool(np.all(self.values == self.values[0]))

    def magnitude_bound(self) -> np.ndarray:
        """(D,) float64: per component, a size no value of the track exceeds at any time.

        Step, linear and cosine segments stay between their two keys. A Catmull-Rom segment
        may overshoot them, by at most half the largest key: its Hermite tangents are at most
        the difference of two keys (twice the largest), and their weights add up to at most
        u (1 - u) <= 1/4.
        """
        largest = np.abs(self.values).max(axis=0)
        if "catmull_rom" in self.modes[:-1]:  # the last key starts no segment
            return largest * 1.5
        return largest

    def __call__(self, t: float):
        """The value at time ``t`` (seconds): float, bool, or a (D,) float64 array."""
        row = self._row(float(t))
        if self.kind == "bool":
            return bool(row[0] >= 0.5)
        return float(row[0]) if self._scalar else row

    def __repr__(self) -> str:
        if len(self.times) == 1:
            return f"Track.constant({self(0.0)!r})"
        return f"Track({len(self.times)} keys, {self.times[0]}..{self.times[-1]} s, loop={self.loop})"

    def _row(self, t: float) -> np.ndarray:
        times = self.times
        if len(times) == 1:
            return self.values[0]
        if self.loop and times[-1] > 0:
            t = math.fmod(t, times[-1])
            if t < 0:
                t += times[-1]
        if t <= times[0]:
            return self.values[0]
        if t >= times[-1]:
            return self.values[-1]
        k = int(np.searchsorted(times, t, side="right")) - 1
        u = (t - times[k]) / (times[k + 1] - times[k])
        return self._segment(k, u)

    def _segment(self, k: int, u: float) -> np.ndarray:
        mode = self.modes[k]
        v1, v2 = self.values[k], self.values[k + 1]
        if mode == "step":
            return v1
        if mode == "linear":
            return v1 * (1.0 - u) + v2 * u
        if mode == "cosine":
            w = (1.0 - math.cos(u * math.pi)) / 2.0
            return v1 * (1.0 - w) + v2 * w
        return self._hermite(k, u)

    def _hermite(self, k: int, u: float) -> np.ndarray:
        """Catmull-Rom through keys k and k+1, tangents scaled to the segment's duration."""
        t, v = self.times, self.values
        dt = t[k + 1] - t[k]
        m1 = self._tangent(k) * dt
        m2 = self._tangent(k + 1) * dt
        u2, u3 = u * u, u * u * u
        h00 = 2 * u3 - 3 * u2 + 1
        h10 = u3 - 2 * u2 + u
        h01 = -2 * u3 + 3 * u2
        h11 = u3 - u2
        return h00 * v[k] + h10 * m1 + h01 * v[k + 1] + h11 * m2

    def _tangent(self, k: int) -> np.ndarray:
        """Velocity at key k: the slope between its neighbours (one-sided at the ends)."""
        t, v = self.times, self.values
        lo, hi = max(k - 1, 0), min(k + 1, len(t) - 1)
        return (v[hi] - v[lo]) / (t[hi] - t[lo])


_SHARED_CONSTANTS: dict = {}


def shared_constant(value, kind: str = "float") -> Track:
    """``Track.constant(value, kind)``, one shared read-only Track per distinct value.

    ``value`` is a float or a tuple of floats. A scene of 50,000 objects holds a few hundred
    thousand constants (every default position, scale, flag and material colour); building
    a Track with its numpy arrays for each dominated loading time. Shared tracks are safe
    because nothing changes a Track after it is built; their arrays are read-only to keep
    it so.
    """
    key = (kind, repr(value))  # repr keeps -0.0 apart from 0.0 (and True from 1.0)
    track = _SHARED_CONSTANTS.get(key)
    if track is None:
        track = Track.constant(value, kind=kind)
        track.times.flags.writeable = False
        track.values.flags.writeable = False
        if len(_SHARED_CONSTANTS) >= 65536:  # many distinct constants: keep memory bounded
            _SHARED_CONSTANTS.clear()
        _SHARED_CONSTANTS[key] = track
    return track


def animated_keys(value, skip: tuple = ()) -> list[str]:
    """The key paths under ``value`` whose Track changes over time, e.g. ["position", "fov"].

    Looks through Tracks, dataclasses, pydantic models, lists, tuples and dicts at any
    depth, so a key added to a model later is found without being listed anywhere.
    ``skip``: field names not to look into at the top level (values that are separate
    inputs, such as an object's materials).
    """
    found = []
    seen = set()
    stack = [("", value, skip)]
    while stack:
        path, item, skipped = stack.pop()
        if isinstance(item, Track):
            if not item.is_constant:
                found.append(path or "(value)")
            continue
        if id(item) in seen:
            continue
        seen.add(id(item))
        stack.extend((f"{path}.{key}" if path and not key.startswith("[") else f"{path}{key}", child, ())
                     for key, child in reversed(_children(item)) if key not in skipped)
    return found


def _children(item) -> list:
    """(key, value) pairs of a container worth looking into; [] for plain values."""
    if isinstance(item, (list, tuple)):
        return [(f"[{i}]", v) for i, v in enumerate(item)]
    if isinstance(item, dict):
        return [(f"[{k!r}]", v) for k, v in item.items()]
    fields = getattr(type(item), "model_fields", None)  # a pydantic model
    if fields is None:
        fields = getattr(type(item), "__dataclass_fields__", None)
    if isinstance(fields, dict):
        return [(name, getattr(item, name, None)) for name in fields]
    return []
