"""Shadow maps: each shadowed light's casters rendered into its tiles of an atlas page."""
from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import bind_material, bind_texture_units, skip_faces, stop_culling
from scenerender.rendering.features import mask_defines
from scenerender.rendering.steps import CHECKPOINT_TEXELS, Waits
from scenerender.world.facing import hidden_side
from scenerender.world.shadows import CUBE_MAP_KINDS, atlas_page_name, back_page_name, hidden_from_light


@dataclass(frozen=True)
class ShadowMapData:
    atlas: Handle


@dataclass(frozen=True)
class ShadowMapPass(RenderPass):
    """Renders the shadow casters' depth from one light into its tiles of an atlas page
    (world.shadows). The first pass of a page creates and clears the whole page (a clear
    of a whole texture is the fast one); later ones write their own tiles of it and leave
    the others untouched. A page's passes all run in the same frames: the page holds maps
    drawn once, or maps redrawn every frame.

    light_name, kind, map_size, pcf: what the dump shows. page: which page;
    page_size: its (width, height). views: the light's ``shadow_views`` input, dynamic
    wherever the views follow the camera. materials: the ``materials`` input, read only in
    a scene with alpha-masked materials (glTF MASK), whose cut-away pixels cast no shadow.
    page_name: the depth texture's name where it is not an atlas page, and ``note`` what
    the dump shows instead (the environment's visibility maps, rendering.pipeline).
    back_faces: draw the casters' far side as the light sees it (the faces turned away
    from it) into the page's back-face twin, same tiles (render.shadows.casters: solid):
    a closed caster then fills the depths between the two maps, an open surface is thin.
    """

    keeps_unchanged = True  # casters are drawn relative to the light, never the camera

    light_name: str
    kind: str
    map_size: int
    pcf: int
    page: int
    page_size: tuple
    views: Handle
    objects: Handle
    atlas_in: Handle | None = None
    materials: Handle | None = None
    page_name: str | None = None
    note: str = ""
    back_faces: bool = False

    @property
    def name(self) -> str:
        return f"shadow_back:{self.light_name}" if self.back_faces else f"shadow:{self.light_name}"

    def setup(self, builder) -> ShadowMapData:
        builder.read(self.views, self.objects, *((self.materials,) if self.materials is not None else ()))
        if self.atlas_in is None:
            name = self.page_name or (back_page_name if self.back_faces else atlas_page_name)(self.page)
            return ShadowMapData(builder.create(name, ResourceDesc("depth", self.page_size, "depth24")))
        return ShadowMapData(builder.write(self.atlas_in, own_region=True))  # its own tiles

    def describe(self) -> str:
        if self.note:
            return self.note
        views = "6 cube faces" if self.kind in CUBE_MAP_KINDS else "1 view"
        back = ", back faces" if self.back_faces else ""
        return f"{self.kind} light, {views}, {self.map_size}px, pcf {self.pcf}{back}"

    def execute(self, ctx, data: ShadowMapData) -> None:
        gl = ctx.gl
        fbo = ctx.framebuffer([], data.atlas)
        fbo.use()
        # directional views are orthographic: window depth is linear depth already (their
        # range spans every caster and receiver, so nothing needs the shader's clamp)
        defines = ({"RADIAL_DEPTH": True} if self.kind in CUBE_MAP_KINDS
                   else {"directional": {"ORTHOGRAPHIC": True}}.get(self.kind, {}))
        program = ctx.programs.get("shadow/depth.vert", "shadow/depth.frag", defines)
        gl.enable(moderngl.DEPTH_TEST)
        gl.depth_func = "<"  # the atlas keeps linear depth, nearest = 0, whatever the camera's convention
        gl.disable(moderngl.BLEND)
        views = ctx.input(self.views).views
        if self.atlas_in is None:
            fbo.viewport = (0, 0, *self.page_size)
            fbo.clear(depth=1.0)
        elif not ctx.written_this_frame(self.atlas_in):
            # the page's first pass kept last frame's maps, so this pass clears its own tiles
            for view in views:
                fbo.clear(depth=1.0, viewport=(view.tile.x, view.tile.y, view.tile.size, view.tile.size))
        # casters are drawn relative to the light's eye, not the camera: the map is then a
        # function of the views and the objects alone (so a frame may keep it, and any
        # frame that draws it draws the same bytes)
        objects = ctx.input(self.objects)
        casters = objects.shadow_casters()
        eye = views[0].eye  # one anchor for all of a point light's faces
        for index in casters:
            ctx.place_instances(objects, index, eye)
        from_eye = np.eye(4)
        from_eye[:3, 3] = eye
        masked = self._masked_programs(ctx, defines, objects, casters)
        # many large maps (the environment's visibility: up to 64, 16 of 4096 px) take
        # seconds on a software renderer: a signal stops them between maps (the clear
        # before them, one memory fill, is left out)
        waits = Waits(ctx, CHECKPOINT_TEXELS)
        for view in views:
            tile = view.tile
            waits.before(tile.size * tile.size)
            fbo.viewport = (tile.x, tile.y, tile.size, tile.size)
            for used in [program, *masked.values()]:
                set_uniforms(used, u_light_view=view.view @ from_eye,
                             u_light_projection=ctx.depth.clip_projection(view.projection),
                             u_depth_range=(view.near, view.far))
            for index in casters:
                frame = objects.frames[index]
                # faces turned away from the light never hold the nearest depth (nor, the
                # other way round, the faces it sees the back-face map's)
                skip_faces(gl, self._skipped(view, frame))
                materials = objects.definitions[index].materials
                if any(id(material) in masked for material in materials):
                    for group, material in enumerate(materials):
                        if id(material) in masked:
                            bind_material(masked[id(material)], material, ctx.input(self.materials))
                        ctx.draw_placed(masked.get(id(material), program), objects, index, group)
                else:
                    ctx.draw_placed(program, objects, index)
        stop_culling(gl)

    def _skipped(self, view, frame) -> str | None:
        """The faces this pass leaves out of a caster (``frame``: its ObjectFrame). The
        back-face map leaves out the side any outside viewpoint sees, even where the near
        plane may cut into the caster (a spot light's wide view): a caster drawn on both
        sides there would be thin. An open surface is drawn on both sides."""
        if not self.back_faces:
            return hidden_from_light(view, frame.winding, frame.bounds)
        hidden = hidden_side(frame.winding)
        return None if hidden is None else ("front" if hidden == "back" else "back")

    def _masked_programs(self, ctx, defines: dict, objects, casters) -> dict:
        """{id(material): program} for the alpha-masked materials of the casters."""
        if self.materials is None:
            return {}
        programs = {}
        for index in casters:
            for material in objects.definitions[index].materials:
                if material.masked and id(material) not in programs:
                    program = ctx.programs.get("shadow/depth.vert", "shadow/depth.frag",
                                               {**defines, **mask_defines(material)})
                    bind_texture_units(program)
                    programs[id(material)] = program
        return programs
