"""Build the render graph for a World: which passes this scene needs, in order.

The builder adds a pass only for features the scene has (a skybox pass only with a
skybox, shadow passes only for shadowed lights...). The render mode then picks which image
the readback takes, and compiling the graph culls every pass that image does not need:
``mode: depth`` keeps the geometry prepass and drops shading, shadows and the sky.
"""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.graph import FrameGraph
from scenerender.render.motion import Motion
from scenerender.render.passes.ambient_occlusion import GBufferPass, SSAOBlurPass, SSAOPass
from scenerender.render.passes.forward import (
    OpaquePass, OutlinePass, SkyboxPass, TransparentPass, WireframeOverlayPass,
)
from scenerender.render.passes.output import OutputTransformPass, ReadbackPass, ResolvePass
from scenerender.render.passes.shadow import ShadowMapPass
from scenerender.render.passes.views import (
    AmbientOcclusionViewPass, DepthViewPass, LightDepthViewPass, NormalsViewPass, ShadowFactorViewPass,
)
from scenerender.scene.schema import AmbientOcclusion

DATA_MODES = ("depth", "normals", "ambient_occlusion", "shadow", "light_depth")


@dataclass(frozen=True)
class GraphOptions:
    size: tuple
    samples: int
    want_linear: bool = False  # also read back linear HDR (EXR output)


def build_graph(world, atlas, motion: Motion, options: GraphOptions) -> FrameGraph:
    """The full graph for ``world``; call ``.compile()`` to cull and order it."""
    graph = FrameGraph()
    render = world.render
    size, samples = options.size, options.samples
    camera_dynamic = not motion.everything_static

    shadow_handles = _add_shadow_passes(graph, world, atlas, motion)
    atlas_final = shadow_handles[-1][1] if shadow_handles else None

    gbuffer = ao = None
    if render.ambient_occlusion is not None or render.mode in ("depth", "normals", "ambient_occlusion"):
        gbuffer = graph.add(GBufferPass(size, camera_dynamic))
    if render.ambient_occlusion is not None or render.mode == "ambient_occlusion":
        settings = render.ambient_occlusion or AmbientOcclusion()
        raw = graph.add(SSAOPass(gbuffer, size, settings, camera_dynamic))
        ao = graph.add(SSAOBlurPass(raw, size, camera_dynamic))
    forward_ao = ao if render.ambient_occlusion is not None else None

    fill = render.mode if render.mode in ("wireframe", "points") else "solid"
    color, depth = graph.add(OpaquePass(size, samples, atlas_final, forward_ao, fill, camera_dynamic))
    if render.skybox is not None:
        color = graph.add(SkyboxPass(color, depth, dynamic=camera_dynamic))
    if any(obj.outline is not None for obj in world.objects):
        color = graph.add(OutlinePass(color, depth, dynamic=camera_dynamic))
    if any(m.transparent for m in world.materials()):
        color = graph.add(TransparentPass(color, depth, atlas_final, forward_ao, camera_dynamic))
    if render.wireframe_overlay:
        color = graph.add(WireframeOverlayPass(color, depth, dynamic=camera_dynamic))
    if samples > 1:
        color = graph.add(ResolvePass(color, size, camera_dynamic))
    final = graph.add(OutputTransformPass(color, size, render.output_transform, render.gamma, camera_dynamic))

    if render.mode in DATA_MODES:
        final = _add_view(graph, render.mode, world, gbuffer, ao, shadow_handles, atlas, size, camera_dynamic)
    linear = color if options.want_linear and render.mode not in DATA_MODES else None
    graph.add(ReadbackPass(final, size, linear))
    return graph


def _add_shadow_passes(graph, world, atlas, motion: Motion) -> list:
    """One pass per shadowed light; returns [(light state index, atlas handle after it)]."""
    handles = []
    current = None
    state_index = -1
    for def_index, light in enumerate(world.lights):
        if light.kind == "ambient":
            continue
        state_index += 1
        if light.shadow is None:
            continue
        current = graph.add(ShadowMapPass(state_index, light, atlas, current, dynamic=not motion.shadow_static(light)))
        handles.append((state_index, current))
    return handles


def _add_view(graph, mode, world, gbuffer, ao, shadow_handles, atlas, size, dynamic):
    if mode == "depth":
        return graph.add(DepthViewPass(gbuffer, size, dynamic))
    if mode == "normals":
        return graph.add(NormalsViewPass(gbuffer, size, dynamic))
    if mode == "ambient_occlusion":
        return graph.add(AmbientOcclusionViewPass(ao, size, dynamic))
    light_index, handle = shadow_handles[0]
    if mode == "shadow":
        return graph.add(ShadowFactorViewPass(handle, size, light_index, dynamic))
    return graph.add(LightDepthViewPass(handle, size, light_index, atlas.size, dynamic))
