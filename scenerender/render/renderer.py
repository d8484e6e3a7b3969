"""The renderer: one GL context, one compiled graph and one GpuScene for a whole run."""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from scenerender.gpu.resources import FramebufferCache, allocate
from scenerender.gpu.shaders import ProgramCache
from scenerender.render.context import PassContext
from scenerender.render.features import SceneFeatures
from scenerender.render.motion import analyse
from scenerender.render.pipeline import GraphOptions, build_graph
from scenerender.world.frame import FrameEvaluator
from scenerender.world.shadows import plan_atlas


@dataclass
class FrameResult:
    """pixels: (H, W, 3) uint8 top row first; linear: (H, W, 3) float32 or None."""

    index: int
    time: float
    pixels: np.ndarray
    linear: np.ndarray | None = None


class GLBackend:
    """Executes passes on the GL context with the graph's resources."""

    def __init__(self, gl, scene, programs, features, resources, timings: dict | None = None):
        self.gl = gl
        self.timings = timings  # pass name -> list of seconds, when profiling
        self.scene = scene
        self.programs = programs
        self.features = features
        self.resources = resources
        self.framebuffers = FramebufferCache(gl)
        self.outputs: dict = {}

    def execute(self, render_pass, frame) -> None:
        ctx = PassContext(self.gl, frame, self.scene, self.programs, self.features, self.resources,
                          self.framebuffers, self.outputs)
        if self.timings is None:
            render_pass.execute(ctx)
            return
        # profiling: wait for the GPU around each pass so its time is its own
        self.gl.finish()
        started = time.perf_counter()
        render_pass.execute(ctx)
        self.gl.finish()
        self.timings.setdefault(render_pass.name, []).append(time.perf_counter() - started)


def plan(world, size, samples: int, max_texture_size: int = 16384, want_linear: bool = False, warn=None):
    """Everything decided before GL work: atlas layout, motion, the compiled graph.

    Returns (atlas, motion, compiled graph). Needs no GL context, so ``scenerender graph``
    and the tests can inspect a scene's graph anywhere.
    """
    atlas = plan_atlas(world.lights, max_texture_size, warn)
    motion = analyse(world)
    graph = build_graph(world, atlas, motion, GraphOptions(tuple(size), samples, want_linear))
    return atlas, motion, graph.compile()


class Renderer:
    """Renders frames of one World at one size. Create once, call ``render`` per frame."""

    def __init__(self, world, gl, size=None, samples=None, warn=None, want_linear: bool = False,
                 profile: bool = False, cache_static_passes: bool = True):
        render = world.render
        self.world = world
        self.gl = gl
        self.size = tuple(size or render.size)
        wanted = samples if samples is not None else render.samples
        self.samples = min(wanted, gl.max_samples) if wanted > 1 else 1
        if self.samples < wanted and warn is not None:
            warn(f"render.samples {wanted} is more than this device offers; using {self.samples}")
        max_size = int(gl.info.get("GL_MAX_TEXTURE_SIZE", 16384))
        self.atlas, self.motion, self.compiled = plan(world, self.size, self.samples, max_size, want_linear, warn)
        self.features = SceneFeatures.of(world)
        self.programs = ProgramCache(gl)
        from scenerender.render.scene_gpu import GpuScene

        self.scene = GpuScene(gl, world, self.atlas)
        resources = {index: allocate(gl, desc) for index, _, desc in self.compiled.resources()}
        self.timings: dict | None = {} if profile else None
        self.backend = GLBackend(gl, self.scene, self.programs, self.features, resources, self.timings)
        self.evaluator = FrameEvaluator(world, self.size, self.atlas)
        self.cache_static_passes = cache_static_passes  # off only to measure what caching saves
        self._rendered_any = False

    def release(self) -> None:
        """Free every GL object this renderer made (the context itself stays)."""
        for resource in self.backend.resources.values():
            resource.release()
        self.backend.framebuffers.release()
        self.programs.release()
        self.scene.release()

    def frame_time(self, index: int) -> float:
        """Time of frame ``index`` in seconds: index / fps, in float64."""
        return index / float(self.world.output.fps)

    def render(self, index: int) -> FrameResult:
        time = self.frame_time(index)
        frame = self.evaluator.evaluate(index, time)
        self.scene.upload(frame)
        first = not self._rendered_any or not self.cache_static_passes
        self.compiled.run_frame(self.backend, frame, first=first)
        self._rendered_any = True
        outputs = self.backend.outputs
        return FrameResult(index, time, outputs.pop("pixels"), outputs.pop("linear", None))
