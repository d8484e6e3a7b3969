"""Evaluate the World at one instant: everything a frame's passes need, as arrays.

Matrices are composed in float64 and made relative to the camera position before they
are rounded to float32, so precision does not depend on where the scene sits in the world.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from scenerender.animation import animated_keys
from scenerender.world.build import World, scene_bounds
from scenerender.world.camera import CameraRig, CameraState
from scenerender.world.inputs import OBJECT_LOOK_KEYS
from scenerender.world.lens import lens_radius, through_lens
from scenerender.world.motion import ShutterMotion, blurs_by_velocity, shutter_motion
from scenerender.world.environment import EnvironmentState
from scenerender.world.lights import LightState, ambient_light, evaluate_lights
from scenerender.world.facing import hidden_from_eye
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
        self.rig = CameraRig(world.spec.camera, self.aspect, max_depth_ratio)

    @cached_property
    def _windings(self) -> list:
        """+1 / -1 for closed, opaque surfaces (their winding), 0 for the rest."""
        return [obj.mesh.closed_winding() if not any(m.transparent for m in obj.materials) else 0
                for obj in self.world.objects]

    @cached_property
    def _fixed(self) -> dict:
        """Objects that never move: index -> their placement (see _placement), so a frame's
        work for them is the camera-relative shift and the view test. Made on the first
        frame: an evaluator asked only for cameras never needs them."""
        return {i: self._placement(obj, obj.matrices(0.0), self._windings[i])
                for i, obj in enumerate(self.world.objects) if not animated_keys(obj, skip=OBJECT_LOOK_KEYS)}

    def evaluate(self, index: int, time: float, lens_point: tuple | None = None) -> FrameState:
        """The frame at ``time``; ``lens_point`` (x, y on the unit disc): seen from that point
        of the lens of ``camera.aperture`` (world.lens), else from the pinhole."""
        world = self.world
        placements = [self._fixed.get(i) or self._placement(obj, obj.matrices(time), self._windings[i])
                      for i, obj in enumerate(world.objects)]
        visible = [bool(obj.visible(time)) for obj in world.objects]
        bounds = union_bounds([p[2] for p, v in zip(placements, visible) if v])
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
        objects = [self._object(obj, p, v, camera, planes) for obj, p, v in zip(world.objects, placements, visible)]
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
            materials={id(m): _material_values(m, time) for m in world.materials()},
            environment=world.environment.state(time) if world.environment is not None else None,
            focus_distance=focus, motion=self._motion(time, camera.position, bounds),
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
        lo, hi = placements[index][2]
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
    def _placement(obj, matrices: np.ndarray, winding: int) -> tuple:
        """(matrices (K, 4, 4) float64, normal matrices (K, 3, 3) float32, world bounds (2, 3),
        winding): the surface's ``winding`` where its instances all keep it, reversed where
        they all mirror it, else 0."""
        if winding:
            signs = np.sign(np.linalg.det(matrices[:, :3, :3]))
            winding *= int(signs[0]) if np.all(signs == signs[0]) else 0
        return matrices, normal_matrices(matrices).astype(np.float32), obj.world_bounds(matrices), winding

    @staticmethod
    def _object(obj, placement: tuple, visible: bool, camera: CameraState, planes: np.ndarray) -> ObjectFrame:
        matrices, normals, bounds, winding = placement
        rel = matrices.copy()
        rel[:, :3, 3] -= camera.position
        inside = instances_in_view(obj.mesh.bounds(), rel, planes)
        order = np.argsort(~inside, kind="stable")  # in-view instances first
        if len(order) > 1:
            rel, normals, matrices = rel[order], normals[order], matrices[order]
        return ObjectFrame(visible, rel.astype(np.float32), matrices, normals, bounds, (bounds[0] + bounds[1]) / 2.0,
                           int(inside.sum()) if visible else 0, hidden_faces(winding, bounds, camera), winding)

    def _shadow_views(self, lights: list[LightState], world: World, objects: list, bounds, camera) -> dict:
        if self.atlas is None:
            return {}
        casters = union_bounds([f.bounds for obj, f in zip(world.objects, objects) if f.visible and obj.cast_shadows])
        fixed = world.fixed_shadow_sizes
        follows_camera = any(light.kind == "directional" and i not in fixed for i, light in enumerate(world.lights))
        visible = visible_region(camera, bounds) if follows_camera else None
        views = {}
        for index, tiles in sorted(self.atlas.tiles.items()):
            views[index] = light_views(lights[index], tiles, casters, bounds, None if index in fixed else visible)
        return views


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
