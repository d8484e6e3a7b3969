"""The in-memory triangle mesh every loader and primitive produces.

Arrays are plain NumPy so the scene model and tests never need a GL context.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from scenerender.mesh.topology import closed_winding


@dataclass(frozen=True)
class MeshGroup:
    """A run of triangles drawn with one material.

    ``first`` and ``count`` count triangles (rows of ``MeshData.indices``), not indices.
    ``material`` is the MTL material name, or None for "the object's material".
    """

    material: str | None
    first: int
    count: int


@dataclass
class MeshData:
    """An indexed triangle mesh.

    positions: (N, 3) float32, object space.
    normals:   (N, 3) float32, unit length (never NaN; degenerate areas get a finite normal).
    uvs:       (N, 2) float32, or None when the source has no texture coordinates.
    indices:   (M, 3) uint32, counter-clockwise triangles seen from the outside.
    groups:    triangle ranges by material, covering 0..M in order.
    materials: the file's materials by name: ``scenerender.mesh.mtl.MtlMaterial`` (OBJ) or
               ``scenerender.mesh.gltf.GltfMaterial`` (glTF); empty when none.
    source:    a human-readable origin ("models/duck.obj", "primitive sphere").
    colors:    (N, 4) float32 linear RGBA vertex colours (glTF ``COLOR_0``), or None.
    images:    images the file holds itself (glTF), by the key its materials' textures name:
               (H, W, 4) uint8 RGBA, top row first; empty when none.
    uvs1:      (N, 2) float32 a second set of texture coordinates (glTF ``TEXCOORD_1``, v
               up as ``uvs``), or None; a texture with ``uv_set`` 1 reads them.
    tangents:  (N, 4) float32 tangents the file stores (glTF ``TANGENT``: xyz the direction
               of increasing u, w the handedness), or None: then ``geometry.tangents``
               works them out from the texture coordinates.
    """

    positions: np.ndarray
    normals: np.ndarray
    uvs: np.ndarray | None
    indices: np.ndarray
    groups: list[MeshGroup] = field(default_factory=list)
    materials: dict = field(default_factory=dict)
    source: str = ""
    colors: np.ndarray | None = None
    images: dict = field(default_factory=dict)
    tangents: np.ndarray | None = None
    uvs1: np.ndarray | None = None
    _bounds: np.ndarray | None = field(default=None, init=False, repr=False, compare=False)
    _winding: int | None = field(default=None, init=False, repr=False, compare=False)
    _sphere: tuple | None = field(default=None, init=False, repr=False, compare=False)
    _convex: bool | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not self.groups:
            self.groups = [MeshGroup(None, 0, len(self.indices))]

    @property
    def triangle_count(self) -> int:
        return int(len(self.indices))

    @property
    def vertex_count(self) -> int:
        return int(len(self.positions))

    def bounds(self) -> np.ndarray:
        """(2, 3) float64: the min and max corners of the positions.

        Computed once: culling and scene bounds ask for it every frame, and a mesh's
        positions do not change after it is built (operations return new meshes).
        """
        if self._bounds is None:
            if len(self.positions) == 0:
                self._bounds = np.zeros((2, 3))
            else:
                p = self.positions.astype(np.float64)
                self._bounds = np.stack([p.min(axis=0), p.max(axis=0)])
        return self._bounds

    def closed_winding(self) -> int:
        """+1: a closed surface wound counter-clockwise seen from outside; -1: closed,
        clockwise; 0: open or inconsistent (mesh.topology.closed_winding). Computed once."""
        if self._winding is None:
            self._winding = closed_winding(self.positions, self.indices)
        return self._winding

    def bounding_sphere(self) -> tuple[np.ndarray, float]:
        """(centre (3,) float64, radius): a sphere around every position, centred on the
        bounds. Computed once."""
        if self._sphere is None:
            centre = self.bounds().mean(axis=0)
            offsets = self.positions.astype(np.float64) - centre
            radius = float(np.sqrt((offsets ** 2).sum(axis=1).max())) if len(offsets) else 0.0
            self._sphere = (centre, radius)
        return self._sphere

    def is_convex(self) -> bool:
        """Whether the mesh is a closed surface with every position on or behind every
        triangle's plane (within float32 rounding): seen from outside, its front faces
        never cover one another. False, unchecked, for meshes over CONVEX_CHECK_LIMIT
        triangle-vertex pairs. Computed once."""
        if self._convex is None:
            self._convex = (self.closed_winding() != 0
                            and len(self.indices) * len(self.positions) <= CONVEX_CHECK_LIMIT
                            and _all_behind_faces(self.positions, self.indices, self.closed_winding()))
        return self._convex

    def record_winding(self, winding: int) -> None:
        """Set what ``closed_winding`` returns, known from an earlier analysis of the same
        positions and indices (the mesh cache keeps it)."""
        self._winding = int(winding)


# is_convex checks every vertex against every face: up to this many pairs (a 256-triangle
# sphere has 256 x 146; a 4,096-triangle model about 8M) before it answers "not known".
CONVEX_CHECK_LIMIT = 20_000_000


def _all_behind_faces(positions: np.ndarray, indices: np.ndarray, winding: int) -> bool:
    """Every position on or behind every triangle's plane, the outside being the side its
    ``winding`` (+1 counter-clockwise, -1 clockwise seen from outside) faces."""
    p = positions.astype(np.float64)
    a, b, c = (p[indices[:, k]] for k in range(3))
    normals = np.cross(b - a, c - a) * float(winding)
    lengths = np.linalg.norm(normals, axis=1)
    keep = lengths > 0.0
    normals, a = normals[keep] / lengths[keep, None], a[keep]
    size = float(np.ptp(p, axis=0).max()) if len(p) else 0.0
    tolerance = 1e-5 * max(size, 1e-30)
    for start in range(0, len(normals), 1024):  # (faces, vertices) a block at a time
        block = normals[start:start + 1024]
        heights = p @ block.T - (a[start:start + 1024] * block).sum(axis=1)
        if heights.max() > tolerance:
            return False
    return True
