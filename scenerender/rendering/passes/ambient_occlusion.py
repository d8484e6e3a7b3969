"""Screen-space ambient occlusion: a geometry prepass (normals and linear depth), the AO
estimate, and a blur. The prepass also feeds the depth and normals views."""
from __future__ import annotations

import numpy as np

from scenerender.graph import ResourceDesc, RenderPass
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import begin_camera_pass, bind_texture_units, camera_objects, draw_object
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.forward import MESH_VERTEX, fullscreen

NOISE_SIZE = 4


class GBufferPass(RenderPass):
    """View-space normal (rgb) and linear view depth (a; 0 where empty), single-sampled."""

    name = "gbuffer"

    def __init__(self, size, dynamic: bool = True):
        self.size = size
        self.dynamic = dynamic

    def setup(self, builder):
        self.gbuffer = builder.create("gbuffer", ResourceDesc("color", self.size, "rgba16f"))
        self.depth = builder.create("gbuffer_depth", ResourceDesc("depth", self.size, "camera_depth"))
        return self.gbuffer

    def execute(self, ctx) -> None:
        begin_camera_pass(ctx, [self.gbuffer], self.depth, (0.0, 0.0, 0.0, 0.0))
        program = ctx.programs.get(MESH_VERTEX, "mesh/gbuffer.frag")
        camera = ctx.frame.camera
        set_uniforms(program, u_view_proj=camera.view_proj_relative(), u_view_rotation=camera.rotation)
        for index in camera_objects(ctx):
            draw_object(ctx, program, index)


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
    import moderngl

    texture = gl.texture((NOISE_SIZE, NOISE_SIZE), 3, rotation_noise())
    texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
    texture.repeat_x = texture.repeat_y = True
    return texture


class SSAOPass(RenderPass):
    name = "ssao"

    def __init__(self, gbuffer, size, settings, dynamic: bool = True):
        self.gbuffer_in = gbuffer
        self.size = size
        self.settings = settings
        self.dynamic = dynamic

    def setup(self, builder):
        builder.read(self.gbuffer_in)
        self.ao = builder.create("ao_raw", ResourceDesc("color", self.size, "r8"))
        return self.ao

    def describe(self) -> str:
        return f"{self.settings.samples} samples, radius {self.settings.radius:g}"

    def execute(self, ctx) -> None:
        import moderngl

        noise = ctx.scene.cached("ssao_noise", _noise_texture)
        ctx.framebuffer([self.ao]).use()
        ctx.gl.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        defines = {"AO_SAMPLES": self.settings.samples}
        if ctx.frame.camera.orthographic:
            defines["ORTHO_CAMERA"] = True
        program = ctx.programs.get("common/fullscreen.vert", "post/ssao.frag", defines)
        bind_texture_units(program)
        ctx.resource(self.gbuffer_in).use(TEXTURE_UNITS["u_gbuffer"])
        noise.use(TEXTURE_UNITS["u_noise"])
        set_uniforms(program, u_kernel=hemisphere_kernel(self.settings.samples).tobytes(),
                     u_projection=ctx.frame.camera.projection, u_screen=self.size,
                     u_radius=self.settings.radius, u_strength=self.settings.strength)
        fullscreen(ctx, program)


class SSAOBlurPass(RenderPass):
    name = "ssao_blur"

    def __init__(self, ao, size, dynamic: bool = True):
        self.ao_in = ao
        self.size = size
        self.dynamic = dynamic

    def setup(self, builder):
        builder.read(self.ao_in)
        self.ao = builder.create("ao", ResourceDesc("color", self.size, "r8"))
        return self.ao

    def execute(self, ctx) -> None:
        import moderngl

        ctx.framebuffer([self.ao]).use()
        ctx.gl.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        program = ctx.programs.get("common/fullscreen.vert", "post/ssao_blur.frag")
        bind_texture_units(program)
        ctx.resource(self.ao_in).use(TEXTURE_UNITS["u_ao"])
        fullscreen(ctx, program)
