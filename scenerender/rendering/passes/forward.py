"""Forward passes from the camera: opaque meshes, outlines, transparent meshes and the
wireframe overlay, all into the (multisampled) colour target (the skybox is passes/sky.py)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import moderngl
import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.resources import GL_FRAMEBUFFER_SRGB
from scenerender.gpu.uniforms import matrix_bytes, set_uniforms
from scenerender.rendering.draw import (
    MESH_VERTEX, begin_camera_pass, bind_light_tables, bind_lights, bind_material,
    bind_texture_units, cull_hidden_faces, draw_item, opaque_items, single_sided_faces, skip_faces, stop_culling, transparent_items,
)
from scenerender.rendering.features import TEXTURE_UNITS, mask_defines
from scenerender.rendering.graph_inputs import InputHandles
from scenerender.rendering.passes.data import ImageData, TargetData
from scenerender.rendering.shadow_reach import around, shadowed_rectangle
from scenerender.rendering.visible_samples import VisibleSamplesPlan, flat_non_occluders, plan_visible_samples

if TYPE_CHECKING:  # only scenes with these load their passes (rendering/pipeline.py)
    from scenerender.rendering.passes.environment import EnvironmentLighting
    from scenerender.rendering.passes.indirect import IndirectLighting

FORWARD_FRAGMENT = "mesh/forward.frag"
DEPTH_ONLY_FRAGMENT = "mesh/depth_only.frag"


@dataclass(frozen=True)
class Shading:
    """What lit shading reads: the world's inputs (InputHandles.shading), plus the shadow
    atlas pages (in page order, none without shadows) and the AO image when the scene has
    them. The lights reach the shaders as the ``lights`` input's buffers, bound in ``bind``."""

    inputs: InputHandles
    atlas_pages: tuple = ()
    ao: Handle | None = None
    visible_samples: bool = False  # shadows averaged over the samples that pass the depth test
    environment: EnvironmentLighting | None = None
    indirect: IndirectLighting | None = None  # render.indirect's probes
    back_pages: tuple = ()  # ((page, handle), ...): solid casters' back faces

    def declare(self, builder) -> None:
        # the shadow views too: where their casters' shadows can fall (shadow_reach.py)
        views = tuple(handle for _, handle in self.inputs.shadow_views) if self.atlas_pages else ()
        builder.read(*self.inputs.shading(), *self.atlas_pages, *(handle for _, handle in self.back_pages),
                     *((self.ao,) if self.ao is not None else ()),
                     *(self.environment.handles() if self.environment is not None else ()),
                     *(self.indirect.handles() if self.indirect is not None else ()), *views)

    def bind(self, ctx) -> None:
        bind_lights(ctx.input(self.inputs.lights))
        bind_light_tables(ctx, self.atlas_pages, self.back_pages)
        if self.ao is not None:
            ctx.image(self.ao).use(TEXTURE_UNITS["u_ao"])
        if self.environment is not None:
            self.environment.bind(ctx)
        if self.indirect is not None:
            self.indirect.bind(ctx)

    def draw(self, ctx, items, mode=None, cull_hidden: bool = False, before_item=None, shadowed: dict | None = None,
             size: tuple = (0, 0), encode_srgb: bool = False) -> None:
        """Shade ``items`` with each material's program variant; ``cull_hidden``: skip the
        faces the camera cannot see (opaque surfaces only), and the back faces of
        single-sided materials; ``before_item(item)``, where given, runs before each draw.
        ``shadowed``: object index -> the screen rectangle (``size`` the target's) outside
        which no shadow falls on it (shadow_reach.py): there it is drawn without them.
        ``encode_srgb``: opaque surfaces write sRGB-encoded values (for an 8-bit sRGB
        target with the device's encoding off)."""
        camera = ctx.input(self.inputs.camera)
        objects = ctx.input(self.inputs.objects)
        materials = ctx.input(self.inputs.materials)
        frame_values = dict(u_view_proj=matrix_bytes(camera.view_proj_relative()),
                            u_ambient=ctx.input(self.inputs.ambient),
                            # only a transparent surface looks the visibility maps up itself where
                            # the visibility pass shares them out (features.interleave_defines)
                            **(self.environment.uniforms(ctx, camera.position,
                                                         any(item.material.transparent for item in items))
                               if self.environment is not None else {}),
                            **(self.indirect.uniforms(camera.position) if self.indirect is not None else {}))
        if self.inputs.fog is not None:
            fog = ctx.input(self.inputs.fog)
            frame_values.update(u_fog_color=fog.color, u_fog_density=fog.density, u_fog_range=fog.range)
        ready = set()  # the programs given frame_values in this draw (many materials share one)

        def prepared(material, shadows: bool = True):
            program = self._program(ctx, material, shadows, encode_srgb)
            if id(program) not in ready:
                set_uniforms(program, **frame_values)
                ready.add(id(program))
            bind_material(program, material, materials)
            return program

        for item in items:
            program = prepared(item.material)
            if cull_hidden:
                cull_faces(ctx.gl, objects, item)
            if before_item is not None:
                before_item(item)
            rectangle = shadowed.get(item.object_index) if shadowed else None
            if rectangle is None:
                draw_item(objects, program, item, mode)
                continue
            # scissor rectangles: every pixel is drawn by exactly one of the draws
            gl = ctx.gl
            if rectangle[2] > rectangle[0] and rectangle[3] > rectangle[1]:
                gl.scissor = (rectangle[0], rectangle[1], rectangle[2] - rectangle[0], rectangle[3] - rectangle[1])
                draw_item(objects, program, item, mode)
            unshadowed = prepared(item.material, shadows=False)
            for x0, y0, x1, y1 in around(rectangle, size):
                gl.scissor = (x0, y0, x1 - x0, y1 - y0)
                draw_item(objects, unshadowed, item, mode)
            gl.scissor = None

    def _program(self, ctx, material, shadows: bool = True, encode_srgb: bool = False):
        """The material's shader variant (worked out on its first draw of the run);
        ``shadows=False``: the same without any shadow lookup; ``encode_srgb``: writing
        sRGB-encoded values."""
        with_ao = self.ao is not None

        def make():
            defines = ctx.features.forward_defines(material, with_ao)
            if not shadows:
                defines.pop("HAS_SHADOWS", None)
            if self.visible_samples and "HAS_SHADOWS" in defines:
                defines["SHADOW_VISIBLE_SAMPLES"] = True
            if encode_srgb:
                defines["ENCODE_SRGB"] = True
            if self.indirect is not None and "UNLIT" not in defines:
                defines.update(self.indirect.defines())
            program = ctx.programs.get(MESH_VERTEX, FORWARD_FRAGMENT, defines)
            bind_texture_units(program)
            return program

        return ctx.programs.memo(("forward", id(material), with_ao, self.visible_samples, shadows, encode_srgb), make)

    def shadow_free(self, ctx, items, camera, size: tuple) -> dict:
        """Object index -> screen rectangle (shadow_reach.shadowed_rectangle) for each flat
        receiver of ``items`` that casts no shadow itself, where every shadowed light is an
        unsized directional one (its lookup is the plain filtered one); {} elsewhere."""
        features = ctx.features
        if not self.atlas_pages or features.soft_shadows or any(features.dir_sized):
            return {}
        objects = ctx.input(self.inputs.objects)
        receivers = [i for i in flat_non_occluders(objects, camera, items) if not objects.definitions[i].cast_shadows]
        if not receivers:
            return {}
        views = [(view, view.tile.size) for _, handle in self.inputs.shadow_views for view in ctx.input(handle).views]
        casters = objects.shadow_casters()
        bounds = np.array([objects.frames[i].bounds for i in casters], dtype=np.float64).reshape(-1, 2, 3)
        pcf = max(features.dir_shadow_taps, default=1) + 1
        found = {}
        for index in receivers:
            lo, hi = np.asarray(objects.frames[index].bounds, dtype=np.float64)
            axis = int(np.argmin(hi - lo))
            rectangle = shadowed_rectangle(views, bounds, axis, 0.5 * (lo[axis] + hi[axis]), camera, size, pcf)
            if rectangle is not None and rectangle != (0, 0, size[0], size[1]):
                found[index] = rectangle
        return found


def cull_faces(gl, objects, item) -> None:
    """Before drawing ``item`` opaque from the camera: skip the faces it does not show, the
    back faces of a single-sided material, else those the camera cannot see."""
    if item.material.double_sided:
        cull_hidden_faces(gl, objects, item.object_index)
    else:
        skip_faces(gl, single_sided_faces(objects, item.object_index))


@dataclass(frozen=True)
class OpaquePass(RenderPass):
    """Clears to the background and draws every opaque surface, lit and shadowed.

    fill: "solid", or "wireframe" / "points" for those render modes (drawn with
    ``line_width`` / ``point_size``). color_format: "rgba16f", or "srgba8" where no value
    above 1 is needed. encode_in_shader (an "srgba8" target only): the shaders write the
    exact sRGB encoding, the device's own turned off while they draw (the builder's
    choice: pipeline.shader_encoding_pays). prepass: lay down depth first (see
    pipeline.prepass_pays).
    sky_behind: the resolve adds the sky behind the samples (passes/sky.py), so the
    target is cleared to transparent black instead of the background.
    """

    size: tuple
    samples: int
    shading: Shading
    background: Handle
    fill: str = "solid"
    prepass: bool = False
    color_format: str = "rgba16f"
    line_width: float = 1.0
    point_size: float = 3.0
    sky_behind: bool = False
    encode_in_shader: bool = False

    name = "opaque"

    def setup(self, builder) -> TargetData:
        self.shading.declare(builder)
        if not self.sky_behind:
            builder.read(self.background)
        samples = self.samples if self.samples > 1 else 0
        name = "hdr_color" if self.color_format == "rgba16f" else "color"
        return TargetData(builder.create(name, ResourceDesc("color", self.size, self.color_format, samples)),
                          builder.create("depth", ResourceDesc("depth", self.size, "camera_depth", samples)))

    def describe(self) -> str:
        extras = [f"{self.samples}x MSAA" if self.samples > 1 else "no MSAA",
                  "float16 target" if self.color_format == "rgba16f"
                  else "8-bit sRGB target" + (", encoded by the shader" if self.encode_in_shader else "")]
        if self.fill != "solid":
            extras.append(self.fill)
        elif self.prepass:
            extras.append("depth prepass")
        if self.shading.atlas_pages:
            extras.append("shadows over the visible samples" if self.shading.visible_samples else "shadows")
        if self.shading.ao is not None:
            extras.append("AO")
        return ", ".join(extras)

    def execute(self, ctx, data: TargetData) -> None:
        gl = ctx.gl
        clear = (0.0, 0.0, 0.0, 0.0) if self.sky_behind else (*ctx.input(self.background)[:3], 1.0)
        fbo = begin_camera_pass(ctx, [data.color], data.depth, clear)  # the clear encoded by the device
        self.shading.bind(ctx)
        mode = None
        if self.fill == "wireframe":
            gl.wireframe = True
        elif self.fill == "points":
            mode = moderngl.POINTS
            gl.point_size = self.point_size
        gl.line_width = self.line_width
        items = opaque_items(ctx.input(self.shading.inputs.objects), ctx.input(self.shading.inputs.camera))
        solid = self.fill == "solid"  # wireframes and points show every face's edges
        shadowed = self.shading.shadow_free(ctx, items, ctx.input(self.shading.inputs.camera), self.size) if solid else {}
        encode = self.encode_in_shader
        try:
            if encode:
                gl.disable_direct(GL_FRAMEBUFFER_SRGB)
            plan = self._depth_prepass(ctx, items, fbo) if self.prepass else None
            if plan is None or plan.prepass_is_everything:
                self.shading.draw(ctx, plan.order if plan else items, mode, cull_hidden=solid, shadowed=shadowed,
                                  size=self.size, encode_srgb=encode)
            else:
                # the depth of what the prepass left out is written as it is shaded; what it
                # drew keeps its own (an alpha-masked surface's holes must stay empty)
                def depth_writes(item):
                    fbo.depth_mask = item.object_index not in plan.prepass
                self.shading.draw(ctx, plan.order, mode, cull_hidden=solid, before_item=depth_writes,
                                  shadowed=shadowed, size=self.size, encode_srgb=encode)
        finally:
            if encode:
                gl.enable_direct(GL_FRAMEBUFFER_SRGB)
            stop_culling(gl)
            gl.wireframe = False
            fbo.color_mask = (True, True, True, True)
            fbo.depth_mask = True
            gl.depth_func = ctx.depth.nearer

    def _depth_prepass(self, ctx, items, fbo) -> VisibleSamplesPlan:
        """Lay down depth for the opaque items without shading, then leave the depth test at
        'equal or nearer': the shading draw that follows runs the expensive fragment shader
        only for the surface each pixel finally shows, and with visible samples its
        post-depth coverage names the samples where that surface is seen. Returns the plan:
        the items in the order the shading draw takes them, and what the prepass drew.

        For visible samples alone, the prepass draws only what rendering/visible_samples.py
        says it must, and the shading draw writes the depth of the rest itself."""
        objects = ctx.input(self.shading.inputs.objects)
        camera = ctx.input(self.shading.inputs.camera)
        if self.shading.visible_samples:
            plan = plan_visible_samples(objects, camera, items, objects.gpu.memory("visible samples"))
        else:
            plan = VisibleSamplesPlan(items, frozenset(item.object_index for item in items))
        view_proj = camera.view_proj_relative()
        program = ctx.programs.get(MESH_VERTEX, DEPTH_ONLY_FRAGMENT)
        set_uniforms(program, u_view_proj=view_proj)
        materials = ctx.input(self.shading.inputs.materials)
        fbo.color_mask = (False, False, False, False)
        for item in items:
            if item.object_index not in plan.prepass:
                continue
            cull_faces(ctx.gl, objects, item)
            draw_item(objects, self._depth_program(ctx, program, item.material, materials, view_proj), item)
        stop_culling(ctx.gl)
        fbo.color_mask = (True, True, True, True)
        fbo.depth_mask = False
        ctx.gl.depth_func = ctx.depth.nearer_or_equal
        return plan

    @staticmethod
    def _depth_program(ctx, program, material, materials, view_proj):
        """``program``, or for an alpha-masked material (glTF MASK) its variant that cuts
        the same pixels away as the shading draw does: a hole must hold no depth, or the
        shading draw's discard leaves the target's clear colour there."""
        if not material.masked:
            return program
        masked = ctx.programs.get(MESH_VERTEX, DEPTH_ONLY_FRAGMENT, mask_defines(material))
        bind_texture_units(masked)
        set_uniforms(masked, u_view_proj=view_proj)
        bind_material(masked, material, materials)
        return masked


def begin_fill(gl, fill: str, line_width: float, point_size: float):
    """Set ``gl`` up to draw surfaces as ``fill`` ("solid", "wireframe": their edges, or
    "points": their vertices) and return the primitive to draw with (None: the mesh's own
    triangles). Callers end with ``gl.wireframe = False``."""
    gl.line_width = line_width
    if fill == "wireframe":
        gl.wireframe = True
    elif fill == "points":
        gl.point_size = point_size
        return moderngl.POINTS
    return None


@dataclass(frozen=True)
class OutlinePass(RenderPass):
    """Selection outlines: each outlined object's back faces, pushed out along the normals
    and drawn in a flat colour; the object itself hides all but the rim. In the wireframe
    and points modes (``fill``) the pushed-out faces are drawn as edges or points too."""

    color: Handle
    depth: Handle
    camera: Handle
    objects: Handle
    outlines: Handle
    fill: str = "solid"
    line_width: float = 1.0
    point_size: float = 3.0

    name = "outline"

    def setup(self, builder) -> ImageData:
        builder.read(self.depth, self.camera, self.objects, self.outlines)
        return ImageData(builder.write(self.color))

    def execute(self, ctx, data: ImageData) -> None:
        gl = ctx.gl
        ctx.framebuffer([data.image], self.depth).use()
        program = ctx.programs.get(MESH_VERTEX, "mesh/solid_color.frag", {"OUTLINE": True})
        gl.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        gl.depth_func = ctx.depth.nearer
        gl.disable(moderngl.BLEND)
        gl.cull_face = "front"
        set_uniforms(program, u_view_proj=ctx.input(self.camera).view_proj_relative())
        objects = ctx.input(self.objects)
        outlines = ctx.input(self.outlines)
        mode = begin_fill(gl, self.fill, self.line_width, self.point_size)
        try:
            for index in objects.in_camera_view():
                if index in outlines:
                    color, width = outlines[index]
                    set_uniforms(program, u_color=color, u_outline_width=width)
                    objects.draw(program, index, mode=mode, welded_normals=True)
        finally:
            gl.wireframe = False
            gl.disable(moderngl.CULL_FACE)
            gl.cull_face = "back"


@dataclass(frozen=True)
class TransparentPass(RenderPass):
    """Transparent surfaces after everything opaque, sorted far to near, blended, with depth
    test but no depth writes. Each object draws its back faces first, then its front faces,
    which orders a convex object's own surfaces correctly. In the wireframe and points modes
    (``fill``) each object draws every face once as edges or points, as opaque ones do.
    ``transmission``: the copy of the opaque scene transmissive surfaces see through
    (passes/transmission.py), where the scene has any."""

    color: Handle
    depth: Handle
    shading: Shading
    fill: str = "solid"
    line_width: float = 1.0
    point_size: float = 3.0
    transmission: Handle | None = None

    name = "transparent"

    def describe(self) -> str:
        extras = [] if self.fill == "solid" else [self.fill]
        if self.transmission is not None:
            extras.append("transmission")
        return ", ".join(extras)

    def setup(self, builder) -> ImageData:
        builder.read(self.depth)
        if self.transmission is not None:
            builder.read(self.transmission)
        self.shading.declare(builder)
        return ImageData(builder.write(self.color))

    def execute(self, ctx, data: ImageData) -> None:
        gl = ctx.gl
        fbo = ctx.framebuffer([data.image], self.depth)
        fbo.use()
        fbo.depth_mask = False
        gl.enable(moderngl.DEPTH_TEST | moderngl.BLEND)
        gl.depth_func = ctx.depth.nearer
        # colour "over" what is there; alpha accumulates coverage, which the resolve's
        # sky-behind needs (passes/sky.py): a + (1 - a) * a_dst
        gl.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA
        self.shading.bind(ctx)
        if self.transmission is not None:
            ctx.image(self.transmission).use(TEXTURE_UNITS["u_transmission_source"])
        items = transparent_items(ctx.input(self.shading.inputs.objects), ctx.input(self.shading.inputs.camera))
        objects = ctx.input(self.shading.inputs.objects)
        mode = begin_fill(gl, self.fill, self.line_width, self.point_size)
        try:
            for item in items:
                if self.fill != "solid":  # edges and points: every face once, as the opaque pass draws them
                    self.shading.draw(ctx, [item], mode)
                    continue
                gl.enable(moderngl.CULL_FACE)
                hidden = None if item.material.double_sided else single_sided_faces(objects, item.object_index)
                # cull front = draw back faces first; a single-sided surface shows one side
                for side in ("front", "back") if hidden is None else (hidden,):
                    gl.cull_face = side
                    self.shading.draw(ctx, [item])
        finally:
            fbo.depth_mask = True
            gl.wireframe = False
            gl.disable(moderngl.BLEND | moderngl.CULL_FACE)
            gl.cull_face = "back"


@dataclass(frozen=True)
class WireframeOverlayPass(RenderPass):
    """Mesh edges drawn over the shaded image (``render.wireframe_overlay``)."""

    color: Handle
    depth: Handle
    camera: Handle
    objects: Handle
    line_width: float = 1.0

    name = "wireframe_overlay"

    def setup(self, builder) -> ImageData:
        builder.read(self.depth, self.camera, self.objects)
        return ImageData(builder.write(self.color))

    def execute(self, ctx, data: ImageData) -> None:
        gl = ctx.gl
        ctx.framebuffer([data.image], self.depth).use()
        program = ctx.programs.get(MESH_VERTEX, "mesh/solid_color.frag",
                                   {"DEPTH_NUDGE": True, **({"REVERSED_DEPTH": True} if ctx.depth.reversed else {})})
        gl.enable(moderngl.DEPTH_TEST)
        gl.depth_func = ctx.depth.nearer_or_equal
        gl.wireframe = True
        gl.line_width = self.line_width
        set_uniforms(program, u_view_proj=ctx.input(self.camera).view_proj_relative(), u_color=(0.0, 0.0, 0.0, 1.0))
        objects = ctx.input(self.objects)
        try:
            for index in objects.in_camera_view():
                objects.draw(program, index)
        finally:
            gl.wireframe = False
            gl.depth_func = ctx.depth.nearer
