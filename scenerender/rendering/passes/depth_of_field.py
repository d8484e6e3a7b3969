"""Depth of field by gathering (``render.depth_of_field: gather``): the fast method. The
resolved linear image is blurred by each pixel's thin-lens circle of confusion, from the
geometry prepass's linear depth (docs/scene-notes.md, "Depth of field"), in the manner of
Jimenez's gather ("Next-generation post-processing in Call of Duty", 2014) without its
tiles, its half resolution and its near-field pass: one full-screen pass gives each pixel
the nearest depth of its 3 x 3 neighbours (an edge pixel's colour holds the nearer
surface's light, which must spread as that surface does), a second gathers. Where the
sub-frames average views from points of the lens, this blurs one view: what a blurred near
edge hides stays hidden, and a blurred near edge does not spread over a sharp background.
"""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import FULLSCREEN_VERTEX, begin_fullscreen_pass, bind_texture_units
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.data import ImageData

# Points of the gather's spiral over a pixel's circle of confusion, and the largest circle
# (radius in pixels): blur beyond it is cut to it.
GATHER_TAPS = 48
MAX_COC_RADIUS = 16.0


def coc_scale(camera, lens, width: int) -> float:
    """Pixels of circle-of-confusion radius per unit of |1/focus - 1/z|: the lens radius
    times the projection's x scale, in pixels (world.lens.through_lens)."""
    return lens.radius * camera.projection[0, 0] * width / 2.0


@dataclass(frozen=True)
class LensDepthPass(RenderPass):
    """Each pixel's inverse linear view depth for the gather: the nearest of ``gbuffer``'s
    3 x 3 around it (0: nothing drawn), into an r32f image."""

    gbuffer: Handle
    size: tuple

    name = "lens_depth"

    def setup(self, builder) -> ImageData:
        builder.read(self.gbuffer)
        return ImageData(builder.create("lens_depth", ResourceDesc("color", self.size, "r32f")))

    def describe(self) -> str:
        return "the nearest depth of each pixel's 3 x 3"

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(FULLSCREEN_VERTEX, "post/dof_nearest.frag")
        bind_texture_units(program)
        ctx.image(self.gbuffer).use(TEXTURE_UNITS["u_gbuffer"])
        ctx.fullscreen(program)


@dataclass(frozen=True)
class DepthOfFieldGatherPass(RenderPass):
    """The gather blur of ``color`` (linear, single-sampled) by ``lens_depth``
    (LensDepthPass)."""

    color: Handle
    lens_depth: Handle
    camera: Handle
    lens: Handle
    size: tuple

    name = "depth_of_field"

    def setup(self, builder) -> ImageData:
        builder.read(self.color, self.lens_depth, self.camera, self.lens)
        return ImageData(builder.create("focused", ResourceDesc("color", self.size, "rgba16f")))

    def describe(self) -> str:
        return f"gather, {GATHER_TAPS} taps, circles up to {MAX_COC_RADIUS:g} px"

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(FULLSCREEN_VERTEX, "post/dof_gather.frag", {"TAPS": GATHER_TAPS})
        bind_texture_units(program)
        ctx.image(self.color).use(TEXTURE_UNITS["u_color"])
        ctx.image(self.lens_depth).use(TEXTURE_UNITS["u_lens_depth"])
        camera, lens = ctx.input(self.camera), ctx.input(self.lens)
        set_uniforms(program, u_coc_scale=coc_scale(camera, lens, self.size[0]), u_inv_focus=1.0 / lens.focus,
                     u_max_radius=MAX_COC_RADIUS)
        ctx.fullscreen(program)


def add_depth_of_field(graph, color: Handle, gbuffer: Handle, inputs, size: tuple) -> Handle:
    """The passes of the gather blur of ``color`` (resolved linear light) by ``gbuffer``
    (the geometry prepass); its result."""
    lens_depth = graph.add(LensDepthPass(gbuffer, size)).image
    return graph.add(DepthOfFieldGatherPass(color, lens_depth, inputs.camera, inputs.lens, size)).image
