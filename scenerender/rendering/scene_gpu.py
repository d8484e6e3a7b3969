"""The scene on the GPU for one run: meshes, textures, instance buffers and the light and
shadow-view storage buffers, refreshed from each FrameState."""
from __future__ import annotations

import numpy as np

from scenerender.gpu.meshes import INSTANCE_FLOATS, GpuMesh, instance_bytes
from scenerender.gpu.textures import TextureCache
from scenerender.world.frame import FrameState

LIGHT_BINDING = 0
SHADOW_VIEW_BINDING = 1
_VEC4 = 16  # bytes


class GpuScene:
    """Uploads a World once and updates per-frame data before the passes run."""

    def __init__(self, ctx, world, atlas):
        self.ctx = ctx
        self.world = world
        self.atlas = atlas
        self.textures = TextureCache(ctx, getattr(world, "images", None))
        self.meshes = self._upload_meshes()
        self.instance_buffers = [ctx.buffer(reserve=obj.instances.count * INSTANCE_FLOATS * 4, dynamic=True)
                                 for obj in world.objects]
        self.eye_relative_buffers: dict = {}  # object index -> instance buffer (made on first use)
        self.light_buffer = ctx.buffer(reserve=_VEC4, dynamic=True)
        self.shadow_buffer = ctx.buffer(reserve=_VEC4, dynamic=True)
        self.first_shadow_view: dict = {}
        self._vaos: dict = {}
        self._extras: dict = {}
        self.skybox = self._skybox()

    def _upload_meshes(self) -> dict:
        needs_tangents: dict = {}
        for obj in self.world.objects:
            wants = any("normal_map" in m.maps for m in obj.materials) and obj.mesh.uvs is not None
            needs_tangents[obj.mesh_key] = needs_tangents.get(obj.mesh_key, False) or wants
        meshes = {}
        for obj in self.world.objects:
            if obj.mesh_key not in meshes:
                meshes[obj.mesh_key] = GpuMesh(self.ctx, obj.mesh, needs_tangents[obj.mesh_key])
        return meshes

    def _skybox(self):
        faces = self.world.settings.skybox
        return self.textures.cube_map(list(faces)) if faces is not None else None

    # -- per frame ---------------------------------------------------------------------
    def upload(self, frame: FrameState) -> None:
        for buffer, state in zip(self.instance_buffers, frame.objects):
            if state.visible:
                buffer.write(instance_bytes(state.models_rel, state.normals))
        views = self._pack_shadow_views(frame)
        self._write(self.shadow_buffer, views)
        self._write(self.light_buffer, self._pack_lights(frame))
        # the same buffers serve programs declaring them as uniform blocks (when they fit)
        # and as storage buffers: the two binding namespaces are separate
        for buffer, binding in ((self.light_buffer, LIGHT_BINDING), (self.shadow_buffer, SHADOW_VIEW_BINDING)):
            buffer.bind_to_storage_buffer(binding)
            buffer.bind_to_uniform_block(binding)

    def _write(self, buffer, data: bytes) -> None:
        if len(data) > buffer.size:
            buffer.orphan(len(data))
        buffer.write(data)

    def _pack_shadow_views(self, frame: FrameState) -> bytes:
        """ShadowView structs (see shaders/lighting/shadows.glsl), in light order (the
        index of World.lights, FrameState.lights and the atlas's tiles)."""
        rows = []
        self.first_shadow_view = {}
        if self.atlas is None:
            return np.zeros(4, dtype=np.float32).tobytes()
        to_world = np.eye(4)
        to_world[:3, 3] = frame.camera.position  # camera-relative -> absolute world
        for light_index in frame.shadowed_lights():
            settings = frame.lights[light_index].definition.shadow
            self.first_shadow_view[light_index] = len(rows)
            for view in frame.shadow_views[light_index]:
                rows.append(_shadow_view_row(view, to_world, settings, self.atlas.pages[view.tile.page]))
        if not rows:
            return np.zeros(4, dtype=np.float32).tobytes()
        return np.asarray(rows, dtype=np.float32).tobytes()

    def _pack_lights(self, frame: FrameState) -> bytes:
        """std430 light arrays in type order (see shaders/lighting/lights.glsl)."""
        cam = frame.camera.position
        dirs, points, spots = [], [], []
        for index, light in enumerate(frame.lights):
            shadow = [float(self.first_shadow_view.get(index, -1)), 0.0, 0.0, 0.0]
            color = [*light.color, 0.0]
            if light.kind == "directional":
                dirs.append([*light.direction, 0.0, *color, *shadow])
            elif light.kind == "point":
                points.append([*(light.position - cam), 1.0, *color, *light.definition.attenuation, 0.0, *shadow])
            else:
                spots.append([*(light.position - cam), 1.0, *light.direction, 0.0, *color,
                              *light.definition.attenuation, 0.0, light.cos_inner, light.cos_outer, 0.0, 0.0,
                              *shadow])
        parts = [np.asarray(group, dtype=np.float64).reshape(-1) for group in (dirs, points, spots) if group]
        parts.append(np.zeros(4))  # lights_end
        return np.concatenate(parts).astype(np.float32).tobytes()

    def cached(self, key: str, make):
        """A GL object passes share for the whole run (noise textures, samplers), made once."""
        if key not in self._extras:
            self._extras[key] = make(self.ctx)
        return self._extras[key]

    def release(self) -> None:
        for obj in list(self._vaos.values()) + list(self._extras.values()):
            obj.release()
        self._vaos.clear()
        self._extras.clear()
        for mesh in self.meshes.values():
            mesh.release()
        for buffer in self.instance_buffers + list(self.eye_relative_buffers.values()) + [self.light_buffer,
                                                                                           self.shadow_buffer]:
            buffer.release()
        self.textures.release()

    # -- drawing -----------------------------------------------------------------------
    def fullscreen_array(self, program):
        """A vertex array with no buffers, for programs that draw one full-screen triangle."""
        key = ("fullscreen", id(program))
        vao = self._vaos.get(key)
        if vao is None:
            vao = self._vaos[key] = self.ctx.vertex_array(program, [])
        return vao

    def vertex_array(self, program, object_index: int, welded_normals: bool = False, eye_relative: bool = False):
        """The vertex array drawing object ``object_index`` with ``program`` (cached): over
        this frame's camera-relative instance buffer, or the one ``write_eye_relative``
        fills."""
        key = (id(program), object_index, welded_normals, eye_relative)
        vao = self._vaos.get(key)
        if vao is None:
            obj = self.world.objects[object_index]
            mesh = self.meshes[obj.mesh_key]
            instances = self._eye_relative_buffer(object_index) if eye_relative else self.instance_buffers[object_index]
            content = mesh.content(program, instances, welded_normals)
            vao = self.ctx.vertex_array(program, content, index_buffer=mesh.indices, index_element_size=4)
            self._vaos[key] = vao
        return vao

    def write_eye_relative(self, object_index: int, models: np.ndarray, normals: np.ndarray) -> None:
        """Fill object ``object_index``'s second instance buffer: models (K, 4, 4) relative
        to some eye, normals (K, 3, 3)."""
        self._write(self._eye_relative_buffer(object_index), instance_bytes(models, normals))

    def _eye_relative_buffer(self, object_index: int):
        if object_index not in self.eye_relative_buffers:
            count = self.world.objects[object_index].instances.count
            self.eye_relative_buffers[object_index] = self.ctx.buffer(reserve=count * INSTANCE_FLOATS * 4, dynamic=True)
        return self.eye_relative_buffers[object_index]


def _shadow_view_row(view, to_world: np.ndarray, settings, page_size) -> np.ndarray:
    """One ShadowView as 36 float64s (see shaders/lighting/shadows.glsl); page_size:
    (width, height) of the atlas page holding the view's tile.

    Everything the lookup needs per fragment is folded into one matrix here, once per
    frame: camera-relative world -> (page u * w, page v * w, linear depth, w), so the
    shader does one matrix product instead of a view, a projection and a tile transform.
    """
    width, height = page_size
    tile = view.tile
    to_light = view.view @ to_world
    clip = view.projection @ to_light
    origin = np.array([tile.x / width, tile.y / height])
    extent = np.array([tile.size / width, tile.size / height])
    to_atlas = np.empty((4, 4))
    to_atlas[:2] = 0.5 * extent[:, None] * clip[:2] + (origin + 0.5 * extent)[:, None] * clip[3]
    depth_range = view.far - view.near
    to_atlas[2] = (-to_light[2] - view.near * np.array([0.0, 0.0, 0.0, 1.0])) / depth_range
    to_atlas[3] = clip[3]
    light_position = np.linalg.inv(to_light)[:3, 3]  # the light's eye, camera-relative
    return np.concatenate([
        to_atlas.T.reshape(-1),
        [*light_position, 1.0 if view.radial else 0.0],
        [*origin, *(origin + extent)],
        [view.near, 1.0 / depth_range, *shadow_bias_texels(settings)],
        [1.0 / width, 1.0 / height, settings.pcf, 0.0],
        _texel_world_size(view),
    ])


# The constant depth bias every lookup gets, in shadow texels: covers the depth a texel's
# centre and a point elsewhere in it can differ by on a surface facing the light.
BASE_BIAS_TEXELS = 0.5


def shadow_bias_texels(settings) -> tuple[float, float]:
    """(constant, slope) depth bias in shadow texels at the receiver (see
    shaders/lighting/shadows.glsl): the built-in amounts plus the light's ``bias`` and
    ``slope_bias``. The slope term covers the filter's reach, pcf / 2 texels."""
    return BASE_BIAS_TEXELS + settings.bias, 0.5 * settings.pcf + settings.slope_bias


def _texel_world_size(view) -> list:
    """World size of one shadow-map texel: (per unit distance, constant, 0, 0).

    Perspective views (spot, cube faces) grow with distance from the light; orthographic
    views (directional) have one size everywhere.
    """
    p = view.projection
    if p[3, 3] == 0.0:  # perspective: x_ndc = p00 * x / -z
        return [2.0 / (p[0, 0] * view.tile.size), 0.0, 0.0, 0.0]
    return [0.0, 2.0 / (p[0, 0] * view.tile.size), 0.0, 0.0]
