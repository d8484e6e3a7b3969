"""Forward passes from the camera: opaque meshes, skybox, outlines, transparent meshes and
the wireframe overlay, all into the (multisampled) HDR colour target."""
from __future__ import annotations

import numpy as np

from scenerender.graph import ResourceDesc, RenderPass
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import (
    begin_camera_pass, bind_material, bind_shadow_atlas, bind_texture_units, camera_objects, draw_item,
    draw_object, opaque_items, transparent_items,
)
from scenerender.rendering.features import TEXTURE_UNITS

MESH_VERTEX = "mesh/mesh.vert"
FORWARD_FRAGMENT = "mesh/forward.frag"


def _camera_uniforms(ctx, program) -> None:
    set_uniforms(program, u_view_proj=ctx.frame.camera.view_proj_relative(), u_ambient=ctx.frame.ambient)


def _fog_uniforms(ctx, program) -> None:
    fog = ctx.world.render.fog
    if fog is not None:
        set_uniforms(program, u_fog_color=ctx.frame.fog_color, u_fog_density=ctx.frame.fog_density,
                     u_fog_range=(fog.start, fog.end))


def _bind_shared_inputs(ctx, atlas, ao) -> None:
    if atlas is not None:
        bind_shadow_atlas(ctx, atlas)
    if ao is not None:
        ctx.resource(ao).use(TEXTURE_UNITS["u_ao"])


def forward_program(ctx, material, with_ao: bool):
    """The material's shader variant (worked out on its first draw of the run)."""
    def make():
        program = ctx.programs.get(MESH_VERTEX, FORWARD_FRAGMENT, ctx.features.forward_defines(material, with_ao))
        bind_texture_units(program)
        return program

    return ctx.programs.memo(("forward", id(material), with_ao), make)


def draw_shaded(ctx, items, with_ao: bool, mode=None) -> None:
    """Shade ``items`` with each material's program variant."""
    for item in items:
        program = forward_program(ctx, item.material, with_ao)
        _camera_uniforms(ctx, program)
        _fog_uniforms(ctx, program)
        bind_material(ctx, program, item.material)
        draw_item(ctx, program, item, mode)


class OpaquePass(RenderPass):
    """Clears to the background and draws every opaque surface, lit and shadowed.

    ``fill``: "solid", or "wireframe" / "points" for those render modes.
    """

    name = "opaque"

    def __init__(self, size, samples: int, atlas=None, ao=None, fill: str = "solid", dynamic: bool = True,
                 prepass: bool = True, color_format: str = "rgba16f"):
        self.size = size
        self.color_format = color_format  # "rgba16f", or "srgba8" where no value above 1 is needed
        self.prepass = prepass and fill == "solid"
        self.samples = samples
        self.atlas = atlas
        self.ao = ao
        self.fill = fill
        self.dynamic = dynamic

    def setup(self, builder):
        for handle in (self.atlas, self.ao):
            if handle is not None:
                builder.read(handle)
        samples = self.samples if self.samples > 1 else 0
        name = "hdr_color" if self.color_format == "rgba16f" else "color"
        self.color = builder.create(name, ResourceDesc("color", self.size, self.color_format, samples))
        self.depth = builder.create("depth", ResourceDesc("depth", self.size, "camera_depth", samples))
        return self.color, self.depth

    def describe(self) -> str:
        extras = [f"{self.samples}x MSAA" if self.samples > 1 else "no MSAA",
                  "float16 target" if self.color_format == "rgba16f" else "8-bit sRGB target"]
        if self.fill != "solid":
            extras.append(self.fill)
        elif self.prepass:
            extras.append("depth prepass")
        if self.atlas is not None:
            extras.append("shadows")
        if self.ao is not None:
            extras.append("AO")
        return ", ".join(extras)

    def execute(self, ctx) -> None:
        import moderngl

        gl = ctx.gl
        fbo = begin_camera_pass(ctx, [self.color], self.depth, (*ctx.frame.background[:3], 1.0))
        _bind_shared_inputs(ctx, self.atlas, self.ao)
        mode = None
        if self.fill == "wireframe":
            gl.wireframe = True
        elif self.fill == "points":
            mode = moderngl.POINTS
            gl.point_size = ctx.world.render.point_size
        gl.line_width = ctx.world.render.line_width
        items = opaque_items(ctx.world, ctx.frame)
        try:
            if self.prepass:
                depth_prepass(ctx, items, fbo)
            draw_shaded(ctx, items, self.ao is not None, mode)
        finally:
            gl.wireframe = False
            fbo.color_mask = (True, True, True, True)
            fbo.depth_mask = True
            gl.depth_func = ctx.depth.nearer


class DrawOverPass(RenderPass):
    """A pass that draws over the opaque pass's colour, depth-tested against its depth.
    ``inputs`` are further resources it samples (shadow atlas, AO)."""

    def __init__(self, color, depth, *inputs, dynamic: bool = True):
        self.color_in, self.depth_in = color, depth
        self.inputs = [h for h in inputs if h is not None]
        self.dynamic = dynamic

    def setup(self, builder):
        for handle in [self.depth_in, *self.inputs]:
            builder.read(handle)
        self.color = builder.write(self.color_in)
        return self.color


class SkyboxPass(DrawOverPass):
    """Draws the cube-map sky where nothing else was drawn (depth still at the far plane)."""

    name = "skybox"

    def execute(self, ctx) -> None:
        import moderngl

        gl = ctx.gl
        fbo = ctx.framebuffer([self.color], self.depth_in)
        fbo.use()
        gl.enable(moderngl.DEPTH_TEST)
        gl.depth_func = ctx.depth.nearer_or_equal
        program = ctx.programs.get("skybox/skybox.vert", "skybox/skybox.frag")
        bind_texture_units(program)
        set_uniforms(program, u_inverse_view_proj=np.linalg.inv(ctx.frame.camera.view_proj_relative()),
                     u_ndc_near_far=ctx.depth.ndc_near_far)
        ctx.scene.skybox.use(TEXTURE_UNITS["u_skybox"])
        fullscreen(ctx, program)
        gl.depth_func = ctx.depth.nearer


class OutlinePass(DrawOverPass):
    """Selection outlines: each outlined object's back faces, pushed out along the normals
    and drawn in a flat colour; the object itself hides all but the rim."""

    name = "outline"

    def execute(self, ctx) -> None:
        import moderngl

        gl = ctx.gl
        ctx.framebuffer([self.color], self.depth_in).use()
        program = ctx.programs.get(MESH_VERTEX, "mesh/solid_color.frag", {"OUTLINE": True})
        gl.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        gl.depth_func = ctx.depth.nearer
        gl.disable(moderngl.BLEND)
        gl.cull_face = "front"
        set_uniforms(program, u_view_proj=ctx.frame.camera.view_proj_relative())
        for index in camera_objects(ctx):
            obj = ctx.world.objects[index]
            if obj.outline is None:
                continue
            set_uniforms(program, u_color=np.asarray(obj.outline.color(ctx.frame.time)),
                         u_outline_width=obj.outline.width)
            draw_object(ctx, program, index, welded_normals=True)
        gl.disable(moderngl.CULL_FACE)
        gl.cull_face = "back"


class TransparentPass(DrawOverPass):
    """Transparent surfaces after everything opaque, sorted far to near, blended, with depth
    test but no depth writes. Each object draws its back faces first, then its front faces,
    which orders a convex object's own surfaces correctly."""

    name = "transparent"

    def __init__(self, color, depth, atlas=None, ao=None, dynamic: bool = True):
        super().__init__(color, depth, atlas, ao, dynamic=dynamic)
        self.atlas, self.ao = atlas, ao

    def execute(self, ctx) -> None:
        import moderngl

        gl = ctx.gl
        fbo = ctx.framebuffer([self.color], self.depth_in)
        fbo.use()
        fbo.depth_mask = False
        gl.enable(moderngl.DEPTH_TEST | moderngl.BLEND | moderngl.CULL_FACE)
        gl.depth_func = ctx.depth.nearer
        gl.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        _bind_shared_inputs(ctx, self.atlas, self.ao)
        try:
            for item in transparent_items(ctx.world, ctx.frame):
                for side in ("front", "back"):  # cull front = draw back faces first
                    gl.cull_face = side
                    draw_shaded(ctx, [item], self.ao is not None)
        finally:
            fbo.depth_mask = True
            gl.disable(moderngl.BLEND | moderngl.CULL_FACE)
            gl.cull_face = "back"


class WireframeOverlayPass(DrawOverPass):
    """Mesh edges drawn over the shaded image (``render.wireframe_overlay``)."""

    name = "wireframe_overlay"

    def execute(self, ctx) -> None:
        import moderngl

        gl = ctx.gl
        ctx.framebuffer([self.color], self.depth_in).use()
        program = ctx.programs.get(MESH_VERTEX, "mesh/solid_color.frag",
                                   {"DEPTH_NUDGE": True, **({"REVERSED_DEPTH": True} if ctx.depth.reversed else {})})
        gl.enable(moderngl.DEPTH_TEST)
        gl.depth_func = ctx.depth.nearer_or_equal
        gl.wireframe = True
        gl.line_width = ctx.world.render.line_width
        set_uniforms(program, u_view_proj=ctx.frame.camera.view_proj_relative(), u_color=(0.0, 0.0, 0.0, 1.0))
        try:
            for index in camera_objects(ctx):
                draw_object(ctx, program, index)
        finally:
            gl.wireframe = False
            gl.depth_func = ctx.depth.nearer


def depth_prepass(ctx, items, fbo) -> None:
    """Lay down depth for every opaque item without shading, then leave the depth test at
    'equal or nearer' with depth writes off: the shading draw that follows runs the
    expensive fragment shader only for the surface each pixel finally shows."""
    program = ctx.programs.get(MESH_VERTEX, "mesh/depth_only.frag")
    set_uniforms(program, u_view_proj=ctx.frame.camera.view_proj_relative())
    fbo.color_mask = (False, False, False, False)
    for item in items:
        draw_item(ctx, program, item)
    fbo.color_mask = (True, True, True, True)
    fbo.depth_mask = False
    ctx.gl.depth_func = ctx.depth.nearer_or_equal


def fullscreen(ctx, program) -> None:
    """Draw one viewport-covering triangle with ``program`` (no vertex buffers)."""
    ctx.scene.fullscreen_array(program).render(vertices=3)
