"""Drawing scene meshes: which (object, group) pairs to draw and how to bind a material."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.features import TEXTURE_UNITS


@dataclass(frozen=True)
class DrawItem:
    object_index: int
    group_index: int
    material: object  # world.materials.Material


def opaque_items(world, frame) -> list[DrawItem]:
    """Visible opaque groups, nearest object first, so the depth test rejects hidden
    fragments before they are shaded."""
    items = [item for item in _items(world, frame) if not item.material.transparent]
    return sorted(items, key=lambda item: _distance(frame, item.object_index))


def _distance(frame, index: int) -> float:
    """Distance from the camera to the nearest point of an object's bounds."""
    lo, hi = frame.objects[index].bounds
    nearest = np.clip(frame.camera.position, lo, hi)
    return float(np.linalg.norm(nearest - frame.camera.position))


def transparent_items(world, frame) -> list[DrawItem]:
    """Visible transparent groups, farthest object first (drawn back to front)."""
    items = [item for item in _items(world, frame) if item.material.transparent]
    distance = {i: float(np.linalg.norm(frame.objects[i].center - frame.camera.position)) for i in
                {item.object_index for item in items}}
    return sorted(items, key=lambda item: -distance[item.object_index])


def _items(world, frame):
    for index, obj in enumerate(world.objects):
        if frame.objects[index].in_view == 0:
            continue
        for group_index, material in enumerate(obj.materials):
            if obj.mesh.groups[group_index].count > 0:
                yield DrawItem(index, group_index, material)


def begin_camera_pass(ctx, colors, depth, clear_color) -> object:
    """Bind and clear a colour + depth target for drawing meshes from the camera, with the
    depth test on and blending and culling off. Returns the framebuffer."""
    import moderngl

    fbo = ctx.framebuffer(colors, depth)
    fbo.use()
    fbo.clear(*clear_color, depth=ctx.depth.clear_value)
    ctx.gl.enable(moderngl.DEPTH_TEST)
    ctx.gl.disable(moderngl.BLEND | moderngl.CULL_FACE)
    ctx.gl.depth_func = ctx.depth.nearer
    return fbo


def bind_shadow_atlas(ctx, atlas) -> None:
    """The shadow atlas on its unit, set for hardware-filtered depth comparison."""
    import moderngl

    texture = ctx.resource(atlas)
    texture.compare_func = "<="
    texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
    texture.use(TEXTURE_UNITS["u_shadow_atlas"])


def bind_texture_units(program) -> None:
    """Point each sampler uniform at its fixed texture unit."""
    for name, unit in TEXTURE_UNITS.items():
        member = program.get(name, None)
        if member is not None:
            member.value = unit


def bind_material(ctx, program, material) -> None:
    """Material uniforms (this frame's values) and its texture maps."""
    values = ctx.frame.materials[id(material)]
    set_uniforms(program, u_ka=values["ambient"], u_kd=values["diffuse"], u_ks=values["specular"],
                 u_ke=values["emissive"], u_shininess=values["shininess"], u_opacity=values["opacity"])
    for key, source in material.maps.items():
        texture = ctx.scene.textures.texture_2d(source.path, source.srgb)
        _sampler_state(texture, material, source)
        texture.use(TEXTURE_UNITS[f"u_{key}"])
        set_uniforms(program, **{f"u_{key}_st": (*source.uv_scale, *source.uv_offset)})
        if key == "normal_map":
            set_uniforms(program, u_normal_strength=source.strength)


def _sampler_state(texture, material, source) -> None:
    import moderngl

    if source.is_placeholder:
        return
    texture.repeat_x = texture.repeat_y = material.wrap != "clamp"
    if material.filter == "nearest":
        texture.filter = (moderngl.NEAREST_MIPMAP_NEAREST, moderngl.NEAREST)
    else:
        texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)


def draw_item(ctx, program, item: DrawItem, mode=None) -> None:
    """Draw one group of one object (its instances in view) with ``program``."""
    obj = ctx.world.objects[item.object_index]
    group = obj.mesh.groups[item.group_index]
    draw_object(ctx, program, item.object_index, mode=mode, first=group.first * 3, vertices=group.count * 3)


def camera_objects(ctx) -> list[int]:
    """Indices of objects with at least one instance in the camera's view."""
    return [i for i, state in enumerate(ctx.frame.objects) if state.in_view > 0]


def light_objects(ctx) -> list[int]:
    """Indices of visible objects that cast shadows (seen from a light, view culling does
    not apply: a caster outside the camera's view still shadows what is in it)."""
    return [i for i, obj in enumerate(ctx.world.objects) if obj.cast_shadows and ctx.frame.objects[i].visible]


def draw_object(ctx, program, index: int, *, all_instances: bool = False, mode=None, first: int = 0,
                vertices: int | None = None, welded_normals: bool = False) -> None:
    """Draw object ``index`` with ``program``: the instances in the camera's view, or all of
    them (``all_instances``, for passes drawn from a light)."""
    import moderngl

    obj = ctx.world.objects[index]
    state = ctx.frame.objects[index]
    count = state.count if all_instances else state.in_view
    if count == 0:
        return
    vao = ctx.scene.vertex_array(program, index, welded_normals)
    vao.render(mode if mode is not None else moderngl.TRIANGLES,
               vertices=obj.mesh.triangle_count * 3 if vertices is None else vertices, first=first, instances=count)
