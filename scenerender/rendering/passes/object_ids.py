"""The object-id pass: which object each pixel shows, for comparing renders in scene terms.

Built only when a run asks for it (``Renderer(..., object_ids=True)``, ``render
--object-ids``), so the graph every other run compiles is unchanged. One sample per pixel,
at the pixel centre, whatever the colour target's MSAA: the id of the nearest surface,
opaque or transparent (a glass object names its pixels, not what shows through it),
drawn with the depth test into a single-sampled 16-bit unsigned integer target. An id is
the object's index in ``World.objects`` plus one; 0 is the background (the sky, the
clear colour). Outlines and wireframe overlays are not surfaces and leave no id.
"""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.draw import MESH_VERTEX, begin_camera_pass, cull_hidden_faces, stop_culling
from scenerender.rendering.passes.data import TargetData

# ids are 16-bit: object index + 1 must fit, 0 being the background
MAX_OBJECT_IDS = 65535


@dataclass(frozen=True)
class ObjectIdPass(RenderPass):
    """Draws every object in the camera's view with its id (index + 1), depth-tested, into
    an r16ui image of ``size``; cleared to 0. Faces the camera cannot see are skipped as
    the colour passes skip them, so the visible surface is the same."""

    size: tuple
    camera: Handle
    objects: Handle

    name = "object_ids"

    def setup(self, builder) -> TargetData:
        builder.read(self.camera, self.objects)
        return TargetData(builder.create("object_ids", ResourceDesc("color", self.size, "r16ui")),
                          builder.create("object_ids_depth", ResourceDesc("depth", self.size, "camera_depth")))

    def describe(self) -> str:
        return "one sample per pixel, nearest surface, 16-bit ids"

    def execute(self, ctx, data: TargetData) -> None:
        begin_camera_pass(ctx, [data.color], data.depth, (0.0, 0.0, 0.0, 0.0))
        program = ctx.programs.get(MESH_VERTEX, "mesh/object_id.frag")
        set_uniforms(program, u_view_proj=ctx.input(self.camera).view_proj_relative())
        objects = ctx.input(self.objects)
        try:
            for index in objects.in_camera_view():
                cull_hidden_faces(ctx.gl, objects, index)
                program["u_object_id"].value = index + 1
                objects.draw(program, index)
        finally:
            stop_culling(ctx.gl)
