"""Build the render graph for a World: which passes this scene needs, in order.

The builder adds a pass only for features the scene has (a skybox pass only with a
skybox, shadow passes only for shadowed lights...). The render mode then picks which image
the readback takes, and compiling the graph culls every pass that image does not need:
``mode: depth`` keeps the geometry prepass and drops shading, shadows and the sky.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from scenerender.graph import FrameGraph
from scenerender.rendering.features import environment_shades, specular_layout, visibility_min_alpha
from scenerender.rendering.graph_inputs import InputHandles, import_inputs
from scenerender.rendering.passes.forward import OpaquePass, OutlinePass, Shading, TransparentPass, WireframeOverlayPass
from scenerender.rendering.passes.output import (
    NO_TONE, OutputTransformPass, ReadbackPass, ResolveOutputPass, ResolvePass, ResolveToSrgbPass, ToneCurve,
)
from scenerender.rendering.passes.sky import NO_SKY, EnvironmentSky, SkyboxPass, SkyUnder
from scenerender.world.environment_visibility import interleave_pattern, visibility_tiles
from scenerender.world.build import scene_bounds
from scenerender.world.frame import FrameEvaluator
from scenerender.world.probe_grid import probe_grid
from scenerender.world.probe_updates import ProbeUpdates
from scenerender.world.settings import DATA_MODES, AmbientOcclusionSettings

# The passes of features only some scenes have (ambient occlusion, the lens and motion
# blurs, bloom, the data views, the environment light, shadow maps, object ids) are
# imported where the builder adds them: a one-frame render is mostly start-up, and a scene
# without them need not pay for their modules (tests/test_startup.py).
if TYPE_CHECKING:
    from scenerender.rendering.passes.environment import EnvironmentLighting


@dataclass(frozen=True)
class GraphOptions:
    size: tuple
    samples: int  # what the device gives (GraphRenderer clamps the scene's request to it)
    want_linear: bool = False  # also read back linear HDR (EXR output)
    object_ids: bool = False   # also read back which object each pixel shows (passes/object_ids.py)
    # Choices the builder normally makes per scene; set only to measure the alternatives.
    depth_prepass: bool | None = None
    fuse_resolve: bool = True
    hdr_target: bool | None = None
    sky_behind_samples: bool = True  # with MSAA, the resolve adds the sky (passes/sky.py)
    # the device reports which samples passed the depth test (GL_ARB_post_depth_coverage);
    # GraphRenderer sets what its context offers
    post_depth_coverage: bool = True
    visible_samples: bool | None = None
    shader_srgb_encoding: bool | None = None  # pipeline.shader_encoding_pays
    # render.indirect where the scene moves: draw only the probes a change touches
    # (world.probe_updates); False bakes every probe each frame
    indirect_updates: bool = True


def build_graph(world, atlas, options: GraphOptions) -> tuple[FrameGraph, InputHandles]:
    """The full graph for ``world`` and the handles of its inputs; call ``.compile()`` on
    the graph to cull and order it."""
    graph = FrameGraph()
    inputs = import_inputs(graph, world)
    settings = world.settings
    size, samples = options.size, options.samples

    shadow_passes, atlas_pages = _add_shadow_passes(graph, world, atlas, inputs)
    back_pages = _add_back_face_passes(graph, world, atlas, inputs) if atlas_pages else ()

    gbuffer = ao = None
    fill = settings.mode if settings.mode in ("wireframe", "points") else "solid"
    lens_blur = inputs.lens is not None and fill == "solid"  # render.depth_of_field: gather
    velocity_blur = inputs.motion is not None and fill == "solid"  # render.motion_blur: velocity
    if (settings.ambient_occlusion is not None or settings.mode in ("depth", "normals", "ambient_occlusion")
            or lens_blur):
        # EXR's depth view holds distances in scene units: 32-bit, not float16's 11 bits
        precision = "rgba32f" if settings.mode == "depth" and options.want_linear else "rgba16f"
        from scenerender.rendering.passes.ambient_occlusion import GBufferPass  # deferred: see the imports

        geometry = graph.add(GBufferPass(size, inputs.camera, inputs.objects, _masked_materials(world, inputs),
                                         precision))
        gbuffer = geometry.color
    if settings.ambient_occlusion is not None or settings.mode == "ambient_occlusion":
        from scenerender.rendering.passes.ambient_occlusion import SSAOBlurPass, SSAOPass  # deferred: see the imports

        raw = graph.add(SSAOPass(gbuffer, geometry.depth, inputs.camera, size,
                                 settings.ambient_occlusion or AmbientOcclusionSettings.default())).image
        ao = graph.add(SSAOBlurPass(raw, size)).image
    visible = fill == "solid" and (options.visible_samples if options.visible_samples is not None
                                   else visible_samples_pay(world, samples, options.post_depth_coverage))
    environment = _environment_lighting(graph, world, inputs, size)
    indirect = (_indirect_lighting(graph, world, inputs, atlas, atlas_pages, environment, back_pages,
                                   options.indirect_updates)
                if fill == "solid" and settings.indirect is not None else None)
    shading = Shading(inputs, atlas_pages, ao if settings.ambient_occlusion is not None else None, visible,
                      environment, indirect, back_pages)
    prepass = fill == "solid" and (options.depth_prepass if options.depth_prepass is not None
                                   else visible or prepass_pays(world, atlas, size, samples))
    tone = _tone_curve(world, inputs)
    bloom = settings.bloom if fill == "solid" and settings.bloom is not None and settings.bloom.strength > 0 else None
    hdr = (options.hdr_target if options.hdr_target is not None
           else hdr_target_pays(options, settings.output_transform,
                                tone is not NO_TONE or bloom is not None or lens_blur or velocity_blur))
    # with MSAA the resolve adds the sky behind the samples; without, a pass draws it (passes/sky.py)
    skybox = _sky(world, inputs)
    sky = SkyUnder(inputs.camera, skybox) if skybox is not None and samples > 1 and options.sky_behind_samples else NO_SKY
    encode_in_shader = not hdr and (options.shader_srgb_encoding if options.shader_srgb_encoding is not None
                                    else shader_encoding_pays(samples))
    opaque = graph.add(OpaquePass(size, samples, shading, inputs.background, fill, prepass,
                                  "rgba16f" if hdr else "srgba8", settings.line_width, settings.point_size,
                                  sky_behind=sky is not NO_SKY, encode_in_shader=encode_in_shader))
    color, depth = opaque.color, opaque.depth
    if skybox is not None and sky is NO_SKY:
        color = graph.add(SkyboxPass(color, depth, inputs.camera, skybox)).image
    lines_and_points = (fill, settings.line_width, settings.point_size)  # how wireframe and points draw
    if inputs.outlines is not None:
        color = graph.add(OutlinePass(color, depth, inputs.camera, inputs.objects, inputs.outlines,
                                      *lines_and_points)).image
    if any(m.transparent for m in world.materials()):
        transmission = _transmission_source(graph, world, color, size, samples, sky)
        color = graph.add(TransparentPass(color, depth, shading, *lines_and_points, transmission)).image
    if settings.wireframe_overlay:
        color = graph.add(WireframeOverlayPass(color, depth, inputs.camera, inputs.objects, settings.line_width)).image
    if bloom is not None or lens_blur or velocity_blur:
        # the motion blur, the lens blur and bloom read the resolved linear image and hand on their own
        if samples > 1:
            color = graph.add(ResolvePass(color, size, sky=sky)).image
        if velocity_blur:
            from scenerender.rendering.passes.motion_blur import add_velocity_blur  # deferred: see the imports

            color = add_velocity_blur(graph, color, inputs, size)
        if lens_blur:
            from scenerender.rendering.passes.depth_of_field import add_depth_of_field  # deferred: see the imports

            color = add_depth_of_field(graph, color, gbuffer, inputs, size)
        if bloom is not None:
            from scenerender.rendering.passes.bloom import add_bloom  # deferred: see the imports

            color = add_bloom(graph, color, size, bloom)
        final = graph.add(OutputTransformPass(color, size, settings.output_transform, settings.gamma, tone)).image
    elif not hdr and settings.output_transform == "srgb" and tone is NO_TONE and options.fuse_resolve:
        # the 8-bit sRGB target already holds the output values: resolve (in linear
        # light) where multisampled, and read back
        final = graph.add(ResolveToSrgbPass(color, size, sky=sky)).image if samples > 1 else color
    elif samples > 1 and not options.want_linear and options.fuse_resolve:
        # nothing needs the resolved linear image: resolve and encode in one pass
        final = graph.add(ResolveOutputPass(color, size, settings.output_transform, settings.gamma, tone,
                                            samples=samples, sky=sky)).image
    else:
        if samples > 1:
            color = graph.add(ResolvePass(color, size, sky=sky)).image
        final = graph.add(OutputTransformPass(color, size, settings.output_transform, settings.gamma, tone)).image

    linear = color if options.want_linear else None
    if settings.mode in DATA_MODES:
        view_format = "rgba32f" if options.want_linear else "rgba8"
        final = _add_view(graph, world, settings.mode, inputs, gbuffer, ao, shadow_passes, size, view_format)
        linear = final if options.want_linear else None  # the values themselves, not a colour
    ids = _add_object_ids(graph, size, inputs) if options.object_ids else None
    graph.add(ReadbackPass(final, size, linear, ids and ids.color, ids and ids.behind))
    return graph, inputs


def _sky(world, inputs: InputHandles):
    """What the sky shows: the environment light's image where it says ``background:
    true``, else render.skybox's cube map, else nothing (None)."""
    if world.environment is not None and world.environment.background:
        return EnvironmentSky(inputs.environment, inputs.environment_map)
    return inputs.skybox


def _tone_curve(world, inputs: InputHandles) -> ToneCurve:
    """What the output transform applies before encoding: NO_TONE where the exposure stays
    0 and the tone map is ``none`` (the output shader and the image are as without either)."""
    curve = world.settings.tone_map
    if curve == "none" and inputs.exposure is None:
        return NO_TONE
    if inputs.exposure is None:
        return ToneCurve(curve)
    exposure = world.render.exposure
    text = "animated exposure" if not exposure.is_constant else f"exposure {exposure(0.0):+g}"
    return ToneCurve(curve, inputs.exposure, text)


# A depth prepass pays only where opaque surfaces cover the image this many times over
# (depth_complexity's estimate). Measured with Mesa llvmpipe without MSAA:
# benchmarks/scenes/overdraw.yaml (estimate 5.9) renders 25% faster with it; the
# benchmark scene and the showcase (1.1 and 1.3) are 10-15% slower with it.
PREPASS_DEPTH_COMPLEXITY = 4.0


def _environment_lighting(graph, world, inputs: InputHandles, size: tuple) -> EnvironmentLighting | None:
    """The environment light's lookups, with the pass that prefilters its image, where a
    material the scene draws lit takes light from it: a pbr material, or a Phong or
    Blinn-Phong one when the light says ``classic: true``. With its visibility shared out
    over pixel blocks, the pass that looks it up at the camera's ``size``."""
    environment = world.environment
    if environment is None or not any(environment_shades(environment.classic, m.model(world.settings.shading))
                                      for m in world.materials()):
        return None
    from scenerender.rendering.passes.environment import (  # deferred: see the imports
        EnvironmentLighting, EnvironmentPrefilterPass, EnvironmentSurfacesPass, EnvironmentVisibilityBlurPass,
        EnvironmentVisibilityPass,
    )
    from scenerender.rendering.passes.shadow import ShadowMapPass  # deferred: see the imports

    specular = graph.add(EnvironmentPrefilterPass(inputs.environment_map, specular_layout(environment),
                                                  environment.samples)).image
    visibility = None
    if inputs.environment_views is not None:
        halves = world.environment_halves
        page_size, tiles = visibility_tiles(environment.visibility, environment.visibility_map_size, halves)
        note = (f"{environment.visibility} directions of the environment, {tiles[0].size}px each" if halves == 1 else
                f"{environment.visibility} directions of the environment in halves, {len(tiles)} maps of {tiles[0].size}px")
        visibility = graph.add(ShadowMapPass(f"{environment.name} visibility", "directional", tiles[0].size, 2, 0,
                                             page_size, inputs.environment_views, inputs.objects, None,
                                             _masked_materials(world, inputs, casters_only=True),
                                             page_name="environment_visibility", note=note)).atlas
    lookups, scale = None, (1.0, 1.0)
    interleave, _ = interleave_pattern(environment.visibility, environment.visibility_interleave)
    if visibility is not None and interleave > 1:
        lookup_size = visibility_lookup_size(size, environment.visibility_half_resolution)
        scale = (lookup_size[0] / size[0], lookup_size[1] / size[1])
        surfaces = graph.add(EnvironmentSurfacesPass(lookup_size, inputs.camera, inputs.objects,
                                                     _masked_materials(world, inputs)))
        found = graph.add(EnvironmentVisibilityPass(lookup_size, inputs.camera, surfaces, inputs.environment_views,
                                                    visibility, environment.visibility, interleave,
                                                    visibility_min_alpha(environment.visibility), halves)).image
        across = graph.add(EnvironmentVisibilityBlurPass(found, lookup_size, interleave, 0, False, True, halves)).image
        lookups = graph.add(EnvironmentVisibilityBlurPass(across, lookup_size, interleave, 1, True, False, halves)).image
    return EnvironmentLighting(inputs.environment, inputs.environment_map, specular, inputs.environment_views,
                               visibility, lookups, scale)


def _transmission_source(graph, world, color, size: tuple, samples: int, sky: SkyUnder):
    """The mip-mapped copy of the opaque scene (and the sky) that transmissive pbr
    materials see through (passes/transmission.py), or None where no material transmits."""
    if not any(m.transmissive and m.model(world.settings.shading) == "pbr" for m in world.materials()):
        return None
    from scenerender.rendering.passes.transmission import TransmissionSourcePass  # deferred: see the imports

    return graph.add(TransmissionSourcePass(color, size, samples, sky)).image


def _indirect_lighting(graph, world, inputs: InputHandles, atlas, atlas_pages: tuple, environment,
                       back_pages: tuple, partial_updates: bool):
    """render.indirect's probe grid over the scene's bounds at t = 0, with the pass that
    bakes it (and, with ``partial_updates``, its record of what each probe holds, so that
    a frame where the scene moved draws only the probes the change touches); None where
    nothing is drawn lit or nothing is there to bounce off."""
    if all(m.model(world.settings.shading) == "unlit" for m in world.materials()):
        return None
    bounds = scene_bounds(world.objects, [obj.matrices(0.0) for obj in world.objects],
                          [bool(obj.visible(0.0)) for obj in world.objects])
    if bounds is None:
        return None
    from scenerender.rendering.passes.indirect import IndirectLighting, IndirectLightPass  # deferred: see the imports

    settings = world.settings.indirect
    grid = probe_grid(bounds, settings.probe_spacing)
    updates = ProbeUpdates(grid, settings.probe_budget, settings.bounces) if partial_updates else None
    baked = graph.add(IndirectLightPass(grid, settings, inputs, atlas, atlas_pages, environment, updates, back_pages))
    return IndirectLighting(grid, baked.irradiance, baked.depth)


def visibility_lookup_size(size: tuple, half: bool) -> tuple:
    """The environment visibility pass's image: the camera's, or half of it a side
    (rounded up) where ``half``."""
    return tuple(max(1, -(-side // 2)) for side in size) if half else tuple(size)


def prepass_pays(world, atlas, size, samples: int) -> bool:
    """Whether a depth prepass saves more shading than it costs in extra geometry work.

    The prepass draws every opaque triangle a second time so the lighting shader runs only
    for the surface each pixel finally shows. Opaque draws are already sorted near to far,
    so that saves little unless many surfaces overlap: judged on the first frame's depth
    complexity. With MSAA it did not pay in any scene measured on Mesa's llvmpipe, the
    overdraw scene included: the shading draw took as long with the prepass as without,
    so llvmpipe appears to shade hidden multisampled fragments anyway.
    """
    if samples > 1 or world.settings.shading == "unlit":
        return False
    if any(m.masked for m in world.materials()):  # cut-away pixels must not hold the prepass's depth
        return False
    return depth_complexity(world, atlas, size) >= PREPASS_DEPTH_COMPLEXITY


def visible_samples_pay(world, samples: int, post_depth_coverage: bool) -> bool:
    """Whether shadow lookups average over only the samples where the surface is seen.

    With MSAA a pixel's shadow is averaged over points spread across the pixel
    (shaders/lighting/shadows.glsl). Where a silhouette crosses the pixel, the points of
    the hidden samples land on the surface behind the nearer object, and where that object
    stands on the surface they are in its shadow: the floor beside a box's base came out
    up to 0.23 too dark (a 24 degree spot over a sphere and a box, 256x192). After a depth
    prepass, the depth test tells the shader which samples it shades
    (GL_ARB_post_depth_coverage), and only their points count. It takes the prepass on
    llvmpipe, which otherwise does not pay with MSAA (prepass_pays).

    From 4 samples up: asked for 2, llvmpipe makes 4 (its coverage masks have four bits,
    at the 4-sample positions), so the mask would name points the 2-sample pattern does
    not have (measured: geometry-edge error 5.13 -> 5.58 % with it at 2 samples).
    """
    return (samples >= 4 and post_depth_coverage and world.settings.shading != "unlit"
            and any(light.shadow is not None for light in world.lights))


def hdr_target_pays(options: GraphOptions, output_transform: str, tone: bool = False) -> bool:
    """Whether shading goes to a 16-bit float target rather than 8-bit sRGB-encoded.

    EXR output needs the linear values above 1, and so does an exposure or a tone curve
    (``tone``): they bring values above 1 down into the image, and an exposure above 0
    must not scale up values the 8-bit target already rounded. A gamma or linear output
    transform needs the linear values too: re-encoding 8-bit sRGB would round twice and
    lose a level (linear 0.5 would become 127, not 128). sRGB output is clamped to [0, 1]
    and stored in 8 bits anyway, and the hardware's sRGB encoding stays within 0.6 levels
    of the exact curve, as the float path does (measured over 200 grey levels on
    llvmpipe); the one difference is that samples above 1 are clamped before the MSAA
    resolve rather than after (a few edge pixels of highlights; golden scenes: worst 8x8
    block 0.7 levels).
    With 4x MSAA the float target costs about 14 ms more per 640x480 layer on llvmpipe
    (writes and resolve), without MSAA about 3 ms.
    """
    return options.want_linear or output_transform != "srgb" or tone


def shader_encoding_pays(samples: int) -> bool:
    """Whether the opaque pass's shaders write the sRGB encoding into the 8-bit target,
    with the device's own turned off while they draw (passes/forward.py).

    Mesa llvmpipe encodes each sample of a multisampled target as it stores it, with an
    approximation one level off the exact curve for about 7 % of values; the shader
    encodes once a pixel, exactly (common/srgb.glsl). Measured on llvmpipe
    (benchmarks/msaa_cost.py): a 640x480 layer of cheap shading at 4x MSAA costs 5.5 ms
    into the sRGB target with the device encoding, 3.0 ms without; the benchmark scene's
    frame 0.98x, the showcase's 0.96x. Without MSAA the device's encoding costs what the
    shader's does, and stays. Sample values change by at most a level; a blend after the
    opaque pass (transparent surfaces, outlines) still decodes and encodes on the device.
    """
    return samples > 1


def depth_complexity(world, atlas, size) -> float:
    """How many times over the opaque objects' screen boxes cover the image at frame 0:
    the sum over instances in view of their projected bounding-box area, over the image
    area (an overestimate for round shapes; an instance reaching behind the camera counts
    as the whole image)."""
    frame = FrameEvaluator(world, size, atlas).evaluate(0, 0.0)
    clip = frame.camera.view_proj_relative()
    covered = 0.0
    for obj, state in zip(world.objects, frame.objects):
        if state.in_view == 0 or all(m.transparent for m in obj.materials):
            continue
        lo, hi = obj.mesh.bounds()
        corners = np.array([[x, y, z, 1.0] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        points = np.einsum("ij,kjl,ml->kmi", clip, state.models_rel[:state.in_view].astype(np.float64), corners)
        w = points[..., 3]
        behind = np.any(w <= 1e-9, axis=1)
        ndc = points[..., :2] / np.where(w > 1e-9, w, 1.0)[..., None]
        extent = np.clip(ndc.max(axis=1), -1, 1) - np.clip(ndc.min(axis=1), -1, 1)
        areas = np.where(behind, 1.0, extent[:, 0] * extent[:, 1] / 4.0)
        covered += float(areas.sum())
    return covered


def _add_object_ids(graph, size, inputs: InputHandles):
    from scenerender.rendering.passes.object_ids import ObjectIdPass  # deferred: see the imports

    return graph.add(ObjectIdPass(size, inputs.camera, inputs.objects))


def _add_shadow_passes(graph, world, atlas, inputs: InputHandles) -> tuple[list, tuple]:
    """One pass per shadowed light. Returns [(light index, its page's handle after it)]
    and the final handle of each atlas page, in page order.

    The passes of one page write it in turn; a page holds either maps drawn once or maps
    redrawn every frame (world.shadows), so its passes are all static or all dynamic. The
    shadow views show the first shadowed light alone; there file order puts it first and
    culls every other pass."""
    if not inputs.shadow_views:
        return [], ()
    from scenerender.rendering.passes.shadow import ShadowMapPass  # deferred: see the imports

    handles = []
    current: dict = {}
    for light_index, views in inputs.shadow_views:
        light = world.lights[light_index]
        page = atlas.page_of(light_index)
        map_size = atlas.tiles[light_index][0].size
        current[page] = graph.add(ShadowMapPass(light.name, light.kind, map_size, light.shadow.pcf, page,
                                                atlas.pages[page], views, inputs.objects, current.get(page),
                                                _masked_materials(world, inputs, casters_only=True))).atlas
        handles.append((light_index, current[page]))
    return handles, tuple(current[page] for page in sorted(current))


def _add_back_face_passes(graph, world, atlas, inputs: InputHandles) -> tuple:
    """The casters' back faces of each light whose soft shadow has solid casters
    (render.shadows.casters: solid), into its tiles of its page's back-face twin; returns
    (page, its final handle) pairs in page order (none where no light has them)."""
    from scenerender.rendering.passes.shadow import ShadowMapPass  # deferred: see the imports

    current: dict = {}
    for light_index, views in inputs.shadow_views:
        light = world.lights[light_index]
        if not light.solid_casters:
            continue
        page = atlas.page_of(light_index)
        current[page] = graph.add(ShadowMapPass(light.name, light.kind, atlas.tiles[light_index][0].size,
                                                light.shadow.pcf, page, atlas.pages[page], views, inputs.objects,
                                                current.get(page), _masked_materials(world, inputs, casters_only=True),
                                                back_faces=True)).atlas
    return tuple(sorted(current.items()))


def _masked_materials(world, inputs: InputHandles, casters_only: bool = False):
    """The ``materials`` input where the passes that draw no colour must cut alpha-masked
    materials (glTF MASK) too, else None: they then read no material, so an animated
    material colour leaves them cached."""
    objects = [obj for obj in world.objects if obj.cast_shadows or not casters_only]
    return inputs.materials if any(m.masked for obj in objects for m in obj.materials) else None


def _add_view(graph, world, mode, inputs: InputHandles, gbuffer, ao, shadow_passes, size, view_format: str):
    from scenerender.rendering.passes.views import (  # deferred: see the imports
        AmbientOcclusionViewPass, DepthViewPass, LightDepthViewPass, NormalsViewPass, ShadowFactorViewPass,
    )

    if mode == "depth":
        return graph.add(DepthViewPass(gbuffer, size, inputs.camera, view_format)).image
    if mode == "normals":
        return graph.add(NormalsViewPass(gbuffer, size, inputs.camera, view_format)).image
    if mode == "ambient_occlusion":
        return graph.add(AmbientOcclusionViewPass(ao, size, view_format)).image
    light_index, handle = shadow_passes[0]
    views = inputs.shadow_view(light_index)
    if mode == "shadow":
        return graph.add(ShadowFactorViewPass(handle, size, inputs.camera, inputs.objects, light_index,
                                              inputs.per_light[light_index], views, inputs.lights, view_format,
                                              _masked_materials(world, inputs))).color
    return graph.add(LightDepthViewPass(handle, size, views, view_format)).image
