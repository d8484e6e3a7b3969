"""A glTF file's animations, read from its JSON (trimesh does not read them), and their
node transforms at any time.

A clip (``animations[i]``) holds channels; a channel drives one node's ``translation``,
``rotation`` (a unit quaternion x, y, z, w) or ``scale`` through a sampler: key times
(``input``), key values (``output``) and an interpolation. The glTF 2.0 specification's
Appendix C gives the formulas; with t_k <= t < t_k+1, td = t_k+1 - t_k and
u = (t - t_k) / td:

- ``STEP``: v_k.
- ``LINEAR``: (1 - u) v_k + u v_k+1; for rotations the spherical interpolation
  slerp(q_k, q_k+1, u) = sin((1 - u) a) / sin(a) q_k + sin(u a) / sin(a) q_k+1 with
  cos(a) = |q_k . q_k+1|, q_k+1 negated where the dot is negative (the shorter way round).
- ``CUBICSPLINE``: each key stores an in-tangent a_k, a value v_k and an out-tangent b_k;
  (2u^3 - 3u^2 + 1) v_k + td (u^3 - 2u^2 + u) b_k + (-2u^3 + 3u^2) v_k+1 + td (u^3 - u^2) a_k+1,
  and a rotation so made is normalised.

Before the first key a channel holds its first value, after the last its last one. Morph
target ``weights`` channels are read with the rest, and skipped where transforms are asked for.

Key values are checked as they are read: every time and value finite, every rotation key
a quaternion of non-zero length (the tangents of a CUBICSPLINE rotation may be zero). A key
that is not is a GltfProblem naming the clip, the channel and the key's index, so neither
``validate`` nor ``render`` goes on with a NaN that would surface as a broken transform.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scenerender.mesh.gltf import GltfProblem, GltfSource
from scenerender.mesh.gltf_geometry import accessor_reader

INTERPOLATIONS = ("STEP", "LINEAR", "CUBICSPLINE")
_WIDTH = {"translation": 3, "rotation": 4, "scale": 3}
# below this angle between two rotations slerp's sin(a) loses its digits: interpolate linearly
_SLERP_MIN_ANGLE = 1e-6


@dataclass(frozen=True)
class Channel:
    """One node property over time. times (K,) float64 increasing; values (K, D), or
    (3 K, D) for CUBICSPLINE (in-tangent, value, out-tangent per key)."""

    node: int
    path: str
    interpolation: str
    times: np.ndarray
    values: np.ndarray

    def __call__(self, t: float) -> np.ndarray:
        """The value at clip time ``t`` (seconds), float64."""
        times = self.times
        cubic = self.interpolation == "CUBICSPLINE"
        keys = self.values[1::3] if cubic else self.values
        if len(times) == 1 or t <= times[0]:
            return keys[0].copy()
        if t >= times[-1]:
            return keys[-1].copy()
        k = int(np.searchsorted(times, t, side="right")) - 1
        td = times[k + 1] - times[k]
        u = (t - times[k]) / td
        if self.interpolation == "STEP":
            return keys[k].copy()
        if cubic:
            value = hermite(keys[k], self.values[3 * k + 2], keys[k + 1], self.values[3 * (k + 1)], td, u)
            return _unit(value) if self.path == "rotation" else value
        if self.path == "rotation":
            return slerp(keys[k], keys[k + 1], u)
        return keys[k] * (1.0 - u) + keys[k + 1] * u

    def magnitude_bound(self) -> np.ndarray:
        """(D,) float64: no value of the channel, at any time, is larger in size. STEP and
        LINEAR stay between their keys; a cubic spline's tangent terms add at most
        td * 4/27 * (|a| + |b|) (the largest size of u^3 - 2u^2 + u and u^3 - u^2 on [0, 1])."""
        cubic = self.interpolation == "CUBICSPLINE"
        keys = np.abs(self.values[1::3] if cubic else self.values)
        bound = keys.max(axis=0)
        if cubic and len(self.times) > 1:
            tangents = np.abs(self.values[0::3]).max(axis=0) + np.abs(self.values[2::3]).max(axis=0)
            bound = bound + float(np.diff(self.times).max()) * 4.0 / 27.0 * tangents
        return bound


def hermite(v0: np.ndarray, out_tangent: np.ndarray, v1: np.ndarray, in_tangent: np.ndarray, td: float,
            u: float) -> np.ndarray:
    """glTF's cubic spline between two keys (Appendix C)."""
    u2, u3 = u * u, u * u * u
    return ((2 * u3 - 3 * u2 + 1) * v0 + td * (u3 - 2 * u2 + u) * out_tangent
            + (-2 * u3 + 3 * u2) * v1 + td * (u3 - u2) * in_tangent)


def slerp(q0: np.ndarray, q1: np.ndarray, u: float) -> np.ndarray:
    """Spherical linear interpolation of unit quaternions, the shorter way round."""
    dot = float(np.dot(q0, q1))
    if dot < 0.0:
        q1, dot = -q1, -dot
    angle = math.acos(min(dot, 1.0))
    if angle < _SLERP_MIN_ANGLE:
        return _unit(q0 * (1.0 - u) + q1 * u)
    s = math.sin(angle)
    return (math.sin((1.0 - u) * angle) / s) * q0 + (math.sin(u * angle) / s) * q1


def _unit(q: np.ndarray) -> np.ndarray:
    norm = float(np.linalg.norm(q))
    return q / norm if norm > 0.0 else np.array([0.0, 0.0, 0.0, 1.0])


@dataclass(frozen=True)
class Clip:
    """One of the file's animations: its index, its name (or None) and its channels."""

    index: int
    name: str | None
    channels: tuple

    @property
    def duration(self) -> float:
        """The last key time of any channel, seconds."""
        return max((float(c.times[-1]) for c in self.channels if len(c.times)), default=0.0)

    @property
    def label(self) -> str:
        return f"'{self.name}'" if self.name else f"#{self.index}"

    def node_values(self, t: float) -> dict:
        """node index -> {path: value} of the transform channels at clip time ``t``."""
        values: dict = {}
        for channel in self.channels:
            if channel.path in _WIDTH:
                values.setdefault(channel.node, {})[channel.path] = channel(t)
        return values


def read_clips(source: GltfSource, read_file=None) -> list[Clip]:
    """The clips of the glTF file ``source`` (mesh.gltf.split_glb). ``read_file(uri)`` reads an
    external buffer. Raises GltfProblem where the animations are malformed."""
    header, binary = source
    animations = header.get("animations", []) or []
    if not animations:
        return []
    read = accessor_reader(header, binary, read_file)
    node_count = len(header.get("nodes", []))
    return [_clip(i, animation, read, node_count) for i, animation in enumerate(animations)]


def _clip(index: int, animation: dict, read, node_count: int) -> Clip:
    name = animation.get("name")
    where = f"animations[{index}]" + (f" ('{name}')" if name else "")
    samplers = animation.get("samplers", [])
    channels = []
    for c, channel in enumerate(animation.get("channels", [])):
        target = channel.get("target", {})
        node, path = target.get("node"), target.get("path")
        if node is None:
            continue  # a channel with no node targets something an extension names: ignored
        if not (isinstance(node, int) and 0 <= node < node_count):
            raise GltfProblem(f"{where}.channels[{c}] targets node {node!r}, the file has {node_count}")
        if path not in (*_WIDTH, "weights"):
            raise GltfProblem(f"{where}.channels[{c}] has the unknown path {path!r}")
        sampler_index = channel.get("sampler")
        if not (isinstance(sampler_index, int) and 0 <= sampler_index < len(samplers)):
            raise GltfProblem(f"{where}.channels[{c}] names sampler {sampler_index!r}, the clip has {len(samplers)}")
        channels.append(_channel(samplers[sampler_index], node, path, read,
                                 f"{where}.channels[{c}] ({path} of node {node}, samplers[{sampler_index}])"))
    return Clip(index, name, tuple(channels))


def _channel(sampler: dict, node: int, path: str, read, where: str) -> Channel:
    interpolation = sampler.get("interpolation", "LINEAR")
    if interpolation not in INTERPOLATIONS:
        raise GltfProblem(f"{where} has the unknown interpolation {interpolation!r}")
    times = read(sampler.get("input"), 1).reshape(-1).astype(np.float64)
    values = read(sampler.get("output"), _WIDTH.get(path)).astype(np.float64)
    if path == "weights":  # one scalar per target per key
        values = values.reshape(len(times) * (3 if interpolation == "CUBICSPLINE" else 1), -1)
    _check_finite_times(times, where)
    if not len(times) or (len(times) > 1 and not np.all(np.diff(times) > 0)):
        raise GltfProblem(f"{where}: key times must be there and strictly increasing")
    expected = len(times) * (3 if interpolation == "CUBICSPLINE" else 1)
    if len(values) != expected:
        raise GltfProblem(f"{where}: {len(values)} values for {len(times)} {interpolation} keys ({expected} expected)")
    _check_values(values, path, interpolation == "CUBICSPLINE", where)
    return Channel(node, path, interpolation, times, values)


def _check_finite_times(times: np.ndarray, where: str) -> None:
    """times (K,) float64: each finite, else a GltfProblem naming the first key that is not."""
    bad = np.flatnonzero(~np.isfinite(times))
    if bad.size:
        raise GltfProblem(f"{where}: key {bad[0]} has the time {times[bad[0]]}, not a finite number")


def _check_values(values: np.ndarray, path: str, cubic: bool, where: str) -> None:
    """values (K, D), or (3 K, D) for a cubic spline: each finite, and each rotation key
    (not its tangents) a quaternion of non-zero length; a GltfProblem names the key."""
    per_key = 3 if cubic else 1
    bad = np.flatnonzero(~np.isfinite(values).all(axis=1))
    if bad.size:
        row = int(bad[0])
        part = ("in-tangent", "value", "out-tangent")[row % 3] + " of " if cubic else ""
        raise GltfProblem(f"{where}: the {part}key {row // per_key} holds {_shown(values[row])}, "
                          "not finite numbers")
    if path == "rotation":
        keys = values[1::3] if cubic else values
        zero = np.flatnonzero(~(np.linalg.norm(keys, axis=1) > 0.0))
        if zero.size:
            raise GltfProblem(f"{where}: key {zero[0]} holds {_shown(keys[zero[0]])}, a quaternion of length 0, "
                              "not a rotation")


def _shown(row: np.ndarray) -> str:
    return "[" + ", ".join(f"{float(v):g}" for v in row) + "]"


def clip_time(t: float, duration: float, speed: float, offset: float, loop: bool) -> float:
    """Scene time ``t`` -> the clip's own time: (t - offset) * speed, wrapped into
    [0, duration) when ``loop``, else held at the ends."""
    local = (t - offset) * speed
    if loop and duration > 0.0:
        local = math.fmod(local, duration)
        return local + duration if local < 0.0 else local
    return min(max(local, 0.0), duration)


@dataclass(frozen=True)
class Skin:
    """``skins[i]``: the joint nodes and each joint's inverse bind matrix (J, 4, 4) float64
    (identity where the file gives none). A vertex with joints j and weights w is placed at
    sum_k w_k W(j_k) IBM(j_k) v, W the joint node's world transform."""

    joints: tuple
    inverse_binds: np.ndarray


def read_skins(source: GltfSource, read_file=None) -> list[Skin]:
    """The skins of the glTF file ``source`` (mesh.gltf.split_glb). Raises GltfProblem where one is malformed."""
    header, binary = source
    skins = header.get("skins", []) or []
    if not skins:
        return []
    read = accessor_reader(header, binary, read_file)
    node_count = len(header.get("nodes", []))
    found = []
    for i, skin in enumerate(skins):
        joints = skin.get("joints", [])
        if not joints or not all(isinstance(j, int) and 0 <= j < node_count for j in joints):
            raise GltfProblem(f"skins[{i}] names joints that are not nodes of the file")
        if skin.get("inverseBindMatrices") is None:
            binds = np.tile(np.eye(4), (len(joints), 1, 1))
        else:  # column-major in the file
            binds = read(skin["inverseBindMatrices"], 16).astype(np.float64).reshape(-1, 4, 4).transpose(0, 2, 1)
        bad = np.flatnonzero(~np.isfinite(binds).all(axis=(1, 2)))
        if bad.size:
            raise GltfProblem(f"skins[{i}]: the inverse bind matrix of joint {bad[0]} holds numbers "
                              "that are not finite")
        if len(binds) != len(joints):
            raise GltfProblem(f"skins[{i}] has {len(binds)} inverse bind matrices for {len(joints)} joints")
        found.append(Skin(tuple(joints), binds))
    return found
