"""The scene on the GPU for one run: meshes, textures, instance buffers and the buffers of
the packed lights and shadow views (rendering.lights), refreshed from each FrameState."""
from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.gpu.meshes import INSTANCE_FLOATS, GpuMesh, instance_bytes, instance_rows
from scenerender.gpu.shaders import assemble
from scenerender.gpu.textures import TextureCache, environment_texture
from scenerender.rendering.graph_inputs import LightsInput
from scenerender.rendering.light_buffers import PackedLights
from scenerender.world.frame import FrameState

_VEC4 = 16  # bytes


@dataclass(frozen=True)
class EnvironmentTextures:
    """The environment light's images on the GPU, made once per run: ``source``, the
    equirectangular radiance with mip levels (what the prefilter pass reads), and
    ``diffuse``, its diffuse map (world.environment.EnvironmentDef.irradiance_map)."""

    source: object
    diffuse: object

    @classmethod
    def upload(cls, gl, environment) -> "EnvironmentTextures":
        return cls(environment_texture(gl, environment.image, mipmaps=True),
                   environment_texture(gl, environment.irradiance_map))

    def release(self) -> None:
        self.source.release()
        self.diffuse.release()


class GpuScene:
    """Uploads a World once and updates per-frame data before the passes run (``upload``)."""

    def __init__(self, ctx, world):
        self.ctx = ctx
        self.world = world
        self.textures = TextureCache(ctx, getattr(world, "images", None))
        self.meshes = self._upload_meshes()
        self.instance_buffers = [ctx.buffer(reserve=obj.instances.count * INSTANCE_FLOATS * 4, dynamic=True)
                                 for obj in world.objects]
        self.eye_relative_buffers: dict = {}  # object index -> instance buffer (made on first use)
        self.light_buffer = ctx.buffer(reserve=_VEC4, dynamic=True)
        self.shadow_buffer = ctx.buffer(reserve=_VEC4, dynamic=True)
        self._vaos: dict = {}
        self._extras: dict = {}
        self._memories: dict = {}
        self.deforms = self._deforms()
        self.skybox = self._skybox()
        self.environment = (EnvironmentTextures.upload(ctx, world.environment)
                            if getattr(world, "environment", None) is not None else None)

    def _upload_meshes(self) -> dict:
        needs_tangents: dict = {}
        for obj in self.world.objects:
            # a normal map reads them along its texture coordinates; an anisotropy needs them
            # (geometry.tangents gives a mesh without texture coordinates a frame of its own)
            wants = any(("normal_map" in m.maps and obj.mesh.uvs is not None) or m.anisotropy > 0.0
                        for m in obj.materials)
            needs_tangents[obj.mesh_key] = needs_tangents.get(obj.mesh_key, False) or wants
        meshes = {}
        for obj in self.world.objects:
            if obj.mesh_key not in meshes:
                meshes[obj.mesh_key] = GpuMesh(self.ctx, obj.mesh, needs_tangents[obj.mesh_key])
        return meshes

    def _deforms(self) -> dict:
        """object index -> GpuDeform for each glTF part with a skin or morph targets that a
        clip plays (none in most scenes)."""
        return {i: GpuDeform(self.ctx, obj.deform, self.meshes[obj.mesh_key])
                for i, obj in enumerate(self.world.objects) if obj.deform is not None}

    def _skybox(self):
        faces = self.world.settings.skybox
        return self.textures.cube_map(list(faces)) if faces is not None else None

    # -- per frame ---------------------------------------------------------------------
    def upload(self, frame: FrameState, lights: PackedLights) -> LightsInput:
        """Write ``frame``'s instance transforms and the packed ``lights`` into the run's
        buffers; returns the value of the graph's ``lights`` input over them. Called by
        GraphRenderer.import_frame before the frame's passes run, and nowhere else."""
        singles = [(buffer, state) for buffer, state in zip(self.instance_buffers, frame.objects)
                   if state.visible and state.count == 1]
        if singles:
            # one conversion for every single-instance object, then one write each: a scene of
            # many separate objects pays no per-object array work here
            rows = instance_rows(np.concatenate([state.models_rel for _, state in singles]),
                                 np.concatenate([state.normals for _, state in singles]))
            for (buffer, _), row in zip(singles, rows):
                buffer.write(row)
        for buffer, state in zip(self.instance_buffers, frame.objects):
            if state.visible and state.count != 1:
                buffer.write(instance_bytes(state.models_rel, state.normals))
        for index, deform in self.deforms.items():
            state = frame.objects[index]
            if state.visible:
                deform.pose(state.skin, state.morph)
        self._write(self.shadow_buffer, lights.views)
        self._write(self.light_buffer, lights.lights)
        return LightsInput(self.light_buffer, self.shadow_buffer, lights.first_view)

    def _write(self, buffer, data: bytes) -> None:
        if len(data) > buffer.size:
            buffer.orphan(len(data))
        buffer.write(data)

    def cached(self, key: str, make):
        """A GL object passes share for the whole run (noise textures, samplers), made once."""
        if key not in self._extras:
            self._extras[key] = make(self.ctx)
        return self._extras[key]

    def memory(self, name: str) -> dict:
        """A dict a pass keeps from frame to frame for the whole run, to reuse what it
        worked out from values that did not change (never GL objects; no image depends
        on what it holds)."""
        return self._memories.setdefault(name, {})

    def release(self) -> None:
        for obj in list(self._vaos.values()) + list(self._extras.values()):
            obj.release()
        self._vaos.clear()
        self._extras.clear()
        if self.environment is not None:
            self.environment.release()
        for deform in self.deforms.values():
            deform.release()
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



class GpuDeform:
    """Poses one part whose vertices move themselves (shaders/mesh/deform.vert): its rest
    vertices, joints and morph deltas stay in buffers of their own; ``pose`` writes the
    posed vertices over the mesh's vertex buffer by transform feedback, in the layout
    every pass reads."""

    MORPH_BINDING = 5  # the MorphDeltas storage block, bound only while posing

    def __init__(self, ctx, deform, mesh: GpuMesh):
        self.mesh = mesh
        self.count = mesh.mesh.vertex_count
        self.rest = ctx.buffer(mesh.vertices.read())
        defines, content, self.buffers = {}, [(self.rest, "3f 3f 2f", "in_position", "in_normal", "in_uv")], [self.rest]
        if deform.skin is not None:
            defines.update(SKINNED=True, JOINT_COUNT=len(deform.skin.joints))
            joints = ctx.buffer(np.ascontiguousarray(np.hstack([deform.joints, deform.weights]), dtype=np.float32))
            content.append((joints, "4f 4f", "in_joints", "in_weights"))
            self.buffers.append(joints)
        self.deltas = None
        if deform.targets is not None:
            defines["MORPH_TARGETS"] = len(deform.targets)
            self.deltas = ctx.buffer(np.ascontiguousarray(deform.targets, dtype=np.float32))
            self.buffers.append(self.deltas)
        self.program = ctx.program(vertex_shader=assemble("mesh/deform.vert", defines),
                                   varyings=["out_position", "out_normal", "out_uv"])
        self.vao = ctx.vertex_array(self.program, content)
        # Mesa runs transform feedback only with a complete framebuffer bound, and before
        # a frame's first pass none may be: a 1 x 1 one of its own (nothing is drawn to it)
        self.target = ctx.renderbuffer((1, 1))
        self.framebuffer = ctx.framebuffer(color_attachments=[self.target])

    def pose(self, palette: np.ndarray | None, weights: np.ndarray | None) -> None:
        """Pose the vertices with the joint matrices ``palette`` (J, 4, 4) and the morph
        target ``weights`` (T,), each None where the part has none."""
        if palette is not None:
            self.program["u_joints"].write(np.ascontiguousarray(palette.transpose(0, 2, 1), dtype=np.float32))
        if weights is not None:
            self.program["u_morph"].write(np.ascontiguousarray(weights, dtype=np.float32))
            if "u_vertex_count" in self.program:  # one target: the compiler folds 0 * count away
                self.program["u_vertex_count"].value = self.count
            self.deltas.bind_to_storage_buffer(self.MORPH_BINDING)
        self.framebuffer.use()
        self.vao.transform(self.mesh.vertices, moderngl.POINTS, vertices=self.count)

    def release(self) -> None:
        for item in (self.vao, self.program, *self.buffers, self.framebuffer, self.target):
            item.release()
