"""The environment light's prefiltered specular image: made once per run (it reads only the
static ``environment_map`` input, so the graph caches it), read by the shading passes.

Layout (rendering.features.specular_layout): SPECULAR_LEVELS equirectangular strips of
prefilter_size x prefilter_size / 2 texels, roughness 0 at the bottom to 1 at the top; the
shader is shaders/environment/prefilter.frag.
"""
from __future__ import annotations

from dataclasses import dataclass

import moderngl

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import FULLSCREEN_VERTEX, begin_fullscreen_pass, bind_texture_units
from scenerender.rendering.features import TEXTURE_UNITS, specular_layout_defines
from scenerender.rendering.passes.data import ImageData

PREFILTER_FRAGMENT = "environment/prefilter.frag"


@dataclass(frozen=True)
class EnvironmentPrefilterPass(RenderPass):
    environment_map: Handle
    layout: tuple  # (levels, strip width, strip height)
    samples: int

    name = "environment_prefilter"

    def setup(self, builder) -> ImageData:
        builder.read(self.environment_map)
        levels, width, height = self.layout
        return ImageData(builder.create("environment_specular", ResourceDesc("color", (width, height * levels),
                                                                             "rgba16f")))

    def describe(self) -> str:
        levels, width, height = self.layout
        return f"{levels} roughness levels of {width}x{height}, {self.samples} samples"

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(FULLSCREEN_VERTEX, PREFILTER_FRAGMENT, specular_layout_defines(self.layout))
        bind_texture_units(program)
        source = ctx.input(self.environment_map).source
        source.use(TEXTURE_UNITS["u_env_source"])
        set_uniforms(program, u_source_size=source.size, u_samples=self.samples)
        ctx.fullscreen(program)


@dataclass(frozen=True)
class EnvironmentLighting:
    """What shading reads of the environment light: its per-frame ``environment`` input,
    the static ``environment_map`` (the diffuse map) and the prefiltered ``specular`` image."""

    environment: Handle
    environment_map: Handle
    specular: Handle

    def handles(self) -> tuple:
        return self.environment, self.environment_map, self.specular

    def bind(self, ctx) -> None:
        specular = ctx.image(self.specular)
        # graph images are sampled texel by texel; this one is filtered, and wraps in u
        specular.filter = (moderngl.LINEAR, moderngl.LINEAR)
        specular.repeat_x = True
        specular.use(TEXTURE_UNITS["u_env_specular"])
        ctx.input(self.environment_map).diffuse.use(TEXTURE_UNITS["u_env_diffuse"])

    def uniforms(self, ctx) -> dict:
        state = ctx.input(self.environment)
        return {"u_env_to_image": state.to_image, "u_env_scale": state.scale}
