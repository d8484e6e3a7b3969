"""Bloom: a glow around bright light, from linear light before the exposure, the tone
curve and the output transform (``render.bloom``; docs/scene-notes.md#bloom).

The image is mixed with a Gaussian blur of itself, ``(1 - strength) * image + strength *
blur(image)``. The blur's weights sum to 1 and it reads the image mirrored about its
edges, so with its symmetric kernel the total light is unchanged: bloom moves light, it
adds none. Two passes, one per direction of the separable kernel; the second also mixes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import FULLSCREEN_VERTEX, begin_fullscreen_pass, bind_texture_units
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.data import ImageData
from scenerender.world.settings import BloomSettings

# The kernel reaches this many standard deviations either side (the weights past it sum
# to less than 0.3 % of the total, and the kept weights are normalised).
GAUSSIAN_REACH = 3.0


def bloom_weights(sigma_pixels: float, limit: int) -> np.ndarray:
    """The normalised one-sided Gaussian weights [centre, 1, 2, ... taps] (float32) for a
    standard deviation in pixels; at most ``limit`` taps either side (the mirrored reads
    reflect only once, so fewer than the image's width)."""
    taps = max(1, min(limit, math.ceil(GAUSSIAN_REACH * sigma_pixels)))
    offsets = np.arange(taps + 1, dtype=np.float64)
    weights = np.exp(-0.5 * (offsets / max(sigma_pixels, 1e-6)) ** 2)
    weights /= weights[0] + 2.0 * weights[1:].sum()
    return weights.astype(np.float32)


@dataclass(frozen=True)
class BloomBlurPass(RenderPass):
    """The horizontal half of the blur of ``color`` (linear, single-sampled)."""

    color: Handle
    size: tuple
    settings: BloomSettings

    name = "bloom_blur"

    def setup(self, builder) -> ImageData:
        builder.read(self.color)
        return ImageData(builder.create("bloom_half", ResourceDesc("color", self.size, "rgba16f")))

    def describe(self) -> str:
        return f"horizontal, {len(self.weights()) - 1} taps either side"

    def weights(self) -> np.ndarray:
        width, height = self.size
        return bloom_weights(self.settings.radius * height, min(width, height) - 1)

    def defines(self) -> dict:
        return {"TAPS": len(self.weights()) - 1, "HORIZONTAL": True}

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(FULLSCREEN_VERTEX, "post/bloom.frag", self.defines())
        bind_texture_units(program)
        ctx.image(self.color).use(TEXTURE_UNITS["u_color"])
        set_uniforms(program, u_weights=self.weights().tobytes())
        ctx.fullscreen(program)


@dataclass(frozen=True)
class BloomMixPass(BloomBlurPass):
    """The vertical half of the blur of ``half`` (BloomBlurPass's image), mixed with the
    original ``color``: the bloomed linear image."""

    half: Handle | None = None

    name = "bloom_mix"

    def setup(self, builder) -> ImageData:
        builder.read(self.color, self.half)
        return ImageData(builder.create("bloomed", ResourceDesc("color", self.size, "rgba16f")))

    def describe(self) -> str:
        return f"vertical, {len(self.weights()) - 1} taps either side, strength {self.settings.strength:g}"

    def defines(self) -> dict:
        return {"TAPS": len(self.weights()) - 1, "MIX": True}

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(FULLSCREEN_VERTEX, "post/bloom.frag", self.defines())
        bind_texture_units(program)
        ctx.image(self.half).use(TEXTURE_UNITS["u_color"])
        ctx.image(self.color).use(TEXTURE_UNITS["u_original"])
        set_uniforms(program, u_weights=self.weights().tobytes(), u_strength=float(self.settings.strength))
        ctx.fullscreen(program)


def add_bloom(graph, color: Handle, size: tuple, settings: BloomSettings) -> Handle:
    """The bloomed image of ``color``; the two passes added to ``graph``."""
    half = graph.add(BloomBlurPass(color, size, settings)).image
    return graph.add(BloomMixPass(color, size, settings, half)).image
