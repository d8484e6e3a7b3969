"""Depth of field by gathering (``render.depth_of_field: gather``): the fast method. The
resolved linear image is blurred by each pixel's thin-lens circle of confusion, from the
geometry prepass's linear depth (docs/scene-notes.md, "Depth of field"), in one full-screen
pass, in the manner of Jimenez's gather ("Next-generation post-processing in Call of Duty",
2014) without its tiles, its half resolution and its near-field pass. Where the sub-frames
average views from points of the lens, this blurs one view: what a blurred near edge
hides stays hidden, and a blurred near edge does not spread over a sharp background.
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
class DepthOfFieldGatherPass(RenderPass):
    """The gather blur of ``color`` (linear, single-sampled) by ``gbuffer``'s depth."""

    color: Handle
    gbuffer: Handle
    camera: Handle
    lens: Handle
    size: tuple

    name = "depth_of_field"

    def setup(self, builder) -> ImageData:
        builder.read(self.color, self.gbuffer, self.camera, self.lens)
        return ImageData(builder.create("focused", ResourceDesc("color", self.size, "rgba16f")))

    def describe(self) -> str:
        return f"gather, {GATHER_TAPS} taps, circles up to {MAX_COC_RADIUS:g} px"

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(FULLSCREEN_VERTEX, "post/dof_gather.frag", {"TAPS": GATHER_TAPS})
        bind_texture_units(program)
        ctx.image(self.color).use(TEXTURE_UNITS["u_color"])
        ctx.image(self.gbuffer).use(TEXTURE_UNITS["u_gbuffer"])
        camera, lens = ctx.input(self.camera), ctx.input(self.lens)
        set_uniforms(program, u_coc_scale=coc_scale(camera, lens, self.size[0]), u_inv_focus=1.0 / lens.focus,
                     u_max_radius=MAX_COC_RADIUS)
        ctx.fullscreen(program)
