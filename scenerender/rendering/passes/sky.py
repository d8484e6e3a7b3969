"""The sky behind everything the camera sees: the cube-map skybox, or the environment
light's image where it says ``background: true`` (turned by its rotation, times its colour
x intensity: ``SKY_ENVIRONMENT`` in the shaders).

Two ways in, by target, each the cheaper there (measured on Mesa llvmpipe, the showcase
at 640x480):

- single-sampled: ``SkyboxPass`` draws the sky after the opaque surfaces, depth-tested
  against the far plane. llvmpipe skips every 4x4 block the depth test rejects, so only
  sky pixels are shaded.
- multisampled: llvmpipe shades every pixel of a full-screen draw into an MSAA target,
  hidden or not, and writes (and sRGB-encodes) all of its samples: 6-7 ms a frame. So
  the forward passes leave the sky out (coverage in alpha: 1 where an opaque surface
  was drawn, 0 where nothing was, blended coverage where a transparent surface lies over
  nothing), and the MSAA resolve adds the sky behind each pixel's samples: ``SkyUnder``.
  A pixel's sky is looked up once at its centre, as the MSAA skybox draw did.
"""
from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.graph import Handle, RenderPass
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import FULLSCREEN_VERTEX, bind_texture_units
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.data import ImageData

SKY_VERTEX = "skybox/skybox.vert"  # a full-screen triangle with each pixel's view direction


@dataclass(frozen=True)
class EnvironmentSky:
    """The environment light's image as the sky: its per-frame ``environment`` input
    (rotation, colour x intensity) and its static ``environment_map`` (the image)."""

    environment: Handle
    environment_map: Handle

    def handles(self) -> tuple:
        return self.environment, self.environment_map


def _use_sky(ctx, program, camera: Handle, skybox) -> None:
    """Bind the sky (a cube map's handle, or an EnvironmentSky) and the camera's inverse
    projection for SKY_VERTEX."""
    set_uniforms(program, u_inverse_view_proj=np.linalg.inv(ctx.input(camera).view_proj_relative()),
                 u_ndc_near_far=ctx.depth.ndc_near_far)
    if isinstance(skybox, EnvironmentSky):
        state = ctx.input(skybox.environment)
        set_uniforms(program, u_env_to_image=state.to_image, u_env_scale=state.scale)
        ctx.input(skybox.environment_map).source.use(TEXTURE_UNITS["u_env_source"])
    else:
        ctx.input(skybox).use(TEXTURE_UNITS["u_skybox"])


def _sky_handles(skybox) -> tuple:
    return skybox.handles() if isinstance(skybox, EnvironmentSky) else (skybox,)


def sky_defines(skybox) -> dict:
    """The sky shaders' defines for ``skybox`` (a cube map's handle or an EnvironmentSky)."""
    return {"SKY_ENVIRONMENT": True} if isinstance(skybox, EnvironmentSky) else {}


@dataclass(frozen=True)
class SkyboxPass(RenderPass):
    """Draws the sky into a single-sampled target where nothing else was drawn (depth
    still at the far plane)."""

    color: Handle
    depth: Handle
    camera: Handle
    skybox: object  # the cube map's handle, or an EnvironmentSky

    name = "skybox"

    def setup(self, builder) -> ImageData:
        builder.read(self.depth, self.camera, *_sky_handles(self.skybox))
        return ImageData(builder.write(self.color))

    def execute(self, ctx, data: ImageData) -> None:
        gl = ctx.gl
        ctx.framebuffer([data.image], self.depth).use()
        gl.enable(moderngl.DEPTH_TEST)
        gl.depth_func = ctx.depth.nearer_or_equal
        program = ctx.programs.get(SKY_VERTEX, "skybox/skybox.frag", sky_defines(self.skybox))
        bind_texture_units(program)
        _use_sky(ctx, program, self.camera, self.skybox)
        ctx.fullscreen(program)
        gl.depth_func = ctx.depth.nearer


@dataclass(frozen=True)
class SkyUnder:
    """The sky a multisampled resolve adds behind the samples (post/sky_under.glsl), or,
    as NO_SKY, nothing: the resolves use either alike."""

    camera: Handle | None = None
    skybox: object = None  # the cube map's handle, or an EnvironmentSky

    def declare(self, builder) -> None:
        if self.skybox is not None:
            builder.read(self.camera, *_sky_handles(self.skybox))

    def vertex(self) -> str:
        """The resolve's vertex shader: with the view direction per pixel where it adds the sky."""
        return SKY_VERTEX if self.skybox is not None else FULLSCREEN_VERTEX

    def defines(self) -> dict:
        return {"SKY_UNDER": True, **sky_defines(self.skybox)} if self.skybox is not None else {}

    def describe(self) -> str:
        return ", sky behind" if self.skybox is not None else ""

    def bind(self, ctx, program) -> None:
        if self.skybox is not None:
            _use_sky(ctx, program, self.camera, self.skybox)


NO_SKY = SkyUnder()
