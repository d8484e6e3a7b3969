"""The environment light's prefiltered specular image: made once per run (it reads only the
static ``environment_map`` input, so the graph caches it), read by the shading passes.

Layout (rendering.features.specular_layout): SPECULAR_LEVELS equirectangular strips of
prefilter_size x prefilter_size / 2 texels, roughness 0 at the bottom to 1 at the top; the
shader is shaders/environment/prefilter.frag.
"""
from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import FULLSCREEN_VERTEX, begin_fullscreen_pass, bind_texture_units
from scenerender.rendering.features import TEXTURE_UNITS, specular_layout_defines
from scenerender.rendering.lights import environment_view_uniforms
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
    the static ``environment_map`` (the diffuse map) and the prefiltered ``specular`` image;
    where the scene blocks its light, the ``views`` input of its visibility maps and the
    depth texture they are drawn into (``visibility``)."""

    environment: Handle
    environment_map: Handle
    specular: Handle
    views: Handle | None = None
    visibility: Handle | None = None

    def handles(self) -> tuple:
        extra = (self.views, self.visibility) if self.visibility is not None else ()
        return self.environment, self.environment_map, self.specular, *extra

    def bind(self, ctx) -> None:
        specular = ctx.image(self.specular)
        # graph images are sampled texel by texel; this one is filtered, and wraps in u
        specular.filter = (moderngl.LINEAR, moderngl.LINEAR)
        specular.repeat_x = True
        specular.use(TEXTURE_UNITS["u_env_specular"])
        ctx.input(self.environment_map).diffuse.use(TEXTURE_UNITS["u_env_diffuse"])
        if self.visibility is not None:
            maps = ctx.image(self.visibility)
            maps.compare_func = "<="
            maps.filter = (moderngl.LINEAR, moderngl.LINEAR)
            maps.use(TEXTURE_UNITS["u_env_visibility"])

    def uniforms(self, ctx, camera_position) -> dict:
        state = ctx.input(self.environment)
        found = {"u_env_to_image": state.to_image, "u_env_scale": state.scale}
        if self.visibility is not None:
            views = ctx.input(self.views)
            to_map, params, tiles = environment_view_uniforms(views.views, camera_position,
                                                              ctx.image(self.visibility).size)
            towards = np.concatenate([views.directions, views.weights[:, None]], axis=1)
            found.update(u_env_vis_to_map=to_map, u_env_vis_params=params, u_env_vis_tile=tiles,
                         u_env_vis_light=towards.astype(np.float32).tobytes())
        return found
