"""Screen-space ambient occlusion: a geometry prepass (normals and linear depth), the AO
estimate, and a blur. The prepass also feeds the depth and normals views."""
from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import (
    FULLSCREEN_VERTEX, MESH_VERTEX, begin_camera_pass, begin_fullscreen_pass, begin_fullscreen_pass_where_drawn,
    bind_texture_units, cull_hidden_faces, draw_cutting_masks, end_where_drawn, far_plane_defines, stop_culling,
)
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.data import ImageData, TargetData
from scenerender.world.settings import AmbientOcclusionSettings

NOISE_SIZE = 4


@dataclass(frozen=True)
class GBufferPass(RenderPass):
    """View-space normal (rgb) and linear view depth (a; 0 where empty), single-sampled.
    materials: the ``materials`` input, read only in a scene with alpha-masked materials
    (glTF MASK): their cut-away pixels hold no depth."""

    size: tuple
    camera: Handle
    objects: Handle
    materials: Handle | None = None
    format: str = "rgba16f"  # rgba32f where the depth view keeps its values (EXR)

    name = "gbuffer"

    def setup(self, builder) -> TargetData:
        builder.read(self.camera, self.objects, *((self.materials,) if self.materials is not None else ()))
        return TargetData(builder.create("gbuffer", ResourceDesc("color", self.size, self.format)),
                           builder.create("gbuffer_depth", ResourceDesc("depth", self.size, "camera_depth")))

    def execute(self, ctx, data: TargetData) -> None:
        begin_camera_pass(ctx, [data.color], data.depth, (0.0, 0.0, 0.0, 0.0))
        program = ctx.programs.get(MESH_VERTEX, "mesh/gbuffer.frag")
        camera = ctx.input(self.camera)
        set_uniforms(program, u_view_proj=camera.view_proj_relative(), u_view_rotation=camera.rotation)
        objects = ctx.input(self.objects)
        materials = ctx.input(self.materials) if self.materials is not None else None
        uniforms = {"u_view_proj": camera.view_proj_relative(), "u_view_rotation": camera.rotation}
        for index in objects.in_camera_view():
            cull_hidden_faces(ctx.gl, objects, index)
            draw_cutting_masks(ctx, objects, index, program, "mesh/gbuffer.frag", {}, materials, uniforms)
        stop_culling(ctx.gl)


def hemisphere_kernel(count: int, seed: int = 1) -> np.ndarray:
    """(count, 3) float32 sample offsets in the unit hemisphere around +Z, denser near the
    centre; a fixed seed keeps renders reproducible."""
    rng = np.random.Generator(np.random.PCG64(seed))
    samples = rng.uniform((-1.0, -1.0, 0.05), (1.0, 1.0, 1.0), size=(count, 3))
    samples /= np.linalg.norm(samples, axis=1, keepdims=True)
    scale = np.linspace(0.0, 1.0, count, endpoint=False)
    samples *= (0.1 + 0.9 * scale * scale)[:, None] * rng.uniform(0.5, 1.0, size=(count, 1))
    return samples.astype(np.float32)


def rotation_noise(seed: int = 2) -> bytes:
    """4x4 RGB8 random tangent-plane rotations (xy in [-1, 1] stored as [0, 255])."""
    rng = np.random.Generator(np.random.PCG64(seed))
    vectors = rng.uniform(-1.0, 1.0, size=(NOISE_SIZE * NOISE_SIZE, 3))
    vectors[:, 2] = 0.0
    return ((vectors * 0.5 + 0.5) * 255).round().astype(np.uint8).tobytes()


def _noise_texture(gl):
    texture = gl.texture((NOISE_SIZE, NOISE_SIZE), 3, rotation_noise())
    texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
    texture.repeat_x = texture.repeat_y = True
    return texture


@dataclass(frozen=True)
class SSAOPass(RenderPass):
    """Occlusion per pixel; 1 (open) where the prepass drew nothing, without shading there."""

    gbuffer: Handle
    gbuffer_depth: Handle
    camera: Handle
    size: tuple
    settings: AmbientOcclusionSettings

    name = "ssao"

    def setup(self, builder) -> ImageData:
        builder.read(self.gbuffer, self.gbuffer_depth, self.camera)
        return ImageData(builder.create("ao_raw", ResourceDesc("color", self.size, "r8")))

    def describe(self) -> str:
        return f"{self.settings.samples} samples, radius {self.settings.radius:g}"

    def execute(self, ctx, data: ImageData) -> None:
        fbo = begin_fullscreen_pass_where_drawn(ctx, data.image, self.gbuffer_depth, 1.0)
        camera = ctx.input(self.camera)
        defines = {"AO_SAMPLES": self.settings.samples, **far_plane_defines(ctx)}
        if camera.orthographic:
            defines["ORTHO_CAMERA"] = True
        program = ctx.programs.get(FULLSCREEN_VERTEX, "post/ssao.frag", defines)
        bind_texture_units(program)
        ctx.image(self.gbuffer).use(TEXTURE_UNITS["u_gbuffer"])
        ctx.shared("ssao_noise", _noise_texture).use(TEXTURE_UNITS["u_noise"])
        set_uniforms(program, u_kernel=hemisphere_kernel(self.settings.samples).tobytes(),
                     u_projection=camera.projection, u_screen=self.size,
                     u_radius=self.settings.radius, u_strength=self.settings.strength)
        ctx.fullscreen(program)
        end_where_drawn(ctx, fbo)


@dataclass(frozen=True)
class SSAOBlurPass(RenderPass):
    raw: Handle
    size: tuple

    name = "ssao_blur"

    def setup(self, builder) -> ImageData:
        builder.read(self.raw)
        return ImageData(builder.create("ao", ResourceDesc("color", self.size, "r8")))

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(FULLSCREEN_VERTEX, "post/ssao_blur.frag")
        bind_texture_units(program)
        ctx.image(self.raw).use(TEXTURE_UNITS["u_ao"])  # clamped at its edges, as every graph image
        ctx.fullscreen(program)
