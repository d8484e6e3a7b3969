"""Drawing helpers the passes share: which (object, group) pairs to draw, binding the
camera target, the shadow atlas, texture units and materials."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import moderngl
import numpy as np

from scenerender.gpu.uniforms import set_uniforms
from scenerender.rendering.features import TEXTURE_UNITS, mask_defines
from scenerender.rendering.graph_inputs import LightsInput, MaterialsInput, ObjectsInput
from scenerender.rendering.light_buffers import LIGHT_BINDING, SHADOW_VIEW_BINDING
from scenerender.world.shadows import atlas_page_name, back_page_name

# The vertex shader of every pass that draws scene meshes.
MESH_VERTEX = "mesh/mesh.vert"
# The vertex shader of every full-screen pass (one triangle, no vertex buffers).
FULLSCREEN_VERTEX = "common/fullscreen.vert"
# The GGX lobe's linearly transformed cosines, fitted by benchmarks/ltc/fit_ltc.py.
LTC_TABLE = Path(__file__).with_name("ltc_ggx.npy")


@dataclass(frozen=True)
class DrawItem:
    object_index: int
    group_index: int
    material: object  # world.materials.Material


def opaque_items(objects: ObjectsInput, camera) -> list[DrawItem]:
    """Visible opaque groups, nearest object first, so the depth test rejects hidden
    fragments before they are shaded."""
    items = [item for item in _items(objects) if not item.material.transparent]
    distance = _distances(objects, camera, sorted({item.object_index for item in items}))
    return sorted(items, key=lambda item: distance[item.object_index])


def _distances(objects: ObjectsInput, camera, indices: list[int]) -> dict:
    """Object index -> distance from the camera to the nearest point of its bounds."""
    if not indices:
        return {}
    bounds = np.array([objects.frames[i].bounds for i in indices])
    eye = np.asarray(camera.position, dtype=np.float64)
    nearest = np.clip(eye, bounds[:, 0], bounds[:, 1])
    return dict(zip(indices, np.sqrt(((nearest - eye) ** 2).sum(axis=1)).tolist()))


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


def draw_cutting_masks(ctx, objects: ObjectsInput, index: int, program, fragment: str, defines: dict,
                       materials: MaterialsInput | None, uniforms: dict) -> None:
    """Draw object ``index`` from the camera with ``program`` in a pass that draws no
    material colour (the geometry prepass, the shadow view), except that the groups of an
    alpha-masked material (glTF MASK) use ``fragment`` with that material's alpha
    (features.mask_defines, shaders/lighting/alpha_mask.glsl) and ``uniforms``, so that
    their cut-away pixels are not drawn. ``materials``: the ``materials`` input's value,
    None where the scene has no masked material."""
    obj = objects.definitions[index]
    if materials is None or not any(material.masked for material in obj.materials):
        objects.draw(program, index)
        return
    for group, material in enumerate(obj.materials):
        used = program
        if material.masked:
            used = ctx.programs.get(MESH_VERTEX, fragment, {**defines, **mask_defines(material)})
            bind_texture_units(used)
            set_uniforms(used, **uniforms)
            bind_material(used, material, materials)
        objects.draw(used, index, group=group)


def draw_item(objects: ObjectsInput, program, item: DrawItem, mode=None) -> None:
    """Draw one group of one object (its instances in view) with ``program``."""
    objects.draw(program, item.object_index, mode=mode, group=item.group_index)


def cull_hidden_faces(gl, objects: ObjectsInput, index: int) -> None:
    """Before drawing object ``index`` opaque from the camera: skip the faces the camera
    cannot see (world.frame.hidden_faces), or none. The image is the same either way; the
    skipped faces cost nothing (with MSAA, llvmpipe shades every rasterised fragment,
    hidden or not). Callers end with ``stop_culling``."""
    skip_faces(gl, objects.frames[index].hidden_faces)


def single_sided_faces(objects: ObjectsInput, index: int) -> str | None:
    """The faces a single-sided material (glTF ``doubleSided: false``) of object ``index``
    does not show, as GL names them: "back" where every instance keeps the mesh's
    counter-clockwise front faces, "front" where every instance mirrors them, None where
    the instances differ (then both are drawn)."""
    models = objects.frames[index].models
    signs = np.sign(np.linalg.det(models[:, :3, :3]))
    if np.all(signs > 0):
        return "back"
    if np.all(signs < 0):
        return "front"
    return None


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


def bind_shadow_depth(ctx, atlas, page: int = 0) -> None:
    """Shadow atlas page ``page`` once more, as plain depth (a sampler with comparison off
    over the same texture): the blocker search of soft shadows reads it
    (shaders/lighting/soft_shadows.glsl)."""
    unit = TEXTURE_UNITS["u_shadow_depth" if page == 0 else f"u_shadow_depth_{page + 1}"]
    ctx.image(atlas).use(unit)
    ctx.shared("plain_depth_sampler", _plain_depth_sampler).use(unit)


def bind_light_tables(ctx, atlas_pages, back_pages: tuple = ()) -> None:
    """What the direct lights read besides their buffers: the LTC table where the scene has
    area lights, and each shadow atlas page (``atlas_pages``: handles), with its plain depth
    too where shadows are soft, and its casters' back faces where they are solid
    (``back_pages``: (page, handle) pairs). The forward pass and the probes' captures share it."""
    if ctx.features.n_area:
        bind_ltc(ctx)
    for page, handle in enumerate(atlas_pages):
        bind_shadow_atlas(ctx, handle, page)
        if ctx.features.soft_shadows:
            bind_shadow_depth(ctx, handle, page)
    for page, handle in back_pages:
        unit = TEXTURE_UNITS[f"u_{back_page_name(page)}"]
        ctx.image(handle).use(unit)
        ctx.shared("plain_depth_sampler", _plain_depth_sampler).use(unit)


def _plain_depth_sampler(gl):
    return gl.sampler(filter=(moderngl.NEAREST, moderngl.NEAREST), compare_func="", repeat_x=False, repeat_y=False)


def bind_ltc(ctx) -> None:
    """The GGX lobe's linearly transformed cosines (shaders/lighting/area.glsl, the pbr
    model's rectangle and disk lights) on their unit: a static table, made once a run."""
    ctx.shared("ltc_ggx", _ltc_texture).use(TEXTURE_UNITS["u_ltc"])


def _ltc_texture(gl):
    """ltc_ggx.npy (benchmarks/ltc/fit_ltc.py wrote it), (roughness, view, 6), as one RGBA
    float texture: x N.V's column, y the roughness row; rows 0 .. n-1 hold M^-1's
    (m02, m11, m20, m22), rows n .. 2n-1 the lobe's (magnitude, Fresnel part, 0, 0)."""
    table = np.load(LTC_TABLE).astype(np.float32)
    rows, columns = table.shape[:2]
    texels = np.zeros((2 * rows, columns, 4), np.float32)
    texels[:rows] = table[:, :, :4]
    texels[rows:, :, :2] = table[:, :, 4:6]
    texture = gl.texture((columns, 2 * rows), 4, texels.tobytes(), dtype="f4")
    texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
    texture.repeat_x = texture.repeat_y = False
    return texture


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
    """Material uniforms (this frame's values) and its texture maps (those the program
    samples: a map only the pbr model reads is not bound for the others)."""
    values = materials.values[id(material)]
    emissive = values["emissive"] if material.emissive_strength == 1.0 else values["emissive"] * material.emissive_strength
    set_uniforms(program, u_ka=values["ambient"], u_kd=values["diffuse"], u_ks=values["specular"],
                 u_ke=emissive, u_shininess=values["shininess"], u_opacity=values["opacity"],
                 u_metallic=values["metallic"], u_roughness=values["roughness"],
                 u_alpha_cutoff=material.alpha_cutoff, u_occlusion_strength=material.occlusion_strength)
    if material.dielectric_specular:
        f0, f90 = material.dielectric_f0_f90()
        set_uniforms(program, u_dielectric_f0=tuple(f0), u_dielectric_f90=f90)
        if "specular_color_map" in material.maps or "specular_glossiness_map" in material.maps:
            set_uniforms(program, u_dielectric_reflectance=tuple(material.dielectric_reflectance()))
    if material.clearcoat > 0.0:
        set_uniforms(program, u_clearcoat=material.clearcoat, u_clearcoat_roughness=material.clearcoat_roughness)
    if material.sheen:
        set_uniforms(program, u_sheen_color=tuple(material.sheen_color), u_sheen_roughness=material.sheen_roughness)
    if material.anisotropy > 0.0:
        set_uniforms(program, u_anisotropy=material.anisotropy, u_anisotropy_direction=material.anisotropy_direction())
    if material.iridescence > 0.0:
        set_uniforms(program, u_iridescence=material.iridescence, u_iridescence_ior=material.iridescence_ior,
                     u_iridescence_thickness=material.iridescence_thickness,
                     u_iridescence_thickness_min=material.iridescence_thickness_min)
    if material.transmissive:
        distance = material.attenuation_distance
        set_uniforms(program, u_transmission=material.transmission, u_transmission_ior=material.ior,
                     u_thickness=material.thickness, u_attenuation_color=tuple(material.attenuation_color),
                     u_attenuation_distance=0.0 if distance == float("inf") else distance)
    for key, source in material.maps.items():
        if program.get(f"u_{key}", None) is None:
            continue
        texture = materials.textures.texture_2d(source.path, source.srgb)
        _sampler_state(texture, material, source)
        texture.use(TEXTURE_UNITS[f"u_{key}"])
        set_uniforms(program, **{f"u_{key}_st": (*source.uv_scale, *source.uv_offset), f"u_{key}_skew": source.uv_skew})
        if key == "normal_map":
            set_uniforms(program, u_normal_strength=source.strength * material.normal_scale)
        if key == "clearcoat_normal_map":
            set_uniforms(program, u_clearcoat_normal_strength=source.strength)


def _sampler_state(texture, material, source) -> None:
    if source.is_placeholder:
        return
    texture.repeat_x = texture.repeat_y = material.wrap != "clamp"
    if material.filter == "nearest":
        texture.filter = (moderngl.NEAREST_MIPMAP_NEAREST, moderngl.NEAREST)
    else:
        texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
