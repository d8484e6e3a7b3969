"""Motion blur along a velocity buffer (``render.motion_blur: velocity``): the fast
shutter. One instant is rendered; a pass draws every object once more writing how far its
surface moves on screen while the shutter is open (world.motion: the camera's motion and
each object's keyframed transform), and the resolved linear image is blurred along it by
McGuire et al.'s reconstruction ("A reconstruction filter for plausible motion blur",
I3D 2012): the largest motion of each tile, the largest of its neighbours, and a gather
along that which keeps what lies in front in front (docs/scene-notes.md, "Motion blur
along a velocity buffer"). Where the sub-frames see what a moving object uncovers, this
sees one instant: what the object hides at the frame's time stays hidden.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import (
    FULLSCREEN_VERTEX, MESH_VERTEX, begin_camera_pass, begin_fullscreen_pass, bind_texture_units, cull_hidden_faces,
    stop_culling,
)
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.data import ImageData, TargetData
from scenerender.rendering.passes.sky import SKY_VERTEX

# The largest blur, as the radius of a pixel's smear (half its motion over the shutter) in
# pixels: longer motion is cut to it, keeping its direction. It is also the tile size, so
# a pixel's smear reaches no further than the neighbouring tiles.
MAX_BLUR_RADIUS = 32
# Points the gather reads along the neighbourhood's largest motion.
GATHER_TAPS = 24
# Where nothing was drawn the velocity image holds no motion and this depth (farther than
# any surface).
EMPTY_DEPTH = 1e30


def tile_count(size: tuple) -> tuple:
    """The tiles of MAX_BLUR_RADIUS pixels covering an image of ``size`` (partial ones at
    the right and top edges count)."""
    return tuple(math.ceil(extent / MAX_BLUR_RADIUS) for extent in size)


@dataclass(frozen=True)
class VelocityPass(RenderPass):
    """Every object in the camera's view, depth-tested, one sample a pixel: its smear (half
    its motion over the shutter, in pixels) in rg and its distance along the view axis in
    b, into an rgba32f image; where nothing was drawn, the skybox's motion (``sky``: the
    scene has one) or none, at EMPTY_DEPTH."""

    size: tuple
    camera: Handle
    objects: Handle
    motion: Handle
    sky: bool = False

    name = "velocity"

    def setup(self, builder) -> TargetData:
        builder.read(self.camera, self.objects, self.motion)
        return TargetData(builder.create("velocity", ResourceDesc("color", self.size, "rgba32f")),
                          builder.create("velocity_depth", ResourceDesc("depth", self.size, "camera_depth")))

    def describe(self) -> str:
        sky = ", the skybox's too" if self.sky else ""
        return f"screen motion over the shutter, up to {MAX_BLUR_RADIUS} px either way{sky}"

    def defines(self) -> dict:
        return {"MAX_RADIUS": float(MAX_BLUR_RADIUS), "EMPTY_DEPTH": EMPTY_DEPTH}

    def execute(self, ctx, data: TargetData) -> None:
        begin_camera_pass(ctx, [data.color], data.depth, (0.0, 0.0, EMPTY_DEPTH, 0.0))
        camera, motion = ctx.input(self.camera), ctx.input(self.motion)
        half_size = (self.size[0] / 2.0, self.size[1] / 2.0)
        if self.sky:
            self._draw_sky(ctx, camera, motion, half_size)
        program = ctx.programs.get(MESH_VERTEX, "mesh/velocity.frag", self.defines())
        set_uniforms(program, u_view_proj=camera.view_proj_relative(), u_forward=camera.forward, u_half_size=half_size)
        objects = ctx.input(self.objects)
        try:
            for index in objects.in_camera_view():
                cull_hidden_faces(ctx.gl, objects, index)
                set_uniforms(program, u_open=motion.open[index], u_close=motion.close[index])
                objects.draw(program, index)
        finally:
            stop_culling(ctx.gl)

    def _draw_sky(self, ctx, camera, motion, half_size) -> None:
        """The skybox's motion over the whole image; the objects are then drawn over it."""
        program = ctx.programs.get(SKY_VERTEX, "mesh/velocity.frag", {**self.defines(), "SKY": True})
        set_uniforms(program, u_inverse_view_proj=np.linalg.inv(camera.view_proj_relative()),
                     u_ndc_near_far=ctx.depth.ndc_near_far, u_open=motion.sky_open, u_close=motion.sky_close,
                     u_half_size=half_size)
        ctx.gl.disable(moderngl.DEPTH_TEST)
        ctx.fullscreen(program)
        ctx.gl.enable(moderngl.DEPTH_TEST)


@dataclass(frozen=True)
class VelocityTilesPass(RenderPass):
    """The longest smear of each tile of ``velocity`` (``neighbours`` False), or of each
    tile's 3 x 3 neighbourhood of such tiles (``neighbours`` True, ``velocity`` then being
    the first pass's tile image)."""

    velocity: Handle
    size: tuple  # of the full image
    neighbours: bool

    @property
    def name(self) -> str:
        return "velocity_neighbours" if self.neighbours else "velocity_tiles"

    def setup(self, builder) -> ImageData:
        builder.read(self.velocity)
        return ImageData(builder.create(self.name, ResourceDesc("color", tile_count(self.size), "rgba32f")))

    def describe(self) -> str:
        return "3 x 3 tiles" if self.neighbours else f"{MAX_BLUR_RADIUS} px tiles"

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        defines = {"NEIGHBOURS": True} if self.neighbours else {"TILE": MAX_BLUR_RADIUS}
        program = ctx.programs.get(FULLSCREEN_VERTEX, "post/velocity_tiles.frag", defines)
        bind_texture_units(program)
        ctx.image(self.velocity).use(TEXTURE_UNITS["u_velocity"])
        ctx.fullscreen(program)


@dataclass(frozen=True)
class MotionBlurGatherPass(RenderPass):
    """The blur of ``color`` (linear, single-sampled) along ``velocity``, led by the
    neighbourhood's longest smear (``tiles``: VelocityTilesPass with neighbours)."""

    color: Handle
    velocity: Handle
    tiles: Handle
    size: tuple

    name = "motion_blur"

    def setup(self, builder) -> ImageData:
        builder.read(self.color, self.velocity, self.tiles)
        return ImageData(builder.create("motion_blurred", ResourceDesc("color", self.size, "rgba16f")))

    def describe(self) -> str:
        return f"gather, {GATHER_TAPS} taps along the neighbourhood's motion"

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(FULLSCREEN_VERTEX, "post/motion_blur.frag",
                                   {"TAPS": GATHER_TAPS, "TILE": MAX_BLUR_RADIUS})
        bind_texture_units(program)
        ctx.image(self.color).use(TEXTURE_UNITS["u_color"])
        ctx.image(self.velocity).use(TEXTURE_UNITS["u_velocity"])
        ctx.image(self.tiles).use(TEXTURE_UNITS["u_velocity_tiles"])
        ctx.fullscreen(program)


def add_velocity_blur(graph, color: Handle, inputs, size: tuple) -> Handle:
    """The passes of the velocity blur of ``color`` (resolved linear light); its result."""
    velocity = graph.add(VelocityPass(size, inputs.camera, inputs.objects, inputs.motion,
                                      sky=inputs.skybox is not None)).color
    tiles = graph.add(VelocityTilesPass(velocity, size, neighbours=False)).image
    neighbourhood = graph.add(VelocityTilesPass(tiles, size, neighbours=True)).image
    return graph.add(MotionBlurGatherPass(color, velocity, neighbourhood, size)).image
