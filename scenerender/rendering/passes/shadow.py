"""Shadow maps: the scene's depth from one light into that light's tiles of the atlas."""
from __future__ import annotations

import numpy as np

from scenerender.graph import ResourceDesc, RenderPass
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import draw_object, light_objects


class ShadowMapPass(RenderPass):
    """Renders the shadow casters' depth from light ``light_index`` (index among the
    frame's non-ambient lights). The first shadow pass creates the atlas; later ones write
    their own tiles of it and leave the others untouched."""

    def __init__(self, light_index: int, light, atlas_layout, atlas_in=None, dynamic: bool = True):
        self.light_index = light_index
        self.light = light
        self.layout = atlas_layout
        self.atlas_in = atlas_in
        self.dynamic = dynamic
        self.name = f"shadow:{light.name}"

    def setup(self, builder):
        if self.atlas_in is None:
            self.atlas = builder.create("shadow_atlas", ResourceDesc("depth", self.layout.size, "depth24"))
        else:
            self.atlas = builder.write(self.atlas_in)
        return self.atlas

    def describe(self) -> str:
        views = "6 cube faces" if self.light.kind == "point" else "1 view"
        return f"{self.light.kind} light, {views}, {self.light.shadow.size}px, pcf {self.light.shadow.pcf}"

    def execute(self, ctx) -> None:
        import moderngl

        gl = ctx.gl
        fbo = ctx.framebuffer([], self.atlas)
        fbo.use()
        # directional views are orthographic: window depth is linear depth already (their
        # range spans every caster and receiver, so nothing needs the shader's clamp)
        defines = {"point": {"RADIAL_DEPTH": True}, "directional": {"ORTHOGRAPHIC": True}}.get(self.light.kind, {})
        program = ctx.programs.get("shadow/depth.vert", "shadow/depth.frag", defines)
        gl.enable(moderngl.DEPTH_TEST)
        gl.depth_func = "<"  # the atlas keeps linear depth, nearest = 0, whatever the camera's convention
        gl.disable(moderngl.BLEND | moderngl.CULL_FACE)
        to_world = np.eye(4)
        to_world[:3, 3] = ctx.frame.camera.position
        casters = light_objects(ctx)
        for view in ctx.frame.shadow_views[self.light_index]:
            tile = view.tile
            region = (tile.x, tile.y, tile.size, tile.size)
            fbo.viewport = region
            fbo.clear(depth=1.0, viewport=region)
            set_uniforms(program, u_light_view=view.view @ to_world, u_light_projection=ctx.depth.clip_projection(view.projection),
                         u_depth_range=(view.near, view.far))
            for index in casters:
                draw_object(ctx, program, index, all_instances=True)
