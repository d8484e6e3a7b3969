"""The world's per-frame inputs as graph resources, and their values for one frame.

``import_inputs`` imports every input of ``World.inputs`` (world.frame_inputs) into the graph and
returns their handles; passes declare the ones they read. Each frame,
``input_values`` turns the evaluated FrameState, and what GraphRenderer.import_frame uploaded
from it, into the value each handle resolves to in ``PassContext.input``. Values are
read-only: nothing here writes GPU state.
"""
from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.graph import FrameGraph, Handle, InputDesc
from scenerender.world.camera import CameraState
from scenerender.world.frame import FrameState
from scenerender.world.frame_inputs import WorldInput
from scenerender.world.lens import lens_radius


@dataclass(frozen=True)
class InputHandles:
    """Handles of the world's inputs in one graph (see world.frame_inputs.WorldInputs).

    per_light:    "light:NAME", one per light of World.lights, same index.
    shadow_views: (light index, "shadow_views:NAME") per shadowed light.
    lights:       "lights": every light and shadow view packed for the shaders
                  (LightsInput); the only way light data reaches a shader.
    exposure:     "exposure": the factor 2^render.exposure the output transform scales
                  linear light by; None where the exposure stays 0.
    """

    camera: Handle
    objects: Handle
    materials: Handle
    background: Handle
    ambient: Handle
    per_light: tuple
    shadow_views: tuple
    lights: Handle
    fog: Handle | None
    outlines: Handle | None
    skybox: Handle | None
    exposure: Handle | None
    environment: Handle | None = None      # EnvironmentState: colour x intensity, rotation
    environment_map: Handle | None = None  # scene_gpu.EnvironmentTextures: static
    lens: Handle | None = None  # LensInput, for render.depth_of_field: gather
    environment_views: Handle | None = None  # world.environment_visibility.EnvironmentViews
    motion: Handle | None = None  # world.motion.ShutterMotion, for render.motion_blur: velocity

    def shading(self) -> tuple:
        """Everything lit shading reads: camera, objects, materials, the ambient light,
        the packed ``lights`` and fog."""
        extra = (self.fog,) if self.fog is not None else ()
        return (self.camera, self.objects, self.materials, self.ambient, self.lights, *extra)

    def shadow_view(self, light_index: int) -> Handle:
        return dict(self.shadow_views)[light_index]

    def all(self) -> list[Handle]:
        """Every input handle, in import order."""
        found = [self.camera, self.objects, self.materials, self.background, self.ambient, *self.per_light,
                 *(handle for _, handle in self.shadow_views), self.lights, self.fog, self.outlines, self.skybox,
                 self.exposure, self.environment, self.environment_map, self.lens,
                 self.environment_views, self.motion]
        return [handle for handle in found if handle is not None]


def import_inputs(graph: FrameGraph, world) -> InputHandles:
    inputs = world.inputs

    def imported(world_input: WorldInput | None) -> Handle | None:
        if world_input is None:
            return None
        return graph.import_input(world_input.name, InputDesc(world_input.dynamic, world_input.describe()))

    return InputHandles(
        camera=imported(inputs.camera), objects=imported(inputs.objects), materials=imported(inputs.materials),
        background=imported(inputs.background), ambient=imported(inputs.ambient),
        per_light=tuple(imported(i) for i in inputs.per_light),
        shadow_views=tuple((index, imported(i)) for index, i in inputs.shadow_views.items()),
        lights=imported(inputs.lights),
        fog=imported(inputs.fog), outlines=imported(inputs.outlines), skybox=imported(inputs.skybox),
        exposure=imported(inputs.exposure), environment=imported(inputs.environment),
        environment_map=imported(inputs.environment_map), lens=imported(inputs.lens),
        environment_views=imported(inputs.environment_views),
        motion=imported(inputs.motion),
    )


# -- values ------------------------------------------------------------------------------

@dataclass(frozen=True)
class ObjectsInput:
    """The objects at one instant, ready to draw.

    definitions: world RenderObjects (static: mesh, materials, cast_shadows).
    frames:      world.frame.ObjectFrame per object (transforms, instances in view).
    origin:      (3,) float64 world position the uploaded transforms are relative to (the
                 camera's position this frame).
    """

    definitions: list
    frames: list
    origin: np.ndarray
    gpu: object  # rendering.scene_gpu.GpuScene: vertex arrays over this frame's instance buffers

    def in_camera_view(self) -> list[int]:
        """Indices of objects with at least one instance in the camera's view."""
        return [i for i, state in enumerate(self.frames) if state.in_view > 0]

    def shadow_casters(self) -> list[int]:
        """Indices of visible objects that cast shadows (seen from a light, view culling does
        not apply: a caster outside the camera's view still shadows what is in it)."""
        return [i for i, obj in enumerate(self.definitions) if obj.cast_shadows and self.frames[i].visible]

    def draw(self, program, index: int, *, mode=None, group: int | None = None, welded_normals: bool = False) -> None:
        """Draw object ``index`` (one mesh ``group`` of it, or all) with ``program``: the
        instances in the camera's view (passes drawn from a light draw every instance,
        through ``PassContext.draw_placed``)."""
        count = self.frames[index].in_view
        if count == 0:
            return
        mesh = self.definitions[index].mesh
        first, vertices = 0, mesh.triangle_count * 3
        if group is not None:
            first, vertices = mesh.groups[group].first * 3, mesh.groups[group].count * 3
        vao = self.gpu.vertex_array(program, index, welded_normals)
        vao.render(mode if mode is not None else moderngl.TRIANGLES, vertices=vertices, first=first, instances=count)


@dataclass(frozen=True)
class MaterialsInput:
    """values: id(Material) -> this frame's uniform values; textures: gpu.textures.TextureCache."""

    values: dict
    textures: object


@dataclass(frozen=True)
class FogInput:
    """color: (3,) linear RGB; density; range: (start, end) of linear fog."""

    color: np.ndarray
    density: float
    range: tuple


@dataclass(frozen=True)
class ShadowViewsInput:
    """One light's shadow views this frame (world.shadows.ShadowView)."""

    views: list

    def same_as(self, other) -> bool:
        """Whether ``other`` holds the same views, to the bit."""
        return (isinstance(other, ShadowViewsInput) and len(self.views) == len(other.views)
                and all(a.same_as(b) for a, b in zip(self.views, other.views)))


@dataclass(frozen=True)
class LightsInput:
    """Every light and shadow view of the frame, packed as the lighting shaders read them
    (rendering.lights) and uploaded before the passes run.

    buffer:     the light arrays (shaders/lighting/lights.glsl), a moderngl.Buffer.
    views:      the ShadowView structs (shaders/lighting/shadows.glsl), a moderngl.Buffer.
    first_view: per light of World.lights, the index of its first view in ``views``, or -1.
    A pass binds the buffers (rendering.draw.bind_lights); the value itself never writes.
    """

    buffer: object
    views: object
    first_view: tuple


def same_value(value, other) -> bool:
    """Whether two values of one input are the same: the same object, or equal by the
    value's own ``same_as`` (inputs without one never count as the same)."""
    return value is other or (hasattr(value, "same_as") and value.same_as(other))


def input_values(handles: InputHandles, frame: FrameState, camera: CameraState, gpu, world, lights) -> dict:
    """resource index -> value of every input for ``frame``; ``camera`` is the frame's
    camera with the device's projection, ``gpu`` the GpuScene the frame was uploaded to,
    ``lights`` the value of the ``lights`` input (LightsInput) that upload returned."""
    values = {
        handles.camera.resource: camera,
        handles.objects.resource: ObjectsInput(world.objects, frame.objects, frame.camera.position, gpu),
        handles.materials.resource: MaterialsInput(frame.materials, gpu.textures),
        handles.background.resource: frame.background,
        handles.ambient.resource: frame.ambient,
        handles.lights.resource: lights,
    }
    for handle, light in zip(handles.per_light, frame.lights):
        values[handle.resource] = light
    for light_index, handle in handles.shadow_views:
        values[handle.resource] = ShadowViewsInput(frame.shadow_views[light_index])
    if handles.fog is not None:
        fog = world.settings.fog
        values[handles.fog.resource] = FogInput(frame.fog_color, frame.fog_density, (fog.start, fog.end))
    if handles.outlines is not None:
        values[handles.outlines.resource] = {
            i: (np.asarray(obj.outline.color(frame.time)), obj.outline.width)
            for i, obj in enumerate(world.objects) if obj.outline is not None}
    if handles.skybox is not None:
        values[handles.skybox.resource] = gpu.skybox
    if handles.exposure is not None:
        values[handles.exposure.resource] = 2.0 ** frame.exposure
    if handles.environment is not None:
        values[handles.environment.resource] = frame.environment
        values[handles.environment_map.resource] = gpu.environment
    if handles.lens is not None:
        spec = world.spec.camera
        radius = lens_radius(frame.camera, spec.aperture, frame.focus_distance, spec.sensor_width)
        values[handles.lens.resource] = LensInput(radius, frame.focus_distance)
    if handles.environment_views is not None:
        values[handles.environment_views.resource] = frame.environment_views
    if handles.motion is not None:
        values[handles.motion.resource] = frame.motion
    return values


@dataclass(frozen=True)
class LensInput:
    """The thin lens at one instant (world.lens): aperture radius and focus distance, in
    scene units."""

    radius: float
    focus: float

    def same_as(self, other) -> bool:
        return isinstance(other, LensInput) and self == other
