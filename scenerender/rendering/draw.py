"""Drawing helpers the passes share: which (object, group) pairs to draw, binding the
camera target, the shadow atlas, texture units and materials."""
from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.inputs import LightsInput, MaterialsInput, ObjectsInput
from scenerender.rendering.lights import LIGHT_BINDING, SHADOW_VIEW_BINDING
from scenerender.world.shadows import atlas_page_name

# The vertex shader of every pass that draws scene meshes.
MESH_VERTEX = "mesh/mesh.vert"
# The vertex shader of every full-screen pass (one triangle, no vertex buffers).
FULLSCREEN_VERTEX = "common/fullscreen.vert"


@dataclass(frozen=True)
class DrawItem:
    object_index: int
    group_index: int
    material: object  # world.materials.Material


def opaque_items(objects: ObjectsInput, camera) -> list[DrawItem]:
    """Visible opaque groups, nearest object first, so the depth test rejects hidden
    fragments before they are shaded."""
    items = [item for item in _items(objects) if not item.material.transparent]
    return sorted(items, key=lambda item: _distance(objects, camera, item.object_index))


def _distance(objects: ObjectsInput, camera, index: int) -> float:
    """Distance from the camera to the nearest point of an object's bounds."""
    lo, hi = objects.frames[index].bounds
    nearest = np.clip(camera.position, lo, hi)
    return float(np.linalg.norm(nearest - camera.position))


def transparent_items(objects: ObjectsInput, camera) -> list[DrawItem]:
    """Visible transparent groups, farthest object first (drawn back to front)."""
    items = [item for item in _items(objects) if item.material.transparent]
    distance = {i: float(np.linalg.norm(objects.frames[i].center - camera.position)) for i in
                {item.object_index for item in items}}
    return sorted(items, key=lambda item: -distance[item.object_index])


def _items(objects: ObjectsInput):
    for index in objects.in_camera_view():
        obj = objects.definitions[index]
        for group_index, material in enumerate(obj.materials):
            if obj.mesh.groups[group_index].count > 0:
                yield DrawItem(index, group_index, material)


def draw_item(objects: ObjectsInput, program, item: DrawItem, mode=None) -> None:
    """Draw one group of one object (its instances in view) with ``program``."""
    objects.draw(program, item.object_index, mode=mode, group=item.group_index)


def cull_hidden_faces(gl, objects: ObjectsInput, index: int) -> None:
    """Before drawing object ``index`` opaque from the camera: skip the faces the camera
    cannot see (world.frame.hidden_faces), or none. The image is the same either way; the
    skipped faces cost nothing (with MSAA, llvmpipe shades every rasterised fragment,
    hidden or not). Callers end with ``stop_culling``."""
    skip_faces(gl, objects.frames[index].hidden_faces)


def skip_faces(gl, faces: str | None) -> None:
    """Skip ``faces`` ("back" or "front") in the draws that follow, or none. Callers end
    with ``stop_culling``."""
    if faces is None:
        gl.disable(moderngl.CULL_FACE)
    else:
        gl.enable(moderngl.CULL_FACE)
        gl.cull_face = faces


def stop_culling(gl) -> None:
    gl.disable(moderngl.CULL_FACE)
    gl.cull_face = "back"


def begin_camera_pass(ctx, colors, depth, clear_color) -> moderngl.Framebuffer:
    """Bind and clear a colour + depth target for drawing meshes from the camera, with the
    depth test on and blending and culling off. Returns the framebuffer."""
    fbo = ctx.framebuffer(colors, depth)
    fbo.use()
    fbo.clear(*clear_color, depth=ctx.depth.clear_value)
    ctx.gl.enable(moderngl.DEPTH_TEST)
    ctx.gl.disable(moderngl.BLEND | moderngl.CULL_FACE)
    ctx.gl.depth_func = ctx.depth.nearer
    return fbo


def begin_fullscreen_pass(ctx, target) -> None:
    """Bind ``target`` (an image handle) with depth test and blending off."""
    ctx.framebuffer([target]).use()
    ctx.gl.disable(moderngl.DEPTH_TEST | moderngl.BLEND)


def begin_fullscreen_pass_where_drawn(ctx, target, depth, empty_value: float) -> moderngl.Framebuffer:
    """Bind ``target`` with the single-sampled camera ``depth`` (both image handles) so that
    a full-screen pass drawn with ``far_plane_defines`` shades only where a surface was
    drawn: its triangle lies on the far plane and the test passes only in front of it.
    Pixels left empty hold ``empty_value``. Without MSAA, llvmpipe skips every 4x4 block
    the depth test rejects, so the sky costs nothing (a branch in the shader saves nothing:
    both sides of it run). Returns the framebuffer; callers end with ``end_where_drawn``."""
    fbo = ctx.framebuffer([target], depth)
    fbo.use()
    fbo.depth_mask = False  # before the clear, which then leaves the depth as it is
    fbo.clear(empty_value, empty_value, empty_value, empty_value)
    ctx.gl.disable(moderngl.BLEND)
    ctx.gl.enable(moderngl.DEPTH_TEST)
    ctx.gl.depth_func = ctx.depth.farther
    return fbo


def far_plane_defines(ctx) -> dict:
    """Defines that put the full-screen triangle on the far plane (common/fullscreen.vert)."""
    return {"FAR_PLANE_Z": ctx.depth.ndc_near_far[1]}


def end_where_drawn(ctx, fbo: moderngl.Framebuffer) -> None:
    fbo.depth_mask = True
    ctx.gl.depth_func = ctx.depth.nearer


def bind_shadow_atlas(ctx, atlas, page: int = 0) -> None:
    """Shadow atlas page ``page`` on its unit, set for hardware-filtered depth comparison."""
    texture = ctx.image(atlas)
    texture.compare_func = "<="
    texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
    texture.use(TEXTURE_UNITS["u_" + atlas_page_name(page)])


def bind_lights(lights: LightsInput) -> None:
    """The packed lights and shadow views (the declared ``lights`` input's value) on the
    binding points shaders/lighting/lights.glsl and shadows.glsl read. The same buffers
    serve programs declaring them as uniform blocks (where they fit) and as storage
    buffers: the two binding namespaces are separate."""
    for buffer, binding in ((lights.buffer, LIGHT_BINDING), (lights.views, SHADOW_VIEW_BINDING)):
        buffer.bind_to_storage_buffer(binding)
        buffer.bind_to_uniform_block(binding)


def bind_texture_units(program) -> None:
    """Point each sampler uniform at its fixed texture unit."""
    for name, unit in TEXTURE_UNITS.items():
        member = program.get(name, None)
        if member is not None:
            member.value = unit


def bind_material(program, material, materials: MaterialsInput) -> None:
    """Material uniforms (this frame's values) and its texture maps."""
    values = materials.values[id(material)]
    set_uniforms(program, u_ka=values["ambient"], u_kd=values["diffuse"], u_ks=values["specular"],
                 u_ke=values["emissive"], u_shininess=values["shininess"], u_opacity=values["opacity"])
    for key, source in material.maps.items():
        texture = materials.textures.texture_2d(source.path, source.srgb)
        _sampler_state(texture, material, source)
        texture.use(TEXTURE_UNITS[f"u_{key}"])
        set_uniforms(program, **{f"u_{key}_st": (*source.uv_scale, *source.uv_offset)})
        if key == "normal_map":
            set_uniforms(program, u_normal_strength=source.strength)


def _sampler_state(texture, material, source) -> None:
    if source.is_placeholder:
        return
    texture.repeat_x = texture.repeat_y = material.wrap != "clamp"
    if material.filter == "nearest":
        texture.filter = (moderngl.NEAREST_MIPMAP_NEAREST, moderngl.NEAREST)
    else:
        texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
