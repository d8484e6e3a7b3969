"""The object-id pass: which object each pixel shows, for comparing renders in scene terms.

Built only when a run asks for it (``Renderer(..., object_ids=True)``, ``render
--object-ids``), so the graph every other run compiles is unchanged. One sample per pixel,
at the pixel centre, whatever the colour target's MSAA: the id of the nearest surface,
opaque or transparent (a glass object names its pixels), drawn with the depth test into
a single-sampled 16-bit unsigned integer target. A second target, the layer behind, keeps
the nearest opaque surface (what shows through the glass): the opaque surfaces are drawn
first into both targets at once, then the transparent ones into the first alone, against
the same depth. An id is the object's index in ``World.objects`` plus one; 0 is the
background (the sky, the clear colour). Outlines and wireframe overlays are not surfaces
and leave no id.
"""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import (
    MESH_VERTEX, begin_camera_pass, cull_hidden_faces, draw_item, opaque_items, stop_culling, transparent_items,
)


@dataclass(frozen=True)
class ObjectIdData:
    """The ids of the nearest surface (``color``), of the nearest opaque one (``behind``),
    and the depth they were drawn with."""

    color: Handle
    behind: Handle
    depth: Handle


@dataclass(frozen=True)
class ObjectIdPass(RenderPass):
    """Draws every object in the camera's view with its id (index + 1), depth-tested, into
    two r16ui images of ``size``, cleared to 0: the nearest surface, and the nearest opaque
    surface behind any transparent one. Faces the camera cannot see are skipped as the
    colour passes skip them, so the visible surface is the same."""

    size: tuple
    camera: Handle
    objects: Handle

    name = "object_ids"

    def setup(self, builder) -> ObjectIdData:
        builder.read(self.camera, self.objects)
        return ObjectIdData(builder.create("object_ids", ResourceDesc("color", self.size, "r16ui")),
                            builder.create("object_ids_behind", ResourceDesc("color", self.size, "r16ui")),
                            builder.create("object_ids_depth", ResourceDesc("depth", self.size, "camera_depth")))

    def describe(self) -> str:
        return "one sample per pixel, nearest surface and nearest opaque surface, 16-bit ids"

    def execute(self, ctx, data: ObjectIdData) -> None:
        objects, camera = ctx.input(self.objects), ctx.input(self.camera)
        begin_camera_pass(ctx, [data.color, data.behind], data.depth, (0.0, 0.0, 0.0, 0.0))
        view_proj = camera.view_proj_relative()
        both = ctx.programs.get(MESH_VERTEX, "mesh/object_id.frag", {"BEHIND_LAYER": 1})
        self._draw(ctx, both, view_proj, objects, opaque_items(objects, camera))
        transparent = transparent_items(objects, camera)
        if transparent:  # the same depth, the first target alone: the layer behind keeps the opaque
            ctx.framebuffer([data.color], data.depth).use()
            self._draw(ctx, ctx.programs.get(MESH_VERTEX, "mesh/object_id.frag"), view_proj, objects, transparent)

    @staticmethod
    def _draw(ctx, program, view_proj, objects, items) -> None:
        set_uniforms(program, u_view_proj=view_proj)
        try:
            for item in items:
                cull_hidden_faces(ctx.gl, objects, item.object_index)
                program["u_object_id"].value = item.object_index + 1
                draw_item(objects, program, item)
        finally:
            stop_culling(ctx.gl)
