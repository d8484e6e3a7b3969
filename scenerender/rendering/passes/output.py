"""The end of the chain: MSAA resolve, exposure and tone curve, the output transform, and
readback to the CPU."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import begin_fullscreen_pass, bind_texture_units
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.data import ImageData
from scenerender.rendering.passes.sky import NO_SKY, SkyUnder


@dataclass(frozen=True)
class ResolvePass(RenderPass):
    """Averages the MSAA samples into a single-sampled texture of ``format``: linear HDR,
    or 8-bit sRGB (averaged in linear light: sampling the sRGB target decodes, writing the
    sRGB image encodes).

    A full-screen pass of our own rather than a resolve blit: the same pixels (every
    showcase frame compared) and the same time per frame, but Mesa llvmpipe compiles its
    blit program on the first frame, about 0.1 s more than this pass's (the benchmark
    scene's first frame, whole commands alternated: 4.5 % sooner). ``sky``: add the sky
    behind the samples (passes/sky.py)."""

    color: Handle
    size: tuple
    format: str = "rgba16f"
    sky: SkyUnder = NO_SKY

    name = "resolve"

    def setup(self, builder) -> ImageData:
        builder.read(self.color)
        self.sky.declare(builder)
        name = "hdr_resolved" if self.format == "rgba16f" else "resolved"
        return ImageData(builder.create(name, ResourceDesc("color", self.size, self.format)))

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        multisampled = ctx.image(self.color)
        program = ctx.programs.get(self.sky.vertex(), "post/resolve_samples.frag",
                                   {"SAMPLES": multisampled.samples, **self.sky.defines()})
        bind_texture_units(program)
        multisampled.use(TEXTURE_UNITS["u_color"])
        self.sky.bind(ctx, program)
        ctx.fullscreen(program)


@dataclass(frozen=True)
class ResolveToSrgbPass(ResolvePass):
    """The MSAA resolve into an 8-bit sRGB texture, which is also the output transform:
    the average is in linear light and the target format encodes with the sRGB curve,
    so the result is the output image. Used for sRGB output from an 8-bit sRGB target."""

    format: str = "srgba8"

    name = "resolve+output_transform"

    def describe(self) -> str:
        return "resolve; srgb by the target format" + self.sky.describe()


@dataclass(frozen=True)
class ToneCurve:
    """What the output transform does to linear light before encoding it: scale it by the
    ``exposure`` input (2^render.exposure; None: the exposure stays 0), then map it through
    the tone ``curve`` ("aces", "agx"; "none": values above 1 clip). Each is compiled into
    the output shader only where the scene has it (post/encode.glsl); NO_TONE, the
    default, compiles neither."""

    curve: str = "none"
    exposure: Handle | None = None
    exposure_text: str = "exposure"  # how describe() shows it: "exposure +0.5", "animated exposure"

    def declare(self, builder) -> None:
        if self.exposure is not None:
            builder.read(self.exposure)

    def defines(self) -> dict:
        found = {"EXPOSURE": True} if self.exposure is not None else {}
        if self.curve != "none":
            found[f"TONE_MAP_{self.curve.upper()}"] = True
        return found

    def describe(self) -> str:
        """What comes before the encoding, as "exposure +0.5, agx tone map, " ("" for none)."""
        steps = ([self.exposure_text] if self.exposure is not None else []) + (
            [f"{self.curve} tone map"] if self.curve != "none" else [])
        return "".join(f"{step}, " for step in steps)

    def bind(self, ctx, program) -> None:
        if self.exposure is not None:
            set_uniforms(program, u_exposure=float(ctx.input(self.exposure)))


NO_TONE = ToneCurve()


@dataclass(frozen=True)
class OutputTransformPass(RenderPass):
    """Linear HDR -> 8-bit display values: exact sRGB, a plain gamma, or linear; with
    ``tone``, after the exposure and the tone curve."""

    color: Handle
    size: tuple
    transform: str
    gamma: float
    tone: ToneCurve = NO_TONE

    name = "output_transform"
    fragment = "post/output_transform.frag"

    def setup(self, builder) -> ImageData:
        builder.read(self.color)
        self.tone.declare(builder)
        return ImageData(builder.create("ldr", ResourceDesc("color", self.size, "rgba8")))

    def describe(self) -> str:
        return self.tone.describe() + (self.transform if self.transform != "gamma" else f"gamma {self.gamma:g}")

    def defines(self) -> dict:
        return {f"OUTPUT_{self.transform.upper()}": True, **self.tone.defines()}

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(self.sky.vertex(), self.fragment, self.defines())
        bind_texture_units(program)
        ctx.image(self.color).use(TEXTURE_UNITS["u_color"])
        set_uniforms(program, u_gamma=self.gamma)
        self.tone.bind(ctx, program)
        self.sky.bind(ctx, program)
        ctx.fullscreen(program)

    @property
    def sky(self) -> SkyUnder:
        """No sky: this pass's input is already resolved (ResolveOutputPass adds one)."""
        return NO_SKY


@dataclass(frozen=True)
class ResolveOutputPass(OutputTransformPass):
    """The MSAA resolve and the output transform fused: one full-screen pass reads the
    multisampled linear colour, averages each pixel's samples and encodes the result.
    Used whenever nothing else needs the resolved linear image (EXR output does).
    ``sky``: add the sky behind the samples before encoding (passes/sky.py)."""

    samples: int = 4
    sky: SkyUnder = NO_SKY

    name = "resolve+output_transform"
    fragment = "post/resolve_output.frag"

    def setup(self, builder) -> ImageData:
        self.sky.declare(builder)
        return super().setup(builder)

    def describe(self) -> str:
        return f"{self.samples}x MSAA, {super().describe()}{self.sky.describe()}"

    def defines(self) -> dict:
        return {**super().defines(), "SAMPLES": self.samples, **self.sky.defines()}


@dataclass(frozen=True)
class ReadbackData:
    pixels: Handle
    linear: Handle | None
    object_ids: Handle | None = None
    object_ids_behind: Handle | None = None


@dataclass(frozen=True)
class ReadbackPass(RenderPass):
    """Copies the final image to the CPU: ctx.outputs["pixels"] = (H, W, 3) uint8, top row
    first; with ``linear`` also ctx.outputs["linear"] = (H, W, 3) float32 for EXR: the linear
    colour, or a data view's values; with ``object_ids`` (passes/object_ids.py) also
    ctx.outputs["object_ids"] = (H, W) uint16, top row first, and with ``object_ids_behind``
    ctx.outputs["object_ids_behind"] the same of the nearest opaque surfaces."""

    pixels: Handle
    size: tuple
    linear: Handle | None = None
    object_ids: Handle | None = None
    object_ids_behind: Handle | None = None

    name = "readback"
    side_effect = True

    def setup(self, builder) -> ReadbackData:
        builder.read(self.pixels, *(h for h in (self.linear, self.object_ids, self.object_ids_behind) if h is not None))
        return ReadbackData(self.pixels, self.linear, self.object_ids, self.object_ids_behind)

    def execute(self, ctx, data: ReadbackData) -> None:
        width, height = self.size
        # RGB straight from the driver: a quarter less to copy than RGBA and no slicing
        raw = ctx.framebuffer([data.pixels]).read(components=3, alignment=1)
        rgb = np.frombuffer(raw, dtype=np.uint8).reshape(height, width, 3)
        ctx.outputs["pixels"] = np.ascontiguousarray(rgb[::-1])
        if data.linear is not None:
            image = ctx.image(data.linear)  # rgba16f colour, or an rgba32f data view
            values = np.frombuffer(image.read(alignment=1), dtype=np.dtype(image.dtype)).reshape(height, width, 4)
            ctx.outputs["linear"] = np.ascontiguousarray(values[::-1, :, :3], dtype=np.float32)
        for key in ("object_ids", "object_ids_behind"):
            handle = getattr(data, key)
            if handle is not None:
                ids = np.frombuffer(ctx.image(handle).read(alignment=1), dtype=np.uint16)
                ctx.outputs[key] = np.ascontiguousarray(ids.reshape(height, width)[::-1])
