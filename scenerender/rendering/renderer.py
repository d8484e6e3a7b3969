"""The renderer: one GL context, one compiled graph and one GpuScene for a whole run."""
from __future__ import annotations

import os
from dataclasses import dataclass, replace
from time import perf_counter

import numpy as np

from scenerender.colorspace import encode_output, tone_map
from scenerender.errors import UserError
from scenerender.graph import CompiledGraph
from scenerender.gpu.depth import depth_convention
from scenerender.gpu.resources import GL_FRAMEBUFFER_SRGB, FramebufferCache, allocate
from scenerender.gpu.shaders import ProgramCache
from scenerender.rendering.pass_context import PassContext, RunState
from scenerender.rendering.features import SceneFeatures
from scenerender.rendering.graph_inputs import InputHandles, input_values, same_value
from scenerender.rendering.light_buffers import pack_lights
from scenerender.rendering.pipeline import GraphOptions, build_graph
from scenerender.rendering.profile import CPU_SETUP
from scenerender.rendering.scene_gpu import GpuScene
from scenerender.sinks.object_ids import MAX_OBJECT_IDS
from scenerender.world.camera_data import camera_record
from scenerender.world.frame import FrameEvaluator, FrameState
from scenerender.world.frame_inputs import redrawn_shadow_maps
from scenerender.world.lens import Film
from scenerender.world.shadows import plan_atlas


# Debug switch: "1" fails a render whose linear colour holds NaN or Inf anywhere.
ENV_CHECK_FINITE = "SCENERENDER_CHECK_FINITE"


class NonFiniteOutput(RuntimeError):
    """A frame's linear colour held NaN or Inf (checked with SCENERENDER_CHECK_FINITE=1).
    Not bad input: a shading bug, or a value too large for the 16-bit float target."""


def check_finite_enabled() -> bool:
    return os.environ.get(ENV_CHECK_FINITE, "0").strip() not in ("", "0")


def first_non_finite(linear: np.ndarray) -> str | None:
    """None when every value of ``linear`` (H, W, 3) float is finite, else a description:
    how many pixels are not, and the first of them (x, y from the top left)."""
    bad = ~np.isfinite(linear).all(axis=2)
    if not bad.any():
        return None
    y, x = (int(v) for v in np.argwhere(bad)[0])
    return f"{int(bad.sum())} pixel(s) with NaN or Inf in the linear colour, the first at x {x}, y {y}"


@dataclass
class FrameResult:
    """pixels: (H, W, 3) uint8 top row first; linear: (H, W, 3) float32 or None;
    object_ids: (H, W) uint16 top row first, each pixel's object index + 1 (0: none), or
    None (passes/object_ids.py); object_ids_behind: the same of the nearest opaque surface
    (what a transparent surface in front lets through), or None."""

    index: int
    time: float
    pixels: np.ndarray
    linear: np.ndarray | None = None
    object_ids: np.ndarray | None = None
    object_ids_behind: np.ndarray | None = None
    camera: dict | None = None  # the frame's camera as cameras.json records it (world/camera_data.py)


class GLBackend:
    """Executes passes on the GL context: each gets a PassContext that resolves only the
    resources its setup declared."""

    def __init__(self, run: RunState, images: dict, timings: dict | None = None):
        self.run = run
        self.images = images
        self.timings = timings  # pass name -> list of seconds, when profiling
        self.inputs: dict = {}  # this frame's input values (rendering.inputs.input_values)
        self.frame_index = 0     # this frame's index
        self.outputs: dict = {}
        self._last_inputs: dict = {}  # (pass index, input index) -> value it last ran with

    def same_input(self, node, handle) -> bool:
        """Whether input ``handle`` has the value it had when ``node`` last ran."""
        last = self._last_inputs.get((node.index, handle.resource))
        return last is not None and same_value(self.inputs[handle.resource], last)

    def execute(self, node, frame, written=frozenset()) -> None:
        ctx = PassContext(self.run, node.render_pass.name, node.declared, self.images, self.inputs, self.outputs,
                          frozenset(written))
        if self.timings is None:
            node.render_pass.execute(ctx, node.data)
        else:
            # profiling: wait for the GPU around each pass so its time is its own
            gl = self.run.gl
            gl.finish()
            started = perf_counter()
            node.render_pass.execute(ctx, node.data)
            gl.finish()
            self.timings.setdefault(node.render_pass.name, []).append(perf_counter() - started)
        # recorded once the pass has run to its end: one a signal stopped runs again
        if node.render_pass.keeps_unchanged:
            for handle in node.reads:
                if handle.resource in self.inputs:
                    self._last_inputs[(node.index, handle.resource)] = self.inputs[handle.resource]


@dataclass(frozen=True)
class Plan:
    """Everything decided before GL work.

    atlas:   the shadow atlas layout (world.shadows.AtlasLayout) or None.
    inputs:  the graph handles of the world's inputs (rendering.inputs.InputHandles).
    compiled: the culled graph, static passes marked.
    """

    atlas: object
    inputs: InputHandles
    compiled: CompiledGraph


def plan(world, size, samples: int, max_texture_size: int = 16384, want_linear: bool = False, warn=None,
         tuning: dict | None = None, object_ids: bool = False) -> Plan:
    """The atlas layout and the compiled graph for ``world`` at ``size`` with ``samples``
    (what the device gives). Needs no GL context, so ``scenerender graph`` and the tests
    can inspect a scene's graph anywhere. ``tuning``: GraphOptions fields that override
    the builder's per-scene choices (benchmarks compare them). ``object_ids``: add the
    object-id pass (passes/object_ids.py); without it the graph has no trace of one.
    """
    if object_ids and len(world.objects) > MAX_OBJECT_IDS:
        raise UserError(f"object ids are 16-bit: at most {MAX_OBJECT_IDS} objects, and this scene has "
                        f"{len(world.objects)}; render without --object-ids")
    atlas = plan_atlas(world.lights, max_texture_size, warn, redrawn_shadow_maps(world), world.fixed_shadow_sizes)
    options = GraphOptions(tuple(size), samples, want_linear, object_ids, **(tuning or {}))
    graph, inputs = build_graph(world, atlas, options)
    return Plan(atlas, inputs, graph.compile())


def device_samples(wanted: int, max_samples: int) -> int:
    """The MSAA samples a run gets: the largest power of two (the only counts GL
    multisampled images come in) not above the request or what the device offers; 1 for
    no multisampling. Scenes ask only for powers of two; callers of ``GraphRenderer`` may not."""
    allowed = min(wanted, max_samples)
    return 1 << (allowed.bit_length() - 1) if allowed > 1 else 1


def lowered_samples_warning(wanted: int, used: int, max_samples: int) -> str:
    if wanted > max_samples:
        return f"render.samples {wanted} is more than this device offers; using {used}"
    return f"MSAA samples {wanted} is not a power of two, the only counts GL offers; using {used}"


class GraphRenderer:
    """Renders frames of one World at one size. Create once, call ``render`` per frame.
    ``report_work(what, fraction)``: told the progress of long GPU work (rendering.steps)."""

    def __init__(self, world, gl, size=None, samples=None, warn=None, want_linear: bool = False,
                 profile: bool = False, cache_static_passes: bool = True, tuning: dict | None = None,
                 object_ids: bool = False, report_work=None):
        render = world.settings
        self.world = world
        self.gl = gl
        self.size = tuple(size or render.size)
        wanted = samples if samples is not None else render.samples
        self.samples = device_samples(wanted, gl.max_samples)
        if self.samples < wanted and warn is not None:
            warn(lowered_samples_warning(wanted, self.samples, gl.max_samples))
        max_size = int(gl.info.get("GL_MAX_TEXTURE_SIZE", 16384))
        # the finite check reads the linear (float) colour back, whether the caller wants it or not
        self.check_finite = check_finite_enabled()
        self.want_linear = want_linear
        self.object_ids = object_ids
        tuning = {"post_depth_coverage": "GL_ARB_post_depth_coverage" in gl.extensions,
                  # uncached, every pass does all its work every frame: the probes' bake too
                  **({} if cache_static_passes else {"indirect_updates": False}), **(tuning or {})}
        # a shutter or a lens: each frame the mean of sub-frames' linear images (world.lens)
        self.film = Film.of_world(world)
        self.plan = plan(world, self.size, self.samples, max_size,
                         want_linear or self.check_finite or self.film is not None, warn, tuning, object_ids)
        self.features = SceneFeatures.of(world, self.samples, self.plan.atlas)
        # encode linear -> sRGB on writes to (only) sRGB-format targets, decode for blending
        gl.enable_direct(GL_FRAMEBUFFER_SRGB)
        self.programs = ProgramCache(gl)
        self.scene = GpuScene(gl, world)
        self.depth = depth_convention(gl)
        images = {index: allocate(gl, desc, self.depth) for index, _, desc in self.compiled.resources()}
        self.timings: dict | None = {} if profile else None
        run = RunState(gl, self.programs, self.features, self.depth, FramebufferCache(gl), self.scene, report_work)
        self.backend = GLBackend(run, images, self.timings)
        self.evaluator = FrameEvaluator(world, self.size, self.atlas, max_depth_ratio=self.depth.max_depth_ratio)
        self.cache_static_passes = cache_static_passes  # off only to measure what caching saves
        self._rendered_any = False
        self.notes: list = []  # lines the passes left for the progress output (a bake's time), not yet taken

    @property
    def atlas(self):
        return self.plan.atlas

    @property
    def compiled(self) -> CompiledGraph:
        return self.plan.compiled

    def release(self) -> None:
        """Free every GL object this renderer made (the context itself stays)."""
        for image in self.backend.images.values():
            image.release()
        self.backend.run.framebuffers.release()
        self.programs.release()
        self.scene.release()

    def frame_time(self, index: int) -> float:
        """Time of frame ``index`` in seconds: index / fps, in float64."""
        return index / float(self.world.output.fps)

    def import_frame(self, frame: FrameState) -> dict:
        """Hand ``frame`` to the graph: upload what the passes draw from (the objects'
        camera-relative instance transforms, the packed lights and shadow views) and return
        every input's value (rendering.inputs.input_values). The one place per-frame data
        reaches the GPU before the passes run; passes then see it only through the inputs
        they declared."""
        camera = replace(frame.camera, projection=self.depth.camera_projection(frame.camera.projection))
        lights = self.scene.upload(frame, pack_lights(frame, self.atlas))
        return input_values(self.plan.inputs, frame, camera, self.scene, self.world, lights)

    def render(self, index: int) -> FrameResult:
        time = self.frame_time(index)
        if self.film is None:
            pixels, linear, ids, behind, camera = self._run_graph(index, time)
        else:
            pixels, linear, ids, behind = self._film(index, time)
            camera = self.evaluator.evaluate(index, time).camera  # the lens's centre at the frame's time
        if self.check_finite and linear is not None:
            problem = first_non_finite(linear)
            if problem is not None:
                raise NonFiniteOutput(f"frame {index}: {problem} ({ENV_CHECK_FINITE} is on)")
        return FrameResult(index, time, pixels, linear if self.want_linear else None, ids, behind,
                           camera_record(camera, self.size, index, time))

    def _run_graph(self, index: int, time: float, lens_point: tuple | None = None) -> tuple:
        """Run the graph for the scene at ``time`` (seen from ``lens_point`` of the lens,
        world.lens): (pixels, linear or None, object ids or None, the object ids behind
        transparent surfaces or None, the camera it was seen from)."""
        started = perf_counter()
        frame = self.evaluator.evaluate(index, time, lens_point)
        self.backend.inputs = self.import_frame(frame)
        self.backend.frame_index = index
        if self.timings is not None:
            self.timings.setdefault(CPU_SETUP, []).append(perf_counter() - started)
        first = not self._rendered_any or not self.cache_static_passes
        self.depth.begin_frame()
        try:
            self.compiled.run_frame(self.backend, frame, first=first)
        finally:
            self.depth.end_frame()
        self._rendered_any = True
        outputs = self.backend.outputs
        self.notes.extend(outputs.pop("notes", ()))
        return (outputs.pop("pixels"), outputs.pop("linear", None), outputs.pop("object_ids", None),
                outputs.pop("object_ids_behind", None), frame.camera)

    def _film(self, index: int, time: float) -> tuple:
        """The frame through the shutter and the lens: the mean in linear light of the
        sub-frames (static passes stay cached across them), then the exposure, the tone
        curve and the output transform once, in NumPy (colorspace), as the output pass
        would. Object ids are the sub-frame's nearest the frame's time."""
        samples = self.film.samples_over(1.0 / float(self.world.output.fps))
        total, ids, nearest = None, (None, None), None
        for sample in samples:
            _, linear, *sample_ids, _ = self._run_graph(index, time + sample.time_offset, sample.lens)
            total = linear.astype(np.float64) if total is None else total + linear
            if nearest is None or abs(sample.time_offset) < nearest:
                ids, nearest = sample_ids, abs(sample.time_offset)
        linear = total / len(samples)
        settings = self.world.settings
        display = tone_map(linear, settings.tone_map, float(self.world.render.exposure(time)))
        pixels = encode_output(display, settings.output_transform, settings.gamma)
        return (pixels, linear.astype(np.float32), *ids)

    def camera_record(self, index: int) -> dict:
        """Frame ``index``'s camera as cameras.json records it, without rendering it."""
        time = self.frame_time(index)
        return camera_record(self.evaluator.evaluate(index, time).camera, self.size, index, time)
