"""What a pass's ``execute`` receives: the GL state of the run, and the resources its
``setup`` declared, nothing else."""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import moderngl
import numpy as np

from scenerender.gpu.depth import DepthConvention
from scenerender.gpu.resources import FramebufferCache
from scenerender.gpu.shaders import ProgramCache
from scenerender.graph import Handle, UndeclaredResource
from scenerender.rendering.features import SceneFeatures
from scenerender.rendering.graph_inputs import ObjectsInput
from scenerender.rendering.scene_gpu import GpuScene


@dataclass(frozen=True)
class RunState:
    """What stays the same for every pass of a run: the context and the caches on it."""

    gl: moderngl.Context
    programs: ProgramCache
    features: SceneFeatures
    depth: DepthConvention
    framebuffers: FramebufferCache
    gpu: GpuScene
    # long work's progress (rendering.steps): (what, share done in [0, 1]); None: untold
    report_work: Callable[[str, float], None] | None = None


@dataclass(frozen=True)
class PassContext:
    """One pass's view of one frame.

    images:  resource index -> moderngl texture or renderbuffer, for every image of the run.
    inputs:  resource index -> this frame's value of every world input.
    outputs: what side-effect passes leave for the renderer (e.g. "pixels").
    written: indices of the images passes drew into earlier this frame.
    frame:   the index of the frame being rendered (a pass that keeps what earlier frames
             made, render.indirect's probes, starts over where frames come out of order).
    Only the indices in ``declared`` resolve; anything else raises UndeclaredResource.
    """

    run: RunState
    pass_name: str
    declared: frozenset
    images: dict
    inputs: dict
    outputs: dict
    written: frozenset = frozenset()
    frame: int = 0

    @property
    def gl(self) -> moderngl.Context:
        return self.run.gl

    @property
    def programs(self) -> ProgramCache:
        return self.run.programs

    @property
    def features(self) -> SceneFeatures:
        return self.run.features

    @property
    def depth(self) -> DepthConvention:
        """The depth convention of the passes drawn from the camera."""
        return self.run.depth

    def image(self, handle: Handle):
        """The texture or renderbuffer of a declared image."""
        self._check(handle, self.images, "image")
        return self.images[handle.resource]

    def input(self, handle: Handle):
        """This frame's value of a declared world input (rendering.inputs)."""
        self._check(handle, self.inputs, "input")
        return self.inputs[handle.resource]

    def written_this_frame(self, handle: Handle) -> bool:
        """Whether a pass drew into the declared image ``handle`` earlier this frame (else
        it holds what the last frame that drew it left)."""
        self._check(handle, self.images, "image")
        return handle.resource in self.written

    def framebuffer(self, colors, depth: Handle | None = None) -> moderngl.Framebuffer:
        """A framebuffer over declared images (cached for the run)."""
        return self.run.framebuffers.get(tuple(self.image(h) for h in colors),
                                         self.image(depth) if depth is not None else None)

    def fullscreen(self, program) -> None:
        """Draw one viewport-covering triangle with ``program`` (no vertex buffers)."""
        self.run.gpu.fullscreen_array(program).render(vertices=3)

    def checkpoint(self) -> None:
        """Wait until the GPU has done what was sent: a signal that arrived meanwhile then
        stops the run here, its handler running as this call returns (rendering.steps)."""
        self.run.gl.finish()

    def report_work(self, what: str, fraction: float) -> None:
        """Tell the run's progress that ``fraction`` of the long work ``what`` is done."""
        if self.run.report_work is not None:
            self.run.report_work(what, fraction)

    def place_instances(self, objects: ObjectsInput, index: int, eye: np.ndarray) -> None:
        """Write object ``index``'s instance transforms (from the declared ``objects``
        input) relative to the world point ``eye`` (float64, rounded to float32 only after
        the subtraction) into its scratch instance buffer, for ``draw_placed``. What such
        draws make then depends on the objects and ``eye`` alone, not on where the camera
        is: a shadow map comes out the same bytes whichever frame draws it."""
        state = objects.frames[index]
        models = state.models.copy()
        models[:, :3, 3] -= eye
        self.run.gpu.write_eye_relative(index, models, state.normals)

    def draw_placed(self, program, objects: ObjectsInput, index: int, group: int | None = None) -> None:
        """Draw every instance of object ``index`` (one mesh ``group`` of it, or all) as
        ``place_instances`` last placed them."""
        count = objects.frames[index].count
        if count:
            mesh = objects.definitions[index].mesh
            first, vertices = 0, mesh.triangle_count * 3
            if group is not None:
                first, vertices = mesh.groups[group].first * 3, mesh.groups[group].count * 3
            vao = self.run.gpu.vertex_array(program, index, eye_relative=True)
            vao.render(moderngl.TRIANGLES, vertices=vertices, first=first, instances=count)

    def shared(self, key: str, make):
        """A GL object passes share for the whole run (noise textures, samplers), made once
        by ``make(gl)``."""
        return self.run.gpu.cached(key, make)

    def _check(self, handle: Handle, kind_table: dict, kind: str) -> None:
        if not isinstance(handle, Handle):
            raise TypeError(f"pass {self.pass_name!r} asked for {handle!r}, which is not a graph handle")
        if handle.resource not in self.declared:
            raise UndeclaredResource(f"pass {self.pass_name!r} uses {handle.name!r}, which its setup does not "
                                     "declare: add builder.read() for it")
        if handle.resource not in kind_table:
            raise UndeclaredResource(f"pass {self.pass_name!r} asks for {handle.name!r} as an {kind}, which it is not")
