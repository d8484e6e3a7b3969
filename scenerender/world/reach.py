"""How large an object's world-space values can get, over the whole animation.

Every frame rounds each object's model matrices and their normal matrices to 32-bit floats
(world.frame), and the shaders place its vertices in world space in 32-bit floats too.
Values that are fine on their own can multiply beyond the largest 32-bit float there
(3.4e38): a scale of 1e30 gives normal-matrix entries of 1e60, which round to infinity.

The world's build refuses such a placement once, for every frame at the same time, from
bounds instead of from evaluated frames, so the check costs the same however long the
animation is:

- no track's value exceeds ``Track.magnitude_bound`` in size, at any time;
- a rotation's entries are at most 1 in size, so entry (i, j) of R S is at most the size of
  scale factor j, and entry (i, j) of its cofactor matrix (the normal matrix up to its sign,
  see world.transforms.normal_matrices) at most the product of the two other factors;
- entrywise |A B| <= |A| |B|, and the cofactor matrix of a product is the product of the
  cofactor matrices: together they bound an object's transform times each instance's;
- a part of an animated glTF file is placed by its node's transform too (world.node_animation):
  each node of the chain from the root is bounded over the whole clip from its channels'
  keys (``Channel.magnitude_bound``), times the part's fixed rest inverse; a skinned part's
  vertices by its joints' transforms times their inverse bind matrices (the largest over
  the joints: each vertex is a weighted mean of its joints' placements of it), its morph
  targets growing its extent by their largest deltas times their largest weights.

The bounds may exceed what any frame reaches (a rotation never has all entries at 1), so a
placement within a factor of a few of the limit can be refused; none that can overflow passes.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenerender.mesh.numbers import BEYOND_FLOAT32
from scenerender.scene.messages import single_error
from scenerender.scene.values import FLOAT32_MAX
from scenerender.world.objects import InstanceSet, RenderObject
from scenerender.world.transforms import normal_matrices

@dataclass
class TransformBound:
    """Entrywise upper bounds on the sizes of K transforms' parts, over all time.

    linear:   (K, 3, 3) bounds on the upper 3x3.
    cofactor: (K, 3, 3) bounds on its cofactor matrix (the normal matrix, up to sign).
    move:     (K, 3) bounds on the translation.
    """

    linear: np.ndarray
    cofactor: np.ndarray
    move: np.ndarray

    @classmethod
    def of_tracks(cls, position: np.ndarray, scale: np.ndarray) -> "TransformBound":
        """The bound of T R S, for any rotation R, from (K, 3) bounds on the position and
        the scale factors."""
        others = np.stack([scale[:, 1] * scale[:, 2], scale[:, 0] * scale[:, 2], scale[:, 0] * scale[:, 1]], axis=1)
        rows = (len(scale), 3, 3)
        return cls(np.broadcast_to(scale[:, None, :], rows), np.broadcast_to(others[:, None, :], rows), position)

    def then(self, inner: "TransformBound") -> "TransformBound":
        """The bound of this transform applied after ``inner`` (self @ inner)."""
        return TransformBound(self.linear @ inner.linear, self.cofactor @ inner.cofactor,
                              (self.linear @ inner.move[..., None])[..., 0] + self.move)

    @classmethod
    def of_matrix(cls, matrix: np.ndarray) -> "TransformBound":
        """The bound of one fixed (4, 4) transform, as K = 1 arrays."""
        matrix = np.asarray(matrix, dtype=np.float64)[None]
        return cls(np.abs(matrix[:, :3, :3]), np.abs(normal_matrices(matrix)), np.abs(matrix[:, :3, 3]))

    def largest(self, other: "TransformBound") -> "TransformBound":
        """Entrywise the larger of two bounds: a bound of either transform."""
        return TransformBound(np.maximum(self.linear, other.linear), np.maximum(self.cofactor, other.cofactor),
                              np.maximum(self.move, other.move))

    def largest_model_entries(self) -> np.ndarray:
        """(K,) bounds on the largest entry of each model matrix's upper 3x3."""
        return self.linear.max(axis=(1, 2))

    def largest_normal_entries(self) -> np.ndarray:
        """(K,) bounds on the largest entry of each normal matrix."""
        return self.cofactor.max(axis=(1, 2))

    def vertex_reach(self, extent: np.ndarray) -> np.ndarray:
        """(K,) bounds on the size of any world coordinate of vertices no larger than
        ``extent`` ((3,) or (K, 3)) per axis."""
        return ((self.linear @ extent[..., None])[..., 0] + self.move).max(axis=1)


def check_placements(objects: list[RenderObject], source) -> None:
    """Raise a UserError at the first object whose model matrices, normal matrices or
    vertices in world space can leave the range of 32-bit floats in any frame."""
    # Objects without instances (often tens of thousands) are checked together, in NumPy.
    single = [i for i, obj in enumerate(objects)
              if obj.instances.single and obj.motion is None and obj.deform is None]
    own = TransformBound.of_tracks(magnitude_bounds([objects[i].position for i in single]),
                                   magnitude_bounds([objects[i].scale for i in single]))
    found = zip(single, placement_problems(own, _extents([objects[i].mesh for i in single])))
    problems = {i: problem for i, problem in found if problem is not None}
    for i, obj in enumerate(objects):
        if obj.motion is not None or obj.deform is not None:
            problem = animated_part_problem(obj)
            if problem is not None:
                problems[i] = problem
        elif not obj.instances.single:
            problem = instanced_placement_problem(obj)
            if problem is not None:
                problems[i] = problem
    if problems:
        first = min(problems)
        message, key = problems[first]
        raise single_error(f"object '{objects[first].name}': {message}", objects[first].path + key, source)


def instanced_placement_problem(obj: RenderObject) -> tuple[str, tuple] | None:
    """(message, key under the object) when some instance of ``obj`` can leave float32."""
    own = TransformBound.of_tracks(magnitude_bounds([obj.position]), magnitude_bounds([obj.scale]))
    placed = own.then(instances_bound(obj.instances))
    problem = next((p for p in placement_problems(placed, _extents([obj.mesh])) if p is not None), None)
    if problem is None or problem[1] != ("scale",):
        return problem
    own_scale = max(own.largest_model_entries()[0], own.largest_normal_entries()[0])
    return problem[0], ("scale",) if own_scale > FLOAT32_MAX else ("instances",)


def animated_part_problem(obj: RenderObject) -> tuple[str, tuple] | None:
    """(message, key under the object) when a part of an animated glTF file can leave
    float32 at some time of its clip: at its ``scale`` or ``instances`` where those alone
    do, else at its ``animation``."""
    own_problem = instanced_placement_problem(obj)
    if own_problem is not None:
        return own_problem
    placed = TransformBound.of_tracks(magnitude_bounds([obj.position]), magnitude_bounds([obj.scale]))
    placed = placed.then(instances_bound(obj.instances))
    if obj.motion is not None:
        placed = placed.then(_chain_bound(obj.motion.player, obj.motion.node).then(
            TransformBound.of_matrix(obj.motion.rest_inverse)))
    extent = _extents([obj.mesh])
    deform = obj.deform
    if deform is not None and deform.targets is not None:
        weights = deform.player.weights_bound(deform.node)
        weights = np.abs(deform.rest_weights if weights is None else weights)
        deltas = np.abs(deform.targets[:, :, :3].astype(np.float64)).max(axis=1)  # (T, 3)
        count = min(len(weights), len(deltas))
        extent = extent + (weights[:count, None] * deltas[:count]).sum(axis=0)
    if deform is not None and deform.skin is not None:
        used = np.unique(deform.joints[deform.weights > 0]).astype(int)
        joints = [_chain_bound(deform.player, deform.skin.joints[j]).then(
            TransformBound.of_matrix(deform.skin.inverse_binds[j])) for j in used]
        if joints:
            skinned = joints[0]
            for joint in joints[1:]:
                skinned = skinned.largest(joint)
            placed = placed.then(skinned)
    problem = placement_problems(placed, extent)[0]
    if problem is None:
        return None
    return f"with its glTF clip, {problem[0]}", ("animation",)


def _chain_bound(player, node: int) -> TransformBound:
    """The bound of a glTF node's world transform over the whole clip (ClipPlayer.chain_bounds)."""
    bound = TransformBound.of_matrix(np.eye(4))
    for kind, *parts in player.chain_bounds(node):
        if kind == "matrix":
            bound = bound.then(TransformBound.of_matrix(parts[0]))
        else:
            bound = bound.then(TransformBound.of_tracks(parts[0][None], parts[1][None]))
    return bound


def placement_problems(placed: TransformBound, extents: np.ndarray) -> list:
    """Per row of ``placed``: (message, key under the object) where that transform can
    leave float32, else None. ``extents``: (3,) or (K, 3), see _extents."""
    model, normal = placed.largest_model_entries(), placed.largest_normal_entries()
    reach = placed.vertex_reach(extents)
    problems = [None] * len(reach)
    for row in np.flatnonzero(np.maximum(np.maximum(model, normal), reach) > FLOAT32_MAX):
        problems[row] = _problem(float(model[row]), float(normal[row]), float(reach[row]))
    return problems


def _problem(model: float, normal: float, reach: float) -> tuple[str, tuple]:
    """The message (and key) for bounds of which at least one is beyond float32."""
    if max(model, normal) > FLOAT32_MAX:
        largest, matrix = (normal, "normal matrix") if normal > model else (model, "model matrix")
        return f"its scale factors multiply to {largest:.3g} in its {matrix}, {BEYOND_FLOAT32}", ("scale",)
    return (f"its vertices can reach {reach:.3g} from the origin in world space, {BEYOND_FLOAT32}; "
            "make it smaller or move it closer to the origin", ())


def magnitude_bounds(tracks: list) -> np.ndarray:
    """(N, 3): each Track's magnitude_bound, a scalar's repeated over x, y and z.

    Constant tracks (nearly all of them) are gathered and read in one NumPy call per shape:
    a scene may have tens of thousands of objects.
    """
    bounds = np.empty((len(tracks), 3))
    constants: dict[tuple, tuple[list, list]] = {(1, 1): ([], []), (1, 3): ([], [])}
    for i, track in enumerate(tracks):
        values = track.values
        group = constants.get(values.shape)
        if group is None:
            bounds[i] = track.magnitude_bound()
        else:
            group[0].append(i)
            group[1].append(values)
    for rows, found in constants.values():
        if rows:
            bounds[rows] = np.abs(np.concatenate(found))  # (n, 1) spreads over x, y and z
    return bounds


def instances_bound(instances: InstanceSet) -> TransformBound:
    """The bound of each instance's own transform, (K, ...) arrays."""
    if instances.tracks is not None:
        positions = magnitude_bounds([position for position, _rotation, _scale in instances.tracks])
        scales = magnitude_bounds([scale for _position, _rotation, scale in instances.tracks])
        return TransformBound.of_tracks(positions, scales)
    fixed = instances.fixed
    return TransformBound(np.abs(fixed[:, :3, :3]), np.abs(normal_matrices(fixed)), np.abs(fixed[:, :3, 3]))


def _extents(meshes: list) -> np.ndarray:
    """(N, 3): per mesh, the largest size of its vertices' coordinates per axis."""
    by_mesh: dict = {}
    for mesh in meshes:
        if id(mesh) not in by_mesh:
            by_mesh[id(mesh)] = np.abs(mesh.bounds()).max(axis=0)
    return np.array([by_mesh[id(mesh)] for mesh in meshes]).reshape(-1, 3)

