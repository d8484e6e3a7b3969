"""The end of the chain: MSAA resolve, the output transform, and readback to the CPU."""
from __future__ import annotations

import numpy as np

from scenerender.graph import ResourceDesc, RenderPass
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import bind_texture_units
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.forward import fullscreen


class ResolvePass(RenderPass):
    """Averages the MSAA samples into a single-sampled texture of ``format``: linear HDR,
    or 8-bit sRGB (averaged in linear light: GL_FRAMEBUFFER_SRGB is on)."""

    name = "resolve"

    def __init__(self, color, size, dynamic: bool = True, format: str = "rgba16f"):
        self.color_in = color
        self.size = size
        self.dynamic = dynamic
        self.format = format

    def setup(self, builder):
        builder.read(self.color_in)
        name = "hdr_resolved" if self.format == "rgba16f" else "resolved"
        self.color = builder.create(name, ResourceDesc("color", self.size, self.format))
        return self.color

    def execute(self, ctx) -> None:
        ctx.gl.copy_framebuffer(ctx.framebuffer([self.color]), ctx.framebuffer([self.color_in]))


class ResolveToSrgbPass(ResolvePass):
    """The MSAA resolve into an 8-bit sRGB texture, which is also the output transform:
    the blit averages in linear light and the target format encodes with the sRGB curve,
    so the result is the output image. Used for sRGB output from an 8-bit sRGB target."""

    name = "resolve+output_transform"

    def __init__(self, color, size, dynamic: bool = True):
        super().__init__(color, size, dynamic, "srgba8")

    def describe(self) -> str:
        return "resolve blit; srgb by the target format"


class OutputTransformPass(RenderPass):
    """Linear HDR -> 8-bit display values: exact sRGB, a plain gamma, or linear."""

    name = "output_transform"

    def __init__(self, color, size, transform: str, gamma: float, dynamic: bool = True):
        self.color_in = color
        self.size = size
        self.transform = transform
        self.gamma = gamma
        self.dynamic = dynamic

    def setup(self, builder):
        builder.read(self.color_in)
        self.ldr = builder.create("ldr", ResourceDesc("color", self.size, "rgba8"))
        return self.ldr

    def describe(self) -> str:
        return self.transform if self.transform != "gamma" else f"gamma {self.gamma:g}"

    def execute(self, ctx) -> None:
        import moderngl

        ctx.framebuffer([self.ldr]).use()
        ctx.gl.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        program = ctx.programs.get("common/fullscreen.vert", "post/output_transform.frag",
                                   {f"OUTPUT_{self.transform.upper()}": True})
        bind_texture_units(program)
        ctx.resource(self.color_in).use(TEXTURE_UNITS["u_color"])
        set_uniforms(program, u_gamma=self.gamma)
        fullscreen(ctx, program)


class ResolveOutputPass(OutputTransformPass):
    """The MSAA resolve and the output transform fused: one full-screen pass reads the
    multisampled linear colour, averages each pixel's samples and encodes the result.
    Used whenever nothing else needs the resolved linear image (EXR output does)."""

    name = "resolve+output_transform"

    def __init__(self, color, size, samples: int, transform: str, gamma: float, dynamic: bool = True):
        super().__init__(color, size, transform, gamma, dynamic)
        self.samples = samples

    def describe(self) -> str:
        return f"{self.samples}x MSAA, {super().describe()}"

    def execute(self, ctx) -> None:
        import moderngl

        ctx.framebuffer([self.ldr]).use()
        ctx.gl.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        program = ctx.programs.get("common/fullscreen.vert", "post/resolve_output.frag",
                                   {f"OUTPUT_{self.transform.upper()}": True, "SAMPLES": self.samples})
        bind_texture_units(program)
        ctx.resource(self.color_in).use(TEXTURE_UNITS["u_color"])
        set_uniforms(program, u_gamma=self.gamma)
        fullscreen(ctx, program)


class ReadbackPass(RenderPass):
    """Copies the final image to the CPU: ctx.outputs["pixels"] = (H, W, 3) uint8, top row
    first; with ``linear_source`` also ctx.outputs["linear"] = (H, W, 3) float32 for EXR."""

    name = "readback"
    side_effect = True

    def __init__(self, ldr, size, linear_source=None):
        self.ldr = ldr
        self.size = size
        self.linear_source = linear_source

    def setup(self, builder):
        builder.read(self.ldr)
        if self.linear_source is not None:
            builder.read(self.linear_source)

    def execute(self, ctx) -> None:
        width, height = self.size
        # RGB straight from the driver: a quarter less to copy than RGBA and no slicing
        data = ctx.framebuffer([self.ldr]).read(components=3, alignment=1)
        rgb = np.frombuffer(data, dtype=np.uint8).reshape(height, width, 3)
        ctx.outputs["pixels"] = np.ascontiguousarray(rgb[::-1])
        if self.linear_source is not None:
            raw = ctx.resource(self.linear_source).read(alignment=1)
            hdr = np.frombuffer(raw, dtype=np.float16).reshape(height, width, 4)
            ctx.outputs["linear"] = np.ascontiguousarray(hdr[::-1, :, :3], dtype=np.float32)
