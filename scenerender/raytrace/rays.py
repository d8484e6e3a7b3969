"""Ray casting against a triangle soup: Embree through trimesh when ``embreex`` is
installed (the ``[reference]`` extra), else trimesh's NumPy intersector (slow; it needs
``rtree``), else a brute-force NumPy test of every ray against every triangle (slower).

The engine only answers "which triangle does each ray hit first"; distances and
barycentric coordinates are recomputed here in float64 for that triangle, so precision does
not depend on the engine's float32 arithmetic.
"""
from __future__ import annotations

import numpy as np

_SLOW_WARNED = False


def embree_available() -> bool:
    try:
        import embreex  # noqa: F401
    except ImportError:
        return False
    return True


class TriangleCaster:
    """First-hit queries for triangles ``vertices`` (T, 3, 3) float64 (one row per triangle,
    already in the space the rays are given in)."""

    def __init__(self, vertices: np.ndarray, warn=None):
        import trimesh

        self.vertices = np.asarray(vertices, dtype=np.float64)
        count = len(self.vertices)
        mesh = trimesh.Trimesh(self.vertices.reshape(-1, 3), np.arange(count * 3).reshape(-1, 3), process=False)
        self._engine = None
        if not count:
            return
        if embree_available():
            from trimesh.ray.ray_pyembree import RayMeshIntersector
        else:
            _warn_slow(warn)
            if not _module_available("rtree"):
                self._engine = _BruteForce(self)
                return
            from trimesh.ray.ray_triangle import RayMeshIntersector
        self._engine = RayMeshIntersector(mesh)

    def first_hit(self, origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
        """(R,) int64 index of the first triangle each ray hits, -1 for none.

        origins, directions: (R, 3) float64 (directions need not be unit)."""
        if self._engine is None or len(origins) == 0:
            return np.full(len(origins), -1, dtype=np.int64)
        unit = directions / np.linalg.norm(directions, axis=1, keepdims=True)
        hits = np.asarray(self._engine.intersects_first(origins, unit), dtype=np.int64)
        if isinstance(self._engine, _BruteForce):
            return hits
        # Embree works in float32 over the whole scene's extent: with a 1 cm object near
        # the eye and a backdrop 5e4 away it reports hits a few percent outside small
        # triangles. Hits that the float64 test rejects are cast again exactly.
        wrong = self._misses_exactly(hits, origins, unit)
        if wrong.any():
            hits[wrong] = _BruteForce(self).intersects_first(origins[wrong], unit[wrong])
        return hits

    def _misses_exactly(self, hits: np.ndarray, origins: np.ndarray, directions: np.ndarray,
                        tolerance: float = 1e-4) -> np.ndarray:
        """(R,) bool: rays whose reported triangle the float64 ray-triangle test misses
        by more than ``tolerance`` in barycentric units."""
        found = np.nonzero(hits >= 0)[0]
        corners = self.vertices[hits[found]]
        e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
        p = np.cross(directions[found], e2)
        det = np.sum(e1 * p, axis=1)
        det = np.where(np.abs(det) < 1e-300, 1e-300, det)
        s = origins[found] - corners[:, 0]
        u = np.sum(s * p, axis=1) / det
        v = np.sum(directions[found] * np.cross(s, e1), axis=1) / det
        wrong = np.zeros(len(hits), dtype=bool)
        wrong[found] = (u < -tolerance) | (v < -tolerance) | (u + v > 1.0 + tolerance)
        return wrong

    def hit_parameters(self, triangles: np.ndarray, origins: np.ndarray, directions: np.ndarray):
        """Möller-Trumbore in float64 for rays known to hit ``triangles`` (R,) int.

        Returns (t (R,), u (R,), v (R,)): the hit is origin + t * direction, and
        (1 - u - v, u, v) its barycentric weights of the triangle's corners 0, 1, 2
        (clamped into the triangle: the engine decided it is a hit)."""
        corners = self.vertices[triangles]
        e1 = corners[:, 1] - corners[:, 0]
        e2 = corners[:, 2] - corners[:, 0]
        p = np.cross(directions, e2)
        det = np.sum(e1 * p, axis=1)
        det = np.where(np.abs(det) < 1e-300, 1e-300, det)
        s = origins - corners[:, 0]
        u = np.sum(s * p, axis=1) / det
        q = np.cross(s, e1)
        v = np.sum(directions * q, axis=1) / det
        t = np.sum(e2 * q, axis=1) / det
        u = np.clip(u, 0.0, 1.0)
        v = np.clip(v, 0.0, 1.0 - u)
        return t, u, v


class _BruteForce:
    """Every ray against every triangle, in blocks: for scenes of a few thousand triangles."""

    def __init__(self, caster: TriangleCaster):
        self.caster = caster

    def intersects_first(self, origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
        corners = self.caster.vertices
        e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
        block = max(1, 2_000_000 // len(corners))
        result = np.full(len(origins), -1, dtype=np.int64)
        for start in range(0, len(origins), block):
            o, d = origins[start:start + block, None, :], directions[start:start + block, None, :]
            p = np.cross(d, e2)
            det = np.sum(e1 * p, axis=2)
            ok = np.abs(det) > 1e-300
            det = np.where(ok, det, 1.0)
            s = o - corners[:, 0]
            u = np.sum(s * p, axis=2) / det
            q = np.cross(s, e1)
            v = np.sum(d * q, axis=2) / det
            t = np.sum(e2 * q, axis=2) / det
            hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
            t = np.where(hit, t, np.inf)
            nearest = np.argmin(t, axis=1)
            found = np.isfinite(t[np.arange(len(t)), nearest])
            result[start:start + block] = np.where(found, nearest, -1)
        return result


def _module_available(name: str) -> bool:
    import importlib.util

    return importlib.util.find_spec(name) is not None


def _warn_slow(warn) -> None:
    global _SLOW_WARNED
    if _SLOW_WARNED:
        return
    _SLOW_WARNED = True
    message = ("the reference renderer casts rays with trimesh's NumPy intersector, which is slow: "
               "install the 'reference' extra (embreex) for Embree")
    if warn is not None:
        warn(message)
    else:
        import warnings

        warnings.warn(message, stacklevel=3)
