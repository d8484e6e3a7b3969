"""The data render modes: depth, normals, ambient_occlusion, shadow and light_depth.
Each writes plain values (no output transform) into an image: 8-bit for PNG, JPG, TGA and
video output, 32-bit float where the values are kept whole (EXR output)."""
from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import (
    FULLSCREEN_VERTEX, MESH_VERTEX, begin_camera_pass, begin_fullscreen_pass, bind_lights, bind_shadow_atlas,
    bind_texture_units, draw_cutting_masks,
)
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.passes.data import ImageData, TargetData


@dataclass(frozen=True)
class _FullscreenView(RenderPass):
    """A full-screen pass from one input image into an image of ``format``."""

    source: Handle
    size: tuple

    fragment = ""
    input_unit = ""

    def extra_reads(self) -> tuple:
        """Inputs the view's uniforms come from."""
        return ()

    def setup(self, builder) -> ImageData:
        builder.read(self.source, *self.extra_reads())
        return ImageData(builder.create("view", ResourceDesc("color", self.size, self.format)))

    def uniforms(self, ctx, program) -> None:
        """Extra uniforms of the view."""

    def defines(self) -> dict:
        """The fragment shader's defines."""
        return {}

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        program = ctx.programs.get(FULLSCREEN_VERTEX, self.fragment, self.defines())
        bind_texture_units(program)
        ctx.image(self.source).use(TEXTURE_UNITS[self.input_unit])
        self.uniforms(ctx, program)
        ctx.fullscreen(program)


@dataclass(frozen=True)
class DepthViewPass(_FullscreenView):
    camera: Handle
    format: str = "rgba8"

    name = "view:depth"
    fragment = "views/depth.frag"
    input_unit = "u_gbuffer"

    def extra_reads(self) -> tuple:
        return (self.camera,)

    def uniforms(self, ctx, program) -> None:
        camera = ctx.input(self.camera)
        set_uniforms(program, u_near_far=(camera.near, camera.far))

    def defines(self) -> dict:
        """In float (EXR) the depth itself, in scene units, not mapped to [0, 1]."""
        return {"DEPTH_IN_SCENE_UNITS": True} if self.format == "rgba32f" else {}


@dataclass(frozen=True)
class NormalsViewPass(_FullscreenView):
    camera: Handle
    format: str = "rgba8"

    name = "view:normals"
    fragment = "views/normals.frag"
    input_unit = "u_gbuffer"

    def extra_reads(self) -> tuple:
        return (self.camera,)

    def uniforms(self, ctx, program) -> None:
        set_uniforms(program, u_view_rotation=ctx.input(self.camera).rotation)


@dataclass(frozen=True)
class AmbientOcclusionViewPass(_FullscreenView):
    format: str = "rgba8"

    name = "view:ambient_occlusion"
    fragment = "views/ambient_occlusion.frag"
    input_unit = "u_ao"


def _raw_depth_sampler(gl):
    """Reads depth values as they are (no comparison), for showing a shadow map."""
    return gl.sampler(filter=(moderngl.NEAREST, moderngl.NEAREST), compare_func="", repeat_x=False, repeat_y=False)


@dataclass(frozen=True)
class LightDepthViewPass(_FullscreenView):
    """The first shadowed light's depth map(s) as seen from the light."""

    views: Handle
    format: str = "rgba8"

    name = "view:light_depth"
    fragment = "views/light_depth.frag"
    input_unit = "u_atlas"

    def extra_reads(self) -> tuple:
        return (self.views,)

    def execute(self, ctx, data: ImageData) -> None:
        sampler = ctx.shared("raw_depth_sampler", _raw_depth_sampler)
        sampler.use(TEXTURE_UNITS["u_atlas"])
        try:
            super().execute(ctx, data)
        finally:
            sampler.clear(TEXTURE_UNITS["u_atlas"])

    def uniforms(self, ctx, program) -> None:
        width, height = ctx.image(self.source).size  # the atlas page holding the light's tiles
        views = ctx.input(self.views).views
        tiles = np.zeros((6, 4), dtype=np.float32)
        for i, view in enumerate(views):
            t = view.tile
            tiles[i] = (t.x / width, t.y / height, t.size / width, t.size / height)
        set_uniforms(program, u_tiles=tiles.tobytes(), u_tile_count=len(views))


@dataclass(frozen=True)
class ShadowFactorViewPass(RenderPass):
    """How much of one shadowed light reaches each visible surface.

    light_index: the light's index in World.lights; light, views: its ``light:NAME`` and
    ``shadow_views:NAME`` inputs (the views are declared as what the lookup depends on;
    it reads them packed); lights: the packed ``lights`` input, whose shadow views the
    lookup reads from the light's first view on.
    """

    atlas: Handle
    size: tuple
    camera: Handle
    objects: Handle
    light_index: int
    light: Handle
    views: Handle
    lights: Handle
    format: str = "rgba8"
    materials: Handle | None = None

    name = "view:shadow"

    def setup(self, builder) -> TargetData:
        builder.read(self.atlas, self.camera, self.objects, self.light, self.views, self.lights,
                     *((self.materials,) if self.materials is not None else ()))
        return TargetData(builder.create("view", ResourceDesc("color", self.size, self.format)),
                          builder.create("view_depth", ResourceDesc("depth", self.size, "camera_depth")))

    def execute(self, ctx, data: TargetData) -> None:
        begin_camera_pass(ctx, [data.color], data.depth, (1.0, 1.0, 1.0, 1.0))
        bind_shadow_atlas(ctx, self.atlas)
        lights = ctx.input(self.lights)
        bind_lights(lights)
        program = ctx.programs.get(MESH_VERTEX, "views/shadow_factor.frag")
        bind_texture_units(program)
        light = ctx.input(self.light)
        camera = ctx.input(self.camera)
        point = light.kind == "point"
        vector = (light.position - camera.position) if point else light.direction
        uniforms = {"u_view_proj": camera.view_proj_relative(), "u_first_view": lights.first_view[self.light_index],
                    "u_point_light": int(point), "u_light_vector": vector}
        set_uniforms(program, **uniforms)
        objects = ctx.input(self.objects)
        materials = ctx.input(self.materials) if self.materials is not None else None
        for index in objects.in_camera_view():
            draw_cutting_masks(ctx, objects, index, program, "views/shadow_factor.frag", {}, materials, uniforms)
