"""The copy of the opaque scene that transmissive materials see through
(KHR_materials_transmission; docs/scene-notes.md, "Transmission and volume").

After everything opaque (and the sky) is drawn, this pass resolves the camera's colour
into a single-sampled float image and builds its mip chain; the transparent pass then
shades each transmissive surface by looking that image up where the refracted ray leaves
it, at a level chosen by the surface's roughness (shaders/lighting/transmission.glsl), as
the Khronos sample viewer does. Only scenes with a transmissive pbr material add it.
"""
from __future__ import annotations

from dataclasses import dataclass

import moderngl

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.rendering.draw import begin_fullscreen_pass, bind_texture_units
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.data import ImageData
from scenerender.rendering.passes.sky import NO_SKY, SkyUnder

SOURCE_FRAGMENT = "post/transmission_source.frag"


@dataclass(frozen=True)
class TransmissionSourcePass(RenderPass):
    """The opaque scene, resolved (with the sky behind the samples where the resolve adds
    it: ``sky``) into an rgba16f image of ``size`` with its full mip chain, filtered
    trilinearly. ``samples``: the colour target's MSAA samples (1: copied as it is)."""

    color: Handle
    size: tuple
    samples: int = 1
    sky: SkyUnder = NO_SKY

    name = "transmission_source"

    def setup(self, builder) -> ImageData:
        builder.read(self.color)
        self.sky.declare(builder)
        return ImageData(builder.create("transmission_source", ResourceDesc("color", self.size, "rgba16f")))

    def describe(self) -> str:
        return "the opaque scene behind transmissive surfaces, mip-mapped" + self.sky.describe()

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(self.sky.vertex(), SOURCE_FRAGMENT,
                                   {"SAMPLES": max(self.samples, 1), **self.sky.defines()})
        bind_texture_units(program)
        ctx.image(self.color).use(TEXTURE_UNITS["u_color"])
        self.sky.bind(ctx, program)
        ctx.fullscreen(program)
        image = ctx.image(data.image)
        image.build_mipmaps()
        image.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
