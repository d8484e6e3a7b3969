"""The environment light's prefiltered specular image: made once per run (it reads only the
static ``environment_map`` input, so the graph caches it), read by the shading passes.

Layout (rendering.features.specular_layout): PREFILTER_LEVELS equirectangular strips of
prefilter_size x prefilter_size / 2 texels, roughness 0 at the bottom to 1 at the top; the
shader is shaders/environment/prefilter.frag.
"""
from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import (
    FULLSCREEN_VERTEX, MESH_VERTEX, begin_camera_pass, begin_fullscreen_pass, bind_texture_units, cull_hidden_faces,
    draw_cutting_masks, stop_culling,
)
from scenerender.rendering.features import TEXTURE_UNITS, specular_layout_defines
from scenerender.rendering.light_buffers import environment_view_uniforms
from scenerender.rendering.passes.data import ImageData, SurfacesData
from scenerender.rendering.steps import Step, Waits, draw_in_steps, steps_over
from scenerender.world.environment_visibility import place_lookups

PREFILTER_FRAGMENT = "environment/prefilter.frag"
VISIBILITY_FRAGMENT = "post/environment_visibility.frag"
SURFACE_FRAGMENT = "mesh/environment_visibility_surface.frag"
BLUR_FRAGMENT = "post/environment_visibility_blur.frag"


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
        # in steps a signal can stop between (at the largest size, one draw takes minutes
        # on a software renderer); a stopped frame marks no static pass done
        # (GraphRenderer), so no half-made image is kept
        draw_in_steps(ctx, prefilter_steps(self.layout, self.samples), lambda: ctx.fullscreen(program),
                      f"prefiltering the environment ({self.layout[1]} px, {self.samples} samples)")


def prefilter_steps(layout: tuple, samples: int) -> list[Step]:
    """The prefilter's draws (rendering.steps): the mirror level (one lookup a texel) and
    each rough level (``samples`` a texel) cut into steps of their own."""
    levels, width, height = layout
    steps = steps_over((0, 0, width, height), 1)
    for level in range(1, levels):
        steps += steps_over((0, level * height, width, height), samples)
    return steps


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
    lookups: Handle | None = None  # the blurred V_d, V_s (EnvironmentVisibilityBlurPass), where the directions are shared out
    lookup_scale: tuple = (1.0, 1.0)  # its texels a pixel of the camera's image

    def handles(self) -> tuple:
        extra = (self.views, self.visibility) if self.visibility is not None else ()
        extra += (self.lookups,) if self.lookups is not None else ()
        return self.environment, self.environment_map, self.specular, *extra

    def bind(self, ctx) -> None:
        specular = ctx.image(self.specular)
        # graph images are sampled texel by texel; this one is filtered, and wraps in u
        specular.filter = (moderngl.LINEAR, moderngl.LINEAR)
        specular.repeat_x = True
        specular.use(TEXTURE_UNITS["u_env_specular"])
        ctx.input(self.environment_map).diffuse.use(TEXTURE_UNITS["u_env_diffuse"])
        if ctx.features.environment_specular_samples:
            # the sampled specular term reads the source image itself, mip levels and all
            ctx.input(self.environment_map).source.use(TEXTURE_UNITS["u_env_source"])
        if self.visibility is not None:
            bind_visibility_maps(ctx, self.visibility)
        if self.lookups is not None:
            ctx.image(self.lookups).use(TEXTURE_UNITS["u_env_vis_samples"])

    def uniforms(self, ctx, camera_position, looks_up: bool = True) -> dict:
        """The shaders' uniforms; ``looks_up``: also the visibility maps', which a shader
        reading the visibility pass's image (``lookups``) has no use for."""
        state = ctx.input(self.environment)
        found = {"u_env_to_image": state.to_image, "u_env_scale": state.scale}
        if self.visibility is not None and (looks_up or self.lookups is None):
            found.update(visibility_uniforms(ctx, self.views, self.visibility, camera_position))
        if self.lookups is not None:
            found["u_env_vis_scale"] = self.lookup_scale
        return found


def bind_visibility_maps(ctx, visibility: Handle) -> None:
    """The visibility maps' depth texture on its unit, read as plain depth: the shader
    gathers 2 x 2 texels and compares each with the receiver's plane."""
    maps = ctx.image(visibility)
    maps.compare_func = ""
    maps.filter = (moderngl.NEAREST, moderngl.NEAREST)
    maps.use(TEXTURE_UNITS["u_env_visibility"])


def visibility_uniforms(ctx, views: Handle, visibility: Handle, camera_position) -> dict:
    """The u_env_vis_* uniforms (shaders/lighting/environment_visibility.glsl) of the
    ``views`` input's maps, drawn into ``visibility``, from ``camera_position``."""
    found = ctx.input(views)
    to_map, params, tiles = environment_view_uniforms(found.views, camera_position, ctx.image(visibility).size)
    towards = np.concatenate([found.directions, found.weights[:, None]], axis=1)
    return {"u_env_vis_to_map": to_map, "u_env_vis_params": params, "u_env_vis_tile": tiles,
            "u_env_vis_light": towards.astype(np.float32).tobytes()}


@dataclass(frozen=True)
class EnvironmentSurfacesPass(RenderPass):
    """What the camera sees at each pixel of the environment visibility's image, ``size``:
    camera-relative positions (whole floats) and normals facing the camera (coded in w)
    (shaders/mesh/environment_visibility_surface.frag); a geometry pass, single-sampled.
    EnvironmentVisibilityPass then looks the directions up once a pixel. materials: as
    GBufferPass's."""

    size: tuple
    camera: Handle
    objects: Handle
    materials: Handle | None = None

    name = "environment_visibility_surfaces"

    def setup(self, builder) -> SurfacesData:
        builder.read(self.camera, self.objects, *((self.materials,) if self.materials is not None else ()))
        return SurfacesData(builder.create("environment_surfaces", ResourceDesc("color", self.size, "rgba32f")),
                            builder.create("environment_lookups_depth", ResourceDesc("depth", self.size, "camera_depth")))

    def describe(self) -> str:
        return f"positions and normals at {self.size[0]}x{self.size[1]}"

    def execute(self, ctx, data: SurfacesData) -> None:
        begin_camera_pass(ctx, [data.surfaces], data.depth, (0.0, 0.0, 0.0, 0.0))
        program = ctx.programs.get(MESH_VERTEX, SURFACE_FRAGMENT)
        bind_texture_units(program)
        uniforms = {"u_view_proj": ctx.input(self.camera).view_proj_relative()}
        set_uniforms(program, **uniforms)
        objects = ctx.input(self.objects)
        materials = ctx.input(self.materials) if self.materials is not None else None
        for index in objects.in_camera_view():
            cull_hidden_faces(ctx.gl, objects, index)
            draw_cutting_masks(ctx, objects, index, program, SURFACE_FRAGMENT, {}, materials, uniforms)
        stop_culling(ctx.gl)


@dataclass(frozen=True)
class EnvironmentVisibilityPass(RenderPass):
    """Each pixel's share of the environment's visibility lookups, where the directions
    are shared out over ``interleave`` x ``interleave`` blocks (place_lookups a pixel;
    world.environment_visibility), at the surface EnvironmentSurfacesPass
    found there, as weighted sums with the surface's distance, packed
    (shaders/post/environment_visibility.frag); full-screen, once for each place in the
    block (and each half of the regions, where ``halves`` is 2), into a sub-image of its
    own (sub_image_layout). ``min_alpha``: the narrowest specular lobe
    (features.visibility_min_alpha)."""

    size: tuple
    camera: Handle
    surfaces: SurfacesData
    views: Handle
    visibility: Handle
    directions: int
    interleave: int
    min_alpha: str
    halves: int = 1  # maps a direction (world.environment_visibility.region_halves)

    name = "environment_visibility"

    def setup(self, builder) -> ImageData:
        builder.read(self.camera, self.views, self.visibility, self.surfaces.surfaces)
        part, _ = sub_image_layout(self.size, self.interleave, self.halves)
        whole = (part[0] * self.interleave, part[1] * self.interleave)
        return ImageData(builder.create("environment_lookups", ResourceDesc("color", whole, "rgba32ui")))

    def describe(self) -> str:
        _, places = sub_image_layout(self.size, self.interleave)
        counts = sorted({place_lookups(place, self.interleave, self.directions) for place in places})
        halves = ", each direction's region in halves taking turns by block" if self.halves > 1 else ""
        return (f"{self.directions} directions over {self.interleave}x{self.interleave} pixels, "
                f"{' or '.join(map(str, counts))} a pixel, at {self.size[0]}x{self.size[1]}{halves}")

    def execute(self, ctx, data: ImageData) -> None:
        fbo = ctx.framebuffer([data.image])
        fbo.use()
        ctx.gl.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        bind_visibility_maps(ctx, self.visibility)
        ctx.image(self.surfaces.surfaces).use(TEXTURE_UNITS["u_env_vis_surfaces"])
        uniforms = visibility_uniforms(ctx, self.views, self.visibility, ctx.input(self.camera).position)
        part, places = sub_image_layout(self.size, self.interleave, self.halves)
        width = part[0] // self.halves  # each half's blocks: a column of the sub-image (sub_image_layout)
        programs = {}
        waits = Waits(ctx)  # over all places: each may be short, all of them long
        try:
            for place in places:
                lookups = place_lookups(place, self.interleave, self.directions)
                if lookups not in programs:
                    programs[lookups] = self._program(ctx, lookups)
                    set_uniforms(programs[lookups], **uniforms)
                program = programs[lookups]
                program["u_env_vis_place"].value = place
                for half in range(self.halves):
                    # one draw a half: all its pixels look up the same maps, whose data
                    # llvmpipe then reads once for all of them
                    fbo.viewport = (place[0] * part[0] + half * width, place[1] * part[1], width, part[1])
                    if self.halves > 1:
                        program["u_env_vis_half"].value = half
                    # at the largest images a place's draw takes seconds on a software renderer
                    draw_in_steps(ctx, steps_over(fbo.viewport, lookups), lambda: ctx.fullscreen(program), waits=waits)
        finally:
            fbo.viewport = (0, 0, *fbo.size)

    def _program(self, ctx, lookups: int):
        """The pass's program for a place that looks up ``lookups`` directions: where N^2
        does not divide the count, the places with one fewer run a shorter loop rather
        than lookups weighed by 0."""
        defines = {"ENV_VISIBILITY": self.directions * self.halves, "ENV_VIS_INTERLEAVE": self.interleave,
                   "ENV_VIS_PER_PIXEL": lookups, "ENV_VIS_MIN_ALPHA": self.min_alpha}
        if self.halves > 1:  # the regions; their second halves' maps follow the first halves'
            defines["ENV_VIS_REGIONS"] = self.directions
        program = ctx.programs.get(FULLSCREEN_VERTEX, VISIBILITY_FRAGMENT, defines)
        bind_texture_units(program)
        return program


def sub_image_layout(size: tuple, interleave: int, halves: int = 1) -> tuple[tuple, list]:
    """The visibility pass's sub-images, one for each place (x, y) in the ``interleave``
    block, of the pixels of ``size`` at that place: their (width, height), each side's
    count of such pixels rounded up (the width to a multiple of ``halves``), and the
    places, the sub-image of (x, y) at (x, y) times that size. With ``halves`` 2 the
    blocks (bx, by) take the regions' halves in turn, h = (bx + by) % 2, and each
    sub-image holds half h's blocks in its h-th column of half its width, block (bx, by)
    at (bx // 2, by) there (shaders/post/environment_visibility.frag)."""
    columns = -(-size[0] // interleave)
    part = (-(-columns // halves) * halves, -(-size[1] // interleave))
    return part, [(x, y) for y in range(interleave) for x in range(interleave)]


@dataclass(frozen=True)
class EnvironmentVisibilityBlurPass(RenderPass):
    """The visibility pass's sums added up along one ``axis`` (0: x, 1: y) over 2N - 1
    pixels, N = ``interleave``, on the pixel's own surface
    (shaders/post/environment_visibility_blur.frag); the second axis writes the ratios
    (``ratio``) that opaque shading reads. Both read and write their values packed in
    unsigned integers (one fetch a tap)."""

    sums: Handle
    size: tuple
    interleave: int
    axis: int
    ratio: bool
    sub_images: bool = False  # ``sums`` laid out as EnvironmentVisibilityPass leaves them
    # maps a direction (world.environment_visibility.region_halves): 2 lays the sub-images
    # out by half, and widens the second pass's window a pixel each side
    halves: int = 1

    name = "environment_visibility_blur"

    def setup(self, builder) -> ImageData:
        builder.read(self.sums)
        name, packing = ("environment_seen", "r32ui") if self.ratio else ("environment_lookups_across", "rgba32ui")
        return ImageData(builder.create(name, ResourceDesc("color", self.size, packing)))

    def describe(self) -> str:
        wide = self.halves > 1 and self.ratio
        return f"{2 * self.interleave + (1 if wide else -1)} pixels along {'xy'[self.axis]}"

    def execute(self, ctx, data: ImageData) -> None:
        begin_fullscreen_pass(ctx, data.image)
        defines = {"ENV_VIS_INTERLEAVE": self.interleave, "ENV_VIS_AXIS": "ivec2(1, 0)" if self.axis == 0 else "ivec2(0, 1)"}
        if self.ratio:
            defines["ENV_VIS_RATIO"] = True
        if self.sub_images:
            defines["ENV_VIS_SUB_IMAGES"] = True
        if self.halves > 1:
            defines["ENV_VIS_HALVES"] = True
        program = ctx.programs.get(FULLSCREEN_VERTEX, BLUR_FRAGMENT, defines)
        bind_texture_units(program)
        if self.sub_images:
            program["u_env_vis_size"].value = tuple(int(side) for side in self.size)
        ctx.image(self.sums).use(TEXTURE_UNITS["u_env_vis_samples"])
        ctx.fullscreen(program)
