"""The data render modes: depth, normals, ambient_occlusion, shadow and light_depth.
Each writes plain values (no output transform) into an 8-bit image."""
from __future__ import annotations

import numpy as np

from scenerender.graph import ResourceDesc, RenderPass
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import (
    begin_camera_pass, bind_shadow_atlas, bind_texture_units, camera_objects, draw_object,
)
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.forward import MESH_VERTEX, fullscreen


class _FullscreenView(RenderPass):
    """A full-screen pass from one input texture into an rgba8 image."""

    fragment = ""
    input_unit = ""

    def __init__(self, source, size, dynamic: bool = True):
        self.source = source
        self.size = size
        self.dynamic = dynamic

    def setup(self, builder):
        builder.read(self.source)
        self.ldr = builder.create("view", ResourceDesc("color", self.size, "rgba8"))
        return self.ldr

    def uniforms(self, ctx, program) -> None:
        """Extra uniforms of the view."""

    def execute(self, ctx) -> None:
        import moderngl

        ctx.framebuffer([self.ldr]).use()
        ctx.gl.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        program = ctx.programs.get("common/fullscreen.vert", self.fragment)
        bind_texture_units(program)
        ctx.resource(self.source).use(TEXTURE_UNITS[self.input_unit])
        self.uniforms(ctx, program)
        fullscreen(ctx, program)


class DepthViewPass(_FullscreenView):
    name = "view:depth"
    fragment = "views/depth.frag"
    input_unit = "u_gbuffer"

    def uniforms(self, ctx, program) -> None:
        set_uniforms(program, u_near_far=(ctx.frame.camera.near, ctx.frame.camera.far))


class NormalsViewPass(_FullscreenView):
    name = "view:normals"
    fragment = "views/normals.frag"
    input_unit = "u_gbuffer"

    def uniforms(self, ctx, program) -> None:
        set_uniforms(program, u_view_rotation=ctx.frame.camera.rotation)


class AmbientOcclusionViewPass(_FullscreenView):
    name = "view:ambient_occlusion"
    fragment = "views/ambient_occlusion.frag"
    input_unit = "u_ao"


def _raw_depth_sampler(gl):
    """Reads depth values as they are (no comparison), for showing a shadow map."""
    import moderngl

    return gl.sampler(filter=(moderngl.NEAREST, moderngl.NEAREST), compare_func="", repeat_x=False, repeat_y=False)


class LightDepthViewPass(_FullscreenView):
    """The first shadowed light's depth map(s) as seen from the light."""

    name = "view:light_depth"
    fragment = "views/light_depth.frag"
    input_unit = "u_atlas"

    def __init__(self, atlas, size, light_index: int, atlas_size, dynamic: bool = True):
        super().__init__(atlas, size, dynamic)
        self.light_index = light_index
        self.atlas_size = atlas_size

    def execute(self, ctx) -> None:
        sampler = ctx.scene.cached("raw_depth_sampler", _raw_depth_sampler)
        sampler.use(TEXTURE_UNITS["u_atlas"])
        try:
            super().execute(ctx)
        finally:
            sampler.clear(TEXTURE_UNITS["u_atlas"])

    def uniforms(self, ctx, program) -> None:
        width, height = self.atlas_size
        views = ctx.frame.shadow_views[self.light_index]
        tiles = np.zeros((6, 4), dtype=np.float32)
        for i, view in enumerate(views):
            t = view.tile
            tiles[i] = (t.x / width, t.y / height, t.size / width, t.size / height)
        set_uniforms(program, u_tiles=tiles.tobytes(), u_tile_count=len(views))


class ShadowFactorViewPass(RenderPass):
    """How much of the first shadowed light reaches each visible surface."""

    name = "view:shadow"

    def __init__(self, atlas, size, light_index: int, dynamic: bool = True):
        self.atlas = atlas
        self.size = size
        self.light_index = light_index
        self.dynamic = dynamic

    def setup(self, builder):
        builder.read(self.atlas)
        self.ldr = builder.create("view", ResourceDesc("color", self.size, "rgba8"))
        self.depth = builder.create("view_depth", ResourceDesc("depth", self.size, "camera_depth"))
        return self.ldr

    def execute(self, ctx) -> None:
        begin_camera_pass(ctx, [self.ldr], self.depth, (1.0, 1.0, 1.0, 1.0))
        bind_shadow_atlas(ctx, self.atlas)
        program = ctx.programs.get(MESH_VERTEX, "views/shadow_factor.frag")
        bind_texture_units(program)
        light = ctx.frame.lights[self.light_index]
        point = light.kind == "point"
        vector = (light.position - ctx.frame.camera.position) if point else light.direction
        set_uniforms(program, u_view_proj=ctx.frame.camera.view_proj_relative(),
                     u_first_view=ctx.scene.first_shadow_view[self.light_index], u_point_light=int(point),
                     u_light_vector=vector)
        for index in camera_objects(ctx):
            draw_object(ctx, program, index)
