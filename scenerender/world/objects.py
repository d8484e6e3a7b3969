"""Objects as the renderer sees them: a mesh, materials per mesh group, and transforms."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenerender.animation import Track
from scenerender.mesh import MeshData
from scenerender.world.settings import OutlineSettings
from scenerender.world.transforms import model_matrices, model_matrix, transformed_bounds


@dataclass
class InstanceSet:
    """Where one mesh is drawn: either fixed local matrices or per-instance tracks.

    fixed:  (K, 4, 4) float64 local matrices (random instances, or one identity).
    tracks: list of (position, rotation, scale) Tracks for listed instances, else None.
    single: True for the one identity instance of an object without ``instances``, whose
            transform is the object's own (checks over many objects skip composing it).
    """

    fixed: np.ndarray | None = None
    tracks: list | None = None
    single: bool = False

    @property
    def count(self) -> int:
        return len(self.tracks) if self.tracks is not None else len(self.fixed)

    def matrices(self, t: float) -> np.ndarray:
        if self.tracks is None:
            return self.fixed
        return np.stack([model_matrix(p(t), r(t), _scale3(s(t))) for p, r, s in self.tracks])


def _scale3(value) -> np.ndarray:
    return np.broadcast_to(np.asarray(value, dtype=np.float64).reshape(-1), (3,))


def single_instance() -> InstanceSet:
    return InstanceSet(fixed=np.eye(4)[None], single=True)


def listed_instances(specs) -> InstanceSet:
    return InstanceSet(tracks=[(s.position, s.rotation, s.scale) for s in specs])


def random_instances(spec) -> InstanceSet:
    """Instances drawn from ``spec`` (count, seed, ranges) with NumPy's PCG64, which
    gives the same numbers on every machine for the same seed."""
    rng = np.random.Generator(np.random.PCG64(spec.seed))
    k = spec.count
    positions = rng.uniform(spec.position.min, spec.position.max, size=(k, 3))
    rotations = rng.uniform(spec.rotation.min, spec.rotation.max, size=(k, 3))
    scales = rng.uniform(spec.scale.min, spec.scale.max, size=(k, 1)).repeat(3, axis=1)
    return InstanceSet(fixed=model_matrices(positions, rotations, scales))


@dataclass
class RenderObject:
    """One scene object.

    mesh: the MeshData (shared between objects that use the same file and options).
    mesh_key: identifies ``mesh`` for GPU upload sharing.
    materials: one Material per ``mesh.groups`` entry.
    """

    name: str
    path: tuple
    mesh: MeshData
    mesh_key: tuple
    materials: list
    position: Track
    rotation: Track
    scale: Track
    visible: Track
    cast_shadows: bool
    outline: OutlineSettings | None
    instances: InstanceSet
    motion: object = None  # world.node_animation.NodeMotion: a glTF node's part that a clip moves
    deform: object = None  # world.node_animation.Deformation: a glTF part's skin or morph targets

    def object_matrix(self, t: float) -> np.ndarray:
        return model_matrix(self.position(t), self.rotation(t), _scale3(self.scale(t)))

    def matrices(self, t: float) -> np.ndarray:
        """(K, 4, 4) float64 world matrices: the object's transform times each instance's
        (times the part's node motion, for a part of an animated glTF file)."""
        placed = self.object_matrix(t)[None] @ self.instances.matrices(t)
        return placed if self.motion is None else placed @ self.motion(t)

    def local_bounds(self, t: float = 0.0) -> np.ndarray:
        """(2, 3) bounds of the mesh as drawn at ``t``, before the object's transform: a
        skin's joints and morph targets move its vertices."""
        rest = self.mesh.bounds()
        return rest if self.deform is None else self.deform.bounds(t, rest)

    def world_bounds(self, matrices: np.ndarray, t: float = 0.0) -> np.ndarray:
        """World bounds of the instances placed by ``matrices``, the object's at ``t``."""
        return transformed_bounds(self.local_bounds(t), matrices)
