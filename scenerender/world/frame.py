"""Evaluate the World at one instant: everything a frame's passes need, as arrays.

Matrices are composed in float64 and made relative to the camera position before they
are rounded to float32, so precision does not depend on where the scene sits in the world.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from scenerender.world.build import World, scene_bounds
from scenerender.world.camera import CameraRig, CameraState
from scenerender.world.lens import lens_radius, through_lens
from scenerender.world.motion import ShutterMotion, blurs_by_velocity, shutter_motion
from scenerender.world.environment_light import EnvironmentState
from scenerender.world.environment_visibility import EnvironmentViews, environment_views, median_cut, visibility_tiles
from scenerender.world.light_states import LightState, ambient_light, evaluate_lights
from scenerender.world.facing import hidden_from_eye, hidden_side
from scenerender.world.frame_inputs import whole_footprint
from scenerender.world.shadows import AtlasLayout, light_views, visible_region
from scenerender.world.transforms import normal_matrices, union_bounds


@dataclass
class ObjectFrame:
    """One object at one instant.

    models_rel: (K, 4, 4) float32 camera-relative model matrices (translation minus camera),
                the instances inside the camera's view first.
    models:     (K, 4, 4) float64 world model matrices, same order.
    normals:    (K, 3, 3) float32 normal matrices, same order.
    in_view:    how many of the K instances (the first ones) the camera can see; passes
                drawn from the camera draw only those, shadow passes draw all K.
    bounds:     (2, 3) float64 world AABB of all instances.
    hidden_faces: "back" or "front": the faces the camera cannot see this frame (a closed,
                opaque surface seen from outside shows only the faces turned towards it),
                which passes drawing opaque surfaces from the camera may skip; None when
                every face may show (see hidden_faces).
    winding:    +1 / -1 where the surface is closed and opaque and every instance keeps
                (+1) or mirrors (-1) its counter-clockwise outward winding, else 0.
    """

    visible: bool
    models_rel: np.ndarray
    models: np.ndarray
    normals: np.ndarray
    bounds: np.ndarray
    center: np.ndarray
    in_view: int
    hidden_faces: str | None = None
    winding: int = 0
    skin: np.ndarray | None = None   # (J, 4, 4) float32 joint matrices of a skinned part (world.node_animation)
    morph: np.ndarray | None = None  # (T,) float32 morph target weights of a morphed part

    @property
    def count(self) -> int:
        return len(self.models_rel)


@dataclass
class FrameState:
    """Everything that varies over time, evaluated for frame ``index`` at ``time`` seconds."""

    index: int
    time: float
    camera: CameraState
    objects: list
    lights: list            # LightState per light of World.lights, same index
    ambient: np.ndarray     # (3,) the ambient lights summed
    background: np.ndarray  # (4,) linear RGBA
    fog_color: np.ndarray   # (3,)
    fog_density: float
    exposure: float         # render.exposure in stops
    bounds: np.ndarray | None
    shadow_views: dict      # light index -> list[ShadowView], for each shadowed light
    materials: dict         # id(Material) -> evaluated uniforms
    environment: EnvironmentState | None = None  # the environment light's, where the scene has one
    focus_distance: float | None = None  # where the lens focuses, with camera.aperture (world.lens)
    # the environment's visibility maps' views (world.environment_visibility), where it has them
    environment_views: EnvironmentViews | None = None
    motion: ShutterMotion | None = None  # each object's motion over the shutter, with render.motion_blur: velocity

    def shadowed_lights(self) -> list[int]:
        return sorted(self.shadow_views)


class FrameEvaluator:
    """Turns times into FrameStates for one World and output size."""

    def __init__(self, world: World, size: tuple, atlas: AtlasLayout | None, max_depth_ratio: float | None = None):
        """max_depth_ratio: the cap on far / near of `near/far: auto` (fit_near_far)."""
        self.world = world
        self.max_depth_ratio = max_depth_ratio
        self.size = size
        self.aspect = size[0] / size[1]
        self.atlas = atlas
        self.rig = CameraRig(world.spec.camera, self.aspect, max_depth_ratio, world.settings.size, world.file_camera)
        self._last_environment_views = None  # (what they were fitted to, EnvironmentViews)

    @cached_property
    def _windings(self) -> list:
        """+1 / -1 for closed, opaque surfaces (their winding), 0 for the rest."""
        # a skin or morph targets may fold or mirror a part: all its faces may show
        return [obj.mesh.closed_winding() if not any(m.transparent for m in obj.materials) and obj.deform is None else 0
                for obj in self.world.objects]

    @cached_property
    def _fixed(self) -> dict:
        """Objects that never move: index -> their placement (see _placement), so a frame's
        work for them is the camera-relative shift and the view test. Made on the first
        frame: an evaluator asked only for cameras never needs them."""
        return {i: self._placement(obj, obj.matrices(0.0), self._windings[i], 0.0)
                for i, (obj, keys) in enumerate(zip(self.world.objects, self.world.animated_parts.per_object))
                if not keys}

    @cached_property
    def _still(self) -> "StillObjects":
        """The objects that never move and have one instance, as arrays: their per-frame
        work (the camera-relative shift, the view test, the faces to skip) done for all
        of them at once."""
        # a skinned or morphed part poses its vertices every frame (world.node_animation)
        return StillObjects.of(self.world.objects, {i: p for i, p in self._fixed.items()
                                                    if len(p[0]) == 1 and self.world.objects[i].deform is None})

    def evaluate(self, index: int, time: float, lens_point: tuple | None = None) -> FrameState:
        """The frame at ``time``; ``lens_point`` (x, y on the unit disc): seen from that point
        of the lens of ``camera.aperture`` (world.lens), else from the pinhole."""
        world = self.world
        still = self._still
        placements = [None if i in still.rows else self._fixed.get(i) or
                      self._placement(obj, obj.matrices(time), self._windings[i], time)
                      for i, obj in enumerate(world.objects)]
        visible = [still.visible[still.rows[i]] if i in still.rows else bool(obj.visible(time))
                   for i, obj in enumerate(world.objects)]
        bounds = union_bounds([p[2] for p, v in zip(placements, visible) if v and p is not None]
                              + still.visible_bounds())
        if self.rig.first_bounds is None:
            # the default camera frames frame 0 (t = 0), whichever frame a run starts
            # with: a resumed or --frames run must draw what a full run draws
            start = bounds if time == 0.0 else scene_bounds(
                world.objects, [obj.matrices(0.0) for obj in world.objects],
                [bool(obj.visible(0.0)) for obj in world.objects])
            self.rig.first_bounds = start if start is not None else np.array([[-1.0] * 3, [1.0] * 3])
        camera = self.rig.at(time, bounds)
        focus = self._focus_distance(time, camera, placements) if self._has_lens else None
        if lens_point is not None:
            camera = self._through_lens(camera, lens_point, focus)
        planes = frustum_planes(camera.view_proj_relative())
        still_frames = still.frames(camera, planes)
        objects = [still_frames[still.rows[i]] if p is None else self._object(obj, p, v, camera, planes, time)
                   for i, (obj, p, v) in enumerate(zip(world.objects, placements, visible))]
        lights = evaluate_lights(world.lights, time, camera)
        render = world.render
        fog = render.fog
        return FrameState(
            index=index, time=time, camera=camera, objects=objects, lights=lights,
            ambient=ambient_light(world.ambient, time),
            background=np.asarray(render.background(time), dtype=np.float64),
            fog_color=np.asarray(fog.color(time), dtype=np.float64)[:3] if fog else np.zeros(3),
            fog_density=fog.density(time) if fog else 0.0, exposure=float(render.exposure(time)),
            bounds=bounds, shadow_views=self._shadow_views(lights, world, objects, bounds, camera),
            materials={id(m): self._constant_materials.get(id(m)) or _material_values(m, time)
                       for m in world.materials()},
            environment=world.environment.state(time) if world.environment is not None else None,
            focus_distance=focus,
            environment_views=self._environment_views(world, objects, bounds, time),
            motion=self._motion(time, camera.position, bounds),
        )

    def _motion(self, time: float, origin: np.ndarray, bounds) -> ShutterMotion | None:
        """The objects' and the camera's motion over the open shutter, where the velocity
        blur films it (world.motion); the cameras at its ends see the frame's ``bounds``
        (which only move the near and far planes, not where a point lands on screen)."""
        if not self._velocity_blur:
            return None
        open_seconds = self.world.spec.camera.shutter / float(self.world.output.fps)
        return shutter_motion(self.world.objects, time, open_seconds, origin, lambda t: self.rig.at(t, bounds))

    @cached_property
    def _velocity_blur(self) -> bool:
        return blurs_by_velocity(self.world)

    # -- camera -----------------------------------------------------------------------
    @cached_property
    def _has_lens(self) -> bool:
        return self.world.spec.camera is not None and self.world.spec.camera.aperture is not None

    def _focus_distance(self, t: float, camera: CameraState, placements: list) -> float:
        """Where the lens focuses at ``t``: on the centre of the object ``camera.focus``
        names (its distance along the view axis), else as the rig says."""
        name = self.world.spec.camera.focus
        if name is None:
            return self.rig.focus_distance(t)
        index = next(i for i, obj in enumerate(self.world.objects) if obj.name == name)
        # a still object's placement is kept in _fixed (evaluate leaves its slot None)
        lo, hi = (placements[index] or self._fixed[index])[2]
        return max(float(np.dot((lo + hi) / 2.0 - camera.position, camera.forward)), 1e-6)

    def _through_lens(self, camera: CameraState, point: tuple, focus: float) -> CameraState:
        spec = self.world.spec.camera
        return through_lens(camera, point, lens_radius(camera, spec.aperture, focus, spec.sensor_width), focus)

    def camera(self, t: float, bounds) -> CameraState:
        """The camera at ``t`` in a scene whose objects span ``bounds`` (2, 3), without
        evaluating the rest of the frame (objects that never move: their bounds at 0)."""
        if self.rig.first_bounds is None:
            self.rig.first_bounds = bounds
        return self.rig.at(t, bounds)

    # -- objects and shadows -------------------------------------------------------------
    @staticmethod
    def _placement(obj, matrices: np.ndarray, winding: int, t: float) -> tuple:
        """(matrices (K, 4, 4) float64, normal matrices (K, 3, 3) float32, world bounds (2, 3),
        winding): the surface's ``winding`` where its instances all keep it, reversed where
        they all mirror it, else 0."""
        if winding:
            signs = np.sign(np.linalg.det(matrices[:, :3, :3]))
            winding *= int(signs[0]) if np.all(signs == signs[0]) else 0
        return matrices, normal_matrices(matrices).astype(np.float32), obj.world_bounds(matrices, t), winding

    @staticmethod
    def _object(obj, placement: tuple, visible: bool, camera: CameraState, planes: np.ndarray, t: float) -> ObjectFrame:
        matrices, normals, bounds, winding = placement
        rel = matrices.copy()
        rel[:, :3, 3] -= camera.position
        inside = instances_in_view(obj.local_bounds(t), rel, planes)
        order = np.argsort(~inside, kind="stable")  # in-view instances first
        if len(order) > 1:
            rel, normals, matrices = rel[order], normals[order], matrices[order]
        return ObjectFrame(visible, rel.astype(np.float32), matrices, normals, bounds, (bounds[0] + bounds[1]) / 2.0,
                           int(inside.sum()) if visible else 0, hidden_faces(winding, bounds, camera), winding,
                           *_deformed(obj, t))

    @cached_property
    def _environment_directions(self) -> tuple:
        """The environment's visibility directions and weights (median_cut, each region
        halved where World.environment_halves says), once a run."""
        environment = self.world.environment
        return median_cut(environment.image, environment.visibility, halves=self.world.environment_halves)

    def _environment_views(self, world: World, objects: list, bounds, time: float) -> EnvironmentViews | None:
        environment = world.environment
        if environment is None or not environment.visibility:
            return None
        casters = union_bounds([f.bounds for obj, f in zip(world.objects, objects) if f.visible and obj.cast_shadows])
        to_image = environment.state(time).to_image
        # the views depend on these alone: a frame where none changed keeps the last ones
        # (fitting K views costs milliseconds; most scenes' objects stand still)
        key = tuple(np.asarray(a).tobytes() if a is not None else None for a in (casters, bounds, to_image))
        if self._last_environment_views is not None and self._last_environment_views[0] == key:
            return self._last_environment_views[1]
        directions, weights = self._environment_directions
        _, tiles = visibility_tiles(environment.visibility, environment.visibility_map_size, world.environment_halves)
        views = environment_views(directions, weights, to_image, tiles, casters, bounds)
        self._last_environment_views = (key, views)
        return views

    @cached_property
    def _constant_materials(self) -> dict:
        """id(Material) -> its values, for the materials none of whose values animate."""
        return {id(m): _material_values(m, 0.0) for m in self.world.materials()
                if all(getattr(m, key).is_constant for key in MATERIAL_TRACKS)}

    def _shadow_views(self, lights: list[LightState], world: World, objects: list, bounds, camera) -> dict:
        if self.atlas is None:
            return {}
        still = self._still
        casters = union_bounds([f.bounds for i, (obj, f) in enumerate(zip(world.objects, objects))
                                if f.visible and obj.cast_shadows and i not in still.rows]
                               + still.visible_bounds(casters_only=True))
        fixed = world.fixed_shadow_sizes
        whole = whole_footprint(world)
        follows_camera = any(light.kind == "directional" and i not in fixed and not whole
                             for i, light in enumerate(world.lights))
        visible = visible_region(camera, bounds) if follows_camera else None
        views = {}
        for index, tiles in sorted(self.atlas.tiles.items()):
            views[index] = light_views(lights[index], tiles, casters, bounds, None if index in fixed else visible)
        return views


class StillObjects:
    """Objects that never move and have one instance each, stacked: a scene of many
    separate objects costs a few array operations a frame for them, not a Python loop's
    worth of small ones per object. ``rows``: object index -> row. The frames it makes
    hold the same values, bit for bit, as FrameEvaluator._object makes one at a time."""

    def __init__(self, rows: dict, visible: list, casts: np.ndarray, matrices: np.ndarray, normals: np.ndarray,
                 bounds: np.ndarray, windings: np.ndarray, local_bounds: np.ndarray):
        self.rows = rows
        self.visible = visible
        self.matrices = matrices          # (M, 4, 4) float64
        self.normals = normals            # (M, 3, 3) float32
        self.bounds = bounds              # (M, 2, 3) world
        self.centers = (bounds[:, 0] + bounds[:, 1]) / 2.0
        self.windings = windings          # (M,) int
        self.local_bounds = local_bounds  # (M, 2, 3) of the meshes
        shown = np.asarray(visible, dtype=bool)
        self._union = union_bounds(list(bounds[shown]))
        self._casters_union = union_bounds(list(bounds[shown & casts]))

    @classmethod
    def of(cls, objects: list, placements: dict) -> "StillObjects":
        """placements: object index -> FrameEvaluator._placement of an object with one instance."""
        indices = sorted(placements)
        rows = {index: row for row, index in enumerate(indices)}
        if not indices:
            empty = np.zeros((0, 2, 3))
            return cls(rows, [], np.zeros(0, dtype=bool), np.zeros((0, 4, 4)), np.zeros((0, 3, 3), np.float32),
                       empty, np.zeros(0, dtype=int), empty)
        chosen = [placements[i] for i in indices]
        return cls(rows, [bool(objects[i].visible(0.0)) for i in indices],
                   np.array([objects[i].cast_shadows for i in indices], dtype=bool),
                   np.concatenate([p[0] for p in chosen]), np.concatenate([p[1] for p in chosen]),
                   np.stack([p[2] for p in chosen]), np.array([p[3] for p in chosen], dtype=int),
                   np.stack([objects[i].mesh.bounds() for i in indices]).astype(np.float64))

    def visible_bounds(self, casters_only: bool = False) -> list:
        """The union of the visible ones' world bounds (of the shadow casters among them), as
        a list of at most one box to add to other boxes."""
        union = self._casters_union if casters_only else self._union
        return [] if union is None else [union]

    def frames(self, camera: CameraState, planes: np.ndarray) -> list:
        """An ObjectFrame per row, for ``camera`` (whose view volume ``planes`` bound)."""
        if not self.rows:
            return []
        rel = self.matrices.copy()
        rel[:, :3, 3] -= camera.position
        rel32 = rel.astype(np.float32)
        inside = _boxes_in_view(self.local_bounds, rel, planes)
        hidden = _hidden_faces_of_boxes(self.windings, self.bounds, camera)
        frames = []
        for row, shown in enumerate(self.visible):
            end = row + 1
            frames.append(ObjectFrame(shown, rel32[row:end], self.matrices[row:end], self.normals[row:end],
                                      self.bounds[row], self.centers[row], int(inside[row]) if shown else 0,
                                      hidden[row], int(self.windings[row])))
        return frames


def _boxes_in_view(local_bounds: np.ndarray, models: np.ndarray, planes: np.ndarray) -> np.ndarray:
    """instances_in_view for M objects of one instance each: local_bounds (M, 2, 3),
    models (M, 4, 4) -> (M,) bool."""
    center = (local_bounds[:, 0] + local_bounds[:, 1]) / 2.0
    extent = (local_bounds[:, 1] - local_bounds[:, 0]) / 2.0
    linear = models[:, :3, :3]
    world_center = np.einsum("mij,mj->mi", linear, center) + models[:, :3, 3]
    world_extent = np.einsum("mij,mj->mi", np.abs(linear), extent)
    normals, offsets = planes[:, :3], planes[:, 3]
    reach = world_extent @ np.abs(normals).T
    distance = world_center @ normals.T + offsets
    return np.all(distance + reach >= 0.0, axis=1)


def _hidden_faces_of_boxes(windings: np.ndarray, bounds: np.ndarray, camera: CameraState) -> list:
    """hidden_faces for M objects: windings (M,), world bounds (M, 2, 3)."""
    if camera.orthographic:
        return [None] * len(windings)
    eye, forward = np.asarray(camera.position, dtype=np.float64), np.asarray(camera.forward, dtype=np.float64)
    lo, hi = bounds[:, 0], bounds[:, 1]
    # the nearest corner along ``forward``: per axis the low or the high side
    nearest = np.where(forward >= 0.0, lo, hi)
    depths = (nearest - eye) @ forward
    projection = camera.projection
    reach = camera.near * float(np.sqrt(1.0 + 1.0 / projection[0, 0] ** 2 + 1.0 / projection[1, 1] ** 2))
    outside_by = np.linalg.norm(np.maximum(np.maximum(lo - eye, eye - hi), 0.0), axis=1)
    may_see_inside = (depths <= camera.near) & (outside_by <= reach)
    return [None if winding == 0 or inside else hidden_side(int(winding))
            for winding, inside in zip(windings, may_see_inside)]


def _deformed(obj, t: float) -> tuple:
    """(joint matrices, morph weights) of a part whose vertices move themselves, float32."""
    deform = obj.deform
    if deform is None:
        return None, None
    palette, weights = deform.palette(t), deform.morph_weights(t)
    return (palette.astype(np.float32) if palette is not None else None,
            np.asarray(weights, dtype=np.float32) if weights is not None else None)


def hidden_faces(winding: int, bounds: np.ndarray, camera: CameraState) -> str | None:
    """The faces of a closed surface the camera cannot see (world.facing.hidden_from_eye),
    or None. Orthographic cameras never skip faces (their near plane is as wide as the
    view, so it may cut into any surface)."""
    if camera.orthographic:
        return None
    return hidden_from_eye(winding, bounds, camera.position, camera.forward, camera.near, camera.projection)


def frustum_planes(clip: np.ndarray) -> np.ndarray:
    """(6, 4) planes (n, d) of a clip matrix; a point p is inside when n.p + d >= 0 for all."""
    rows = clip
    return np.stack([rows[3] + rows[0], rows[3] - rows[0], rows[3] + rows[1],
                     rows[3] - rows[1], rows[3] + rows[2], rows[3] - rows[2]])


def instances_in_view(local_bounds: np.ndarray, models: np.ndarray, planes: np.ndarray) -> np.ndarray:
    """(K,) bool: whether each instance's box can touch the view volume.

    local_bounds (2, 3); models (K, 4, 4) in the same space as ``planes``. Conservative:
    a box straddling a plane counts as inside, so culling never changes the image.
    """
    center = (local_bounds[0] + local_bounds[1]) / 2.0
    extent = (local_bounds[1] - local_bounds[0]) / 2.0
    linear = models[:, :3, :3]
    world_center = linear @ center + models[:, :3, 3]           # (K, 3)
    world_extent = np.abs(linear) @ extent                      # (K, 3)
    normals, offsets = planes[:, :3], planes[:, 3]
    reach = world_extent @ np.abs(normals).T                    # (K, 6)
    distance = world_center @ normals.T + offsets               # (K, 6)
    return np.all(distance + reach >= 0.0, axis=1)


MATERIAL_TRACKS = ("ambient", "diffuse", "specular", "emissive", "shininess", "opacity", "metallic", "roughness")


def _material_values(material, t: float) -> dict:
    """A material's uniform values at ``t`` (linear RGBA colours, floats)."""
    return {
        "ambient": np.asarray(material.ambient(t))[:3],
        "diffuse": np.asarray(material.diffuse(t)),
        "specular": np.asarray(material.specular(t))[:3],
        "emissive": np.asarray(material.emissive(t))[:3],
        "shininess": float(material.shininess(t)),
        "opacity": float(material.opacity(t)),
        "metallic": float(material.metallic(t)),
        "roughness": float(material.roughness(t)),
    }
