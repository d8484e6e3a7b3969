"""Which opaque objects the visible-samples depth prepass must draw, and in what order the
shading draw takes them, so that every fragment's post-depth coverage is exact.

With visible samples (pipeline.visible_samples_pay) the shading draw averages a pixel's
shadow over the samples where the surface passed the depth test (GL_ARB_post_depth_coverage).
That mask is right when, as a fragment is shaded, the depth buffer already holds every
surface nearer than it at its samples: laid down by the prepass, or drawn before it. So
an object can skip the prepass where nothing it hides is drawn before it:

- A flat object with the camera and every other object on one side of its plane hides
  nothing, itself included (a ground under what stands on it). It is drawn last.
- A convex closed object whose back faces are culled never covers itself, and where its
  bounding sphere meets no other object's, the two spheres' radical plane (the points of
  equal power |x - c|^2 - r^2) separates it from each of the others: of two objects only
  the one on the camera's side of that plane can hide the other, and it is the one whose
  power at the camera is smaller. The shading draw takes the objects in order of that
  power, so it comes first.

Every other object goes through the prepass, as before, and so does every object seen
through an orthographic camera. With no object left out the
order is the usual near-to-far one and the depth writes stop after the prepass, exactly
as without this plan.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenerender.rendering.draw import DrawItem, single_sided_faces
from scenerender.rendering.graph_inputs import ObjectsInput

# A surface counts as flat, and an object as standing on it, within this share of the size
# of what the camera sees (float32 vertices moved by float64 transforms: about 1e-7).
FLAT_TOLERANCE = 1e-6


@dataclass(frozen=True)
class VisibleSamplesPlan:
    """order: the opaque items as the shading draw takes them; prepass: the object indices
    whose depth the prepass lays down first."""

    order: list
    prepass: frozenset

    @property
    def prepass_is_everything(self) -> bool:
        return len(self.prepass) == len({item.object_index for item in self.order})


def plan_visible_samples(objects: ObjectsInput, camera, items: list[DrawItem],
                         last: dict | None = None) -> VisibleSamplesPlan:
    """The plan for ``items`` (opaque, nearest first, as draw.opaque_items gives them).
    ``last``: a dict the caller keeps across frames, where what objects that do not move
    keep is kept (the spheres' overlaps of the last frame)."""
    last = last if last is not None else {}
    indices = sorted({item.object_index for item in items})
    if camera.orthographic:  # parallel rays: both arguments above speak of rays from an eye
        return VisibleSamplesPlan(items, frozenset(indices))
    flat = flat_non_occluders(objects, camera, items)
    rest = [i for i in indices if i not in flat]
    # overlaps among every opaque object shown, in the camera's view or not (the same
    # set from frame to frame while nothing moves), the grounds drawn last aside
    shown = [i for i in _opaque_objects(objects, last) if objects.frames[i].visible and i not in flat]
    centres, radii = _bounding_spheres(objects, shown)
    apart = dict(zip(shown, _apart_as_before(centres, radii, last)))
    by_object: dict = {}
    for item in items:
        by_object.setdefault(item.object_index, []).append(item)
    free = {i for i in rest if apart.get(i, False) and _never_covers_itself(objects, i, by_object[i])}
    if not free and not flat:
        return VisibleSamplesPlan(items, frozenset(indices))
    eye = np.asarray(camera.position, dtype=np.float64)
    power = dict(zip(shown, ((centres - eye) ** 2).sum(axis=1) - radii ** 2))
    order = (sorted([item for item in items if item.object_index not in flat], key=lambda it: power[it.object_index])
             + [item for item in items if item.object_index in flat])
    return VisibleSamplesPlan(order, frozenset(rest) - free)


def _opaque_objects(objects: ObjectsInput, last: dict) -> list[int]:
    """The objects with an opaque material (worked out once a run: whether a material is
    transparent never changes)."""
    if "opaque" not in last:
        last["opaque"] = [i for i, obj in enumerate(objects.definitions)
                          if any(not material.transparent for material in obj.materials)]
    return last["opaque"]


def flat_non_occluders(objects: ObjectsInput, camera, items: list[DrawItem]) -> set[int]:
    """The objects of ``items`` that are flat (their world bounds have no thickness along
    an axis) with the camera on one side of their plane and every other object in view on
    that side too, touching it at most: they can hide nothing. Objects with an
    alpha-masked material are left out: the shading draw's early depth writes would fill
    their holes."""
    indices = sorted({item.object_index for item in items})
    if len(indices) < 2:
        return set()
    masked = {item.object_index for item in items if item.material.masked}
    bounds = np.array([objects.frames[i].bounds for i in indices])  # (n, 2, 3)
    lo, hi = bounds[:, 0], bounds[:, 1]
    tolerance = FLAT_TOLERANCE * max(float(np.max(hi.max(axis=0) - lo.min(axis=0))), 1e-30)
    eye = np.asarray(camera.position, dtype=np.float64)
    flat = set()
    for row in np.flatnonzero(np.any(hi - lo <= tolerance, axis=1)):
        if indices[row] in masked:
            continue
        others = np.arange(len(indices)) != row
        for axis in np.flatnonzero(hi[row] - lo[row] <= tolerance):
            plane = 0.5 * (lo[row, axis] + hi[row, axis])
            above = eye[axis] > plane + tolerance and np.all(lo[others, axis] >= plane - tolerance)
            below = eye[axis] < plane - tolerance and np.all(hi[others, axis] <= plane + tolerance)
            if above or below:
                flat.add(indices[row])
                break
    return flat


def _bounding_spheres(objects: ObjectsInput, indices: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """(n, 3) centres and (n,) radii of spheres around each object's instances: the mesh's
    own sphere moved by the model matrix for one instance (radius times the matrix's
    largest stretch), else the world bounds' sphere."""
    frames = [objects.frames[i] for i in indices]
    bounds = np.array([f.bounds for f in frames]).reshape(-1, 2, 3)
    centres = (bounds[:, 0] + bounds[:, 1]) / 2.0
    radii = np.linalg.norm(bounds[:, 1] - bounds[:, 0], axis=1) / 2.0
    single = [row for row, f in enumerate(frames) if f.count == 1]
    if single:
        spheres = [objects.definitions[indices[row]].mesh.bounding_sphere() for row in single]
        models = np.stack([frames[row].models[0] for row in single])
        local = np.array([centre for centre, _ in spheres])
        centres[single] = np.einsum("nij,nj->ni", models[:, :3, :3], local) + models[:, :3, 3]
        radii[single] = np.array([radius for _, radius in spheres]) * np.linalg.norm(models[:, :3, :3], 2, axis=(1, 2))
    return centres, radii


def _apart_as_before(centres: np.ndarray, radii: np.ndarray, last: dict) -> np.ndarray:
    """_apart, reused from ``last`` where the spheres are the same as there."""
    key = centres.tobytes() + radii.tobytes()
    if last.get("key") != key:
        last["key"], last["apart"] = key, _apart(centres, radii)
    return last["apart"]


def _apart(centres: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """(n,) bool: whether each sphere meets no other (touching counts as apart). Sweeps
    along x, so only spheres whose x extents overlap are compared."""
    n = len(radii)
    apart = np.ones(n, dtype=bool)
    order = np.argsort(centres[:, 0] - radii)
    left = (centres[:, 0] - radii)[order]
    right = (centres[:, 0] + radii)[order]
    for k in range(n):
        end = int(np.searchsorted(left, right[k], side="left"))
        if end <= k + 1:
            continue
        a, others = order[k], order[k + 1:end]
        meets = np.linalg.norm(centres[others] - centres[a], axis=1) < radii[others] + radii[a]
        if meets.any():
            apart[a] = False
            apart[others[meets]] = False
    return apart


def _never_covers_itself(objects: ObjectsInput, index: int, items: list[DrawItem]) -> bool:
    """A convex closed mesh, one instance, drawn with the faces turned away from the camera
    culled, and no alpha-masked material; ``items``: the object's own."""
    frame = objects.frames[index]
    if frame.count != 1 or frame.hidden_faces is None or not objects.definitions[index].mesh.is_convex():
        return False
    for item in items:
        if item.material.masked:
            return False
        if not item.material.double_sided and single_sided_faces(objects, index) != frame.hidden_faces:
            return False
    return True
