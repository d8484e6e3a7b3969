"""render.indirect: light bounced between surfaces, baked into a grid of probes.

Each probe (world.probe_grid) sees the scene through a small cube map, rasterised once
with the forward shader itself (every light with its shadows, the environment light,
emission, the ambient light): the light each texel's surface gives, its diffuse
reflectance, its normal and its distance. Full-screen passes then reduce the cube maps to

- the irradiance at each probe, as nine spherical-harmonic coefficients convolved with
  the clamped cosine (shaders/indirect/project_irradiance.frag), written out over a small
  octahedral tile of directions (shaders/indirect/irradiance_tiles.frag), and
- the mean and mean squared distance to what it sees, as a small octahedral tile
  (shaders/indirect/project_depth.frag), for the Chebyshev visibility test the lookup
  (shaders/lighting/indirect.glsl) makes so that light does not come through walls.

Each further bounce relights the captured texels with the last bounce's probes
(shaders/indirect/relight.frag) and projects them again: no scene drawn again, so a bounce
costs a small fraction of the first. The bake reads the objects, materials, lights, their
shadow maps and the environment, never the camera: in a scene where those stay still it
is a static pass, baked once for the whole run. Where they move, the pass runs every frame
and draws again only the probes the change touches, within a budget
(world.probe_updates): each bounce keeps its own nine coefficients for every probe, so a
probe drawn again is relit from its neighbours' light as they hold it, and the bounces
after the first are worked out again over every probe once the scene is at rest.
Everything a probe sees is drawn relative to the grid's first probe, and its lights are
packed relative to it too (light_buffers.pack_lights_from).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from time import perf_counter

import moderngl
import numpy as np

from scenerender.graph import Handle, RenderPass, ResourceDesc
from scenerender.gpu.uniforms import matrix_bytes, set_uniforms
from scenerender.rendering.draw import (
    FULLSCREEN_VERTEX, MESH_VERTEX, begin_fullscreen_pass, bind_light_tables, bind_lights, bind_material,
    bind_texture_units, stop_culling,
)
from scenerender.rendering.features import TEXTURE_UNITS
from scenerender.rendering.graph_inputs import InputHandles, LightsInput
from scenerender.rendering.light_buffers import pack_lights_from
from scenerender.world.probe_grid import ProbeGrid
from scenerender.world.probe_updates import ProbeUpdates, UpdatePlan, scene_state
from scenerender.world.settings import IndirectSettings
from scenerender.world.shadows import AtlasLayout

FORWARD_FRAGMENT = "mesh/forward.frag"
IRRADIANCE_FRAGMENT = "indirect/project_irradiance.frag"
TILES_FRAGMENT = "indirect/irradiance_tiles.frag"
DEPTH_FRAGMENT = "indirect/project_depth.frag"
RELIGHT_FRAGMENT = "indirect/relight.frag"

# Cube face f looks along CUBE_FACES[f][0] with CUBE_FACES[f][1] up (shaders/indirect/probes.glsl).
CUBE_FACES = (((1, 0, 0), (0, 1, 0)), ((-1, 0, 0), (0, 1, 0)), ((0, 1, 0), (0, 0, 1)),
              ((0, -1, 0), (0, 0, -1)), ((0, 0, 1), (0, 1, 0)), ((0, 0, -1), (0, 1, 0)))
SH_COEFFICIENTS = 9
CAPTURE_COLUMNS = 8     # probes side by side in the capture images (each six faces wide)
DEPTH_TILE = 16         # texels a side of a probe's octahedral depth tile
DEPTH_TILES_X = 64      # depth tiles to a row


@dataclass(frozen=True)
class IndirectLighting:
    """What shading reads of render.indirect: the probes' ``irradiance`` and ``depth``
    (octahedral tiles of irradiance and of distance moments, one layout), and their grid."""

    grid: ProbeGrid
    irradiance: Handle
    depth: Handle

    def handles(self) -> tuple:
        return self.irradiance, self.depth

    def defines(self) -> dict:
        return probe_defines(self.grid)

    def bind(self, ctx, irradiance: Handle | None = None) -> None:
        """The probes' images on their units; ``irradiance``: another image of the same
        layout in place of the final one (the bake's last bounce)."""
        for handle, unit in ((irradiance or self.irradiance, "u_probe_irradiance"), (self.depth, "u_probe_depth")):
            image = ctx.image(handle)
            image.filter = (moderngl.LINEAR, moderngl.LINEAR)  # graph images are sampled texel by texel
            image.use(TEXTURE_UNITS[unit])

    def uniforms(self, origin) -> dict:
        return probe_uniforms(self.grid, origin)


def probe_defines(grid: ProbeGrid) -> dict:
    """The grid's layout (shaders/lighting/indirect.glsl)."""
    return {"HAS_INDIRECT": True, "PROBE_COUNTS": "ivec3({}, {}, {})".format(*grid.counts),
            "PROBE_DEPTH_SIZE": DEPTH_TILE, "PROBE_DEPTH_TILES_X": DEPTH_TILES_X}


def probe_uniforms(grid: ProbeGrid, origin) -> dict:
    """Where the grid is, relative to ``origin`` (the world point the shader's positions
    are relative to: the camera's position, or the bake's anchor)."""
    return {"u_probe_origin": grid.origin - np.asarray(origin, dtype=np.float64), "u_probe_spacing": grid.spacing}


def depth_atlas_size(grid: ProbeGrid) -> tuple:
    """(width, height) of the depth and the irradiance tiles' images: DEPTH_TILES_X tiles a row."""
    return DEPTH_TILES_X * DEPTH_TILE, math.ceil(grid.count / DEPTH_TILES_X) * DEPTH_TILE


def capture_size(grid: ProbeGrid, face: int) -> tuple:
    """(width, height) of the images every probe's six faces are captured into."""
    columns = min(CAPTURE_COLUMNS, grid.count)
    return columns * 6 * face, math.ceil(grid.count / columns) * face


def capture_reach(grid: ProbeGrid) -> float:
    """The largest distance a capture records: twice a cell's diagonal. The lookup only
    compares distances within a cell; a cap keeps the moments' variance meaningful where a
    probe sees nothing (Majercik et al. clamp theirs alike)."""
    return 2.0 * float(np.linalg.norm(grid.spacing))


def face_view_projections(eye: np.ndarray, near: float, far: float, depth) -> list[bytes]:
    """The six faces' origin-relative world -> clip matrices from ``eye`` (relative to the
    same origin), 90-degree perspective, in the device's depth convention (column-major
    float32 bytes)."""
    projection = np.zeros((4, 4))
    projection[0, 0] = projection[1, 1] = 1.0
    projection[2, 2] = (far + near) / (near - far)
    projection[2, 3] = 2.0 * far * near / (near - far)
    projection[3, 2] = -1.0
    projection = depth.camera_projection(projection)
    found = []
    for forward, up in CUBE_FACES:
        forward, up = np.array(forward, dtype=np.float64), np.array(up, dtype=np.float64)
        right = np.cross(forward, up)
        view = np.eye(4)
        view[0, :3], view[1, :3], view[2, :3] = right, up, -forward
        view[:3, 3] = -view[:3, :3] @ eye
        found.append(matrix_bytes(projection @ view))
    return found


@dataclass(frozen=True)
class IndirectData:
    """The probes' images (IndirectLighting's two and ``last_irradiance``, the bounce
    before, where there are several; ``harmonics``, every bounce's coefficients, texel
    (9 (bounce - 1) + i, probe): coefficient i) and the captures: the light each texel
    gives (``capture``, in later bounces ``relit``), its reflectance and its normal."""

    harmonics: Handle
    irradiance: Handle
    depth: Handle
    last_irradiance: Handle | None
    capture: Handle
    reflectance: Handle
    normal: Handle
    capture_depth: Handle
    relit: Handle | None


@dataclass(frozen=True)
class IndirectLightPass(RenderPass):
    """Bakes the probe grid (see the module's docstring). atlas: the run's shadow atlas
    layout, atlas_pages its pages' handles; environment: the environment light's lookups
    where it shades (rendering.pipeline), whose camera-only visibility image it leaves.
    updates: the run's record of what each probe holds, which lets a frame where the
    scene moved draw only the probes it touches; None: every run of the pass bakes every
    probe (what a full bake each frame costs, benchmarks/indirect_cost.py)."""

    grid: ProbeGrid
    settings: IndirectSettings
    inputs: InputHandles
    atlas: AtlasLayout | None = None
    atlas_pages: tuple = ()
    environment: object = None  # passes.environment.EnvironmentLighting
    updates: ProbeUpdates | None = None
    back_pages: tuple = ()  # ((page, handle), ...): solid casters' back faces

    name = "indirect_light"

    def setup(self, builder) -> IndirectData:
        views = tuple(handle for _, handle in self.inputs.shadow_views) if self.atlas_pages else ()
        builder.read(self.inputs.objects, self.inputs.materials, self.inputs.ambient, *self.inputs.per_light,
                     *views, *self.atlas_pages, *(handle for _, handle in self.back_pages),
                     *(self._environment().handles() if self.environment else ()))
        layout = ResourceDesc("color", depth_atlas_size(self.grid), "rgba16f")
        capture = capture_size(self.grid, self.settings.capture_size)
        several = self.settings.bounces > 1
        return IndirectData(
            builder.create("probe_harmonics", ResourceDesc("color", (SH_COEFFICIENTS * self.settings.bounces,
                                                                      self.grid.count), "rgba32f")),
            builder.create("probe_irradiance", layout),
            builder.create("probe_depth", ResourceDesc("color", depth_atlas_size(self.grid), "rgba32f")),
            builder.create("probe_irradiance_last", layout) if several else None,
            builder.create("probe_capture", ResourceDesc("color", capture, "rgba32f")),
            builder.create("probe_capture_reflectance", ResourceDesc("color", capture, "rgba16f")),
            builder.create("probe_capture_normal", ResourceDesc("color", capture, "rgba32f")),
            builder.create("probe_capture_depth", ResourceDesc("depth", capture, "camera_depth")),
            builder.create("probe_capture_relit", ResourceDesc("color", capture, "rgba32f")) if several else None)

    def describe(self) -> str:
        bounces = self.settings.bounces
        text = (f"{self.grid.describe()}, {bounces} bounce{'s' if bounces > 1 else ''}, "
                f"{self.settings.capture_size}px cube faces")
        if self.updates is not None:
            text += f"; at most {self.settings.probe_budget} probes drawn again a frame where the scene moves"
        return text

    def _environment(self):
        """The environment's lookups without the camera's visibility image: a capture looks
        every direction up itself, as a transparent surface does."""
        return replace(self.environment, lookups=None)

    def execute(self, ctx, data: IndirectData) -> None:
        started = perf_counter()
        plan, record = self._plan(ctx)
        if plan.probes.size:
            buffers = self._bind_lighting(ctx, self.grid.origin)  # everything is drawn relative to it
            try:
                self._capture(ctx, data, plan)
            finally:
                stop_culling(ctx.gl)
                for buffer in buffers:
                    buffer.release()
            self._project(ctx, data.capture, data.depth, DEPTH_FRAGMENT, self._rects(plan, DEPTH_TILES_X, DEPTH_TILE))
        if plan.settle:
            self._bounce(ctx, data, plan.settle, self._every_probe())
        elif plan.probes.size:
            for bounce in range(1, self.settings.bounces + 1):
                self._bounce(ctx, data, bounce, plan)
        if not plan.idle:
            self._tiles(ctx, data, self.settings.bounces, data.irradiance)
        if record is not None:
            self.updates.done(record)
        if plan.full:
            ctx.gl.finish()  # the bake's own time, for the progress line (once a bake)
            ctx.outputs.setdefault("notes", []).append(
                f"indirect light baked in {perf_counter() - started:.2f} s ({self.describe()})")

    def _every_probe(self) -> UpdatePlan:
        return UpdatePlan(np.arange(self.grid.count, dtype=np.int64), full=True)

    def _plan(self, ctx) -> tuple:
        """This frame's UpdatePlan and the record to keep once it is done (None without a
        record of updates: a full bake)."""
        if self.updates is None:
            return self._every_probe(), None
        objects = ctx.input(self.inputs.objects)
        state = scene_state(objects.frames, objects.definitions, [ctx.input(h) for h in self.inputs.per_light],
                            ctx.input(self.inputs.materials).values, ctx.input(self.inputs.ambient),
                            ctx.input(self.inputs.environment) if self.environment is not None else None)
        return self.updates.plan(state, ctx.frame)

    def _bounce(self, ctx, data: IndirectData, bounce: int, plan: UpdatePlan) -> None:
        """Bounce ``bounce``'s coefficients of ``plan``'s probes: from the captures (the
        first) or from them relit with every probe's last bounce as it is held."""
        seen = data.capture
        if bounce > 1:
            self._tiles(ctx, data, bounce - 1, data.last_irradiance)
            self._relight(ctx, data, data.last_irradiance, self._rects(plan, CAPTURE_COLUMNS, 0))
            seen = data.relit
        column = SH_COEFFICIENTS * (bounce - 1)
        rows = [(column, first, SH_COEFFICIENTS, count) for first, count in _runs(plan.probes, self.grid.count)]
        self._project(ctx, seen, data.harmonics, IRRADIANCE_FRAGMENT, rows, column)

    def _tiles(self, ctx, data: IndirectData, bounce: int, target: Handle) -> None:
        """Every probe's irradiance tile of bounce ``bounce`` into ``target``."""
        self._project(ctx, data.harmonics, target, TILES_FRAGMENT, None, SH_COEFFICIENTS * (bounce - 1))

    def _rects(self, plan: UpdatePlan, per_row: int, tile: int) -> list | None:
        """The rectangles of ``plan``'s probes in an image of ``per_row`` probes a row, each
        a ``tile``-texel square (0: six capture faces side by side); None for every probe."""
        if plan.full:
            return None
        width, height = (6 * self.settings.capture_size, self.settings.capture_size) if tile == 0 else (tile, tile)
        rects = []
        for first, count in _runs(plan.probes, per_row):
            row, column = divmod(first, per_row)
            rects.append((column * width, row * height, count * width, height))
        return rects

    def _bind_lighting(self, ctx, anchor: np.ndarray) -> tuple:
        """Bind the lights packed relative to ``anchor``, their shadow maps and the
        environment; returns the buffers made for the lights (released after the capture)."""
        lights = [ctx.input(handle) for handle in self.inputs.per_light]
        views = {index: ctx.input(handle).views for index, handle in self.inputs.shadow_views} if self.atlas_pages else {}
        packed = pack_lights_from(lights, views, anchor, self.atlas)
        buffers = (ctx.gl.buffer(packed.lights), ctx.gl.buffer(packed.views))
        bind_lights(LightsInput(*buffers, packed.first_view))
        bind_light_tables(ctx, self.atlas_pages, self.back_pages)
        if self.environment is not None:
            self._environment().bind(ctx)
        return buffers

    def _program(self, ctx, material):
        """The forward shader's variant for ``material`` drawn into a capture."""
        def make():
            defines = ctx.features.forward_defines(material, False)
            for key in [k for k in defines if k.startswith("FOG_") or k.startswith("ENV_VIS_INTER")
                        or k in ("HAS_FOG", "ENV_VIS_PER_PIXEL")]:
                defines.pop(key)
            defines["INDIRECT_CAPTURE"] = True
            program = ctx.programs.get(MESH_VERTEX, FORWARD_FRAGMENT, defines)
            bind_texture_units(program)
            return program

        return ctx.programs.memo(("indirect_capture", id(material)), make)

    def _capture(self, ctx, data: IndirectData, plan: UpdatePlan) -> None:
        """Draw ``plan``'s probes' six faces into the capture images."""
        gl = ctx.gl
        objects = ctx.input(self.inputs.objects)
        drawn = [i for i, frame in enumerate(objects.frames) if frame.visible and frame.count]
        for index in drawn:
            ctx.place_instances(objects, index, self.grid.origin)
        items = [(index, group, material) for index in drawn
                 for group, material in enumerate(objects.definitions[index].materials)
                 if objects.definitions[index].mesh.groups[group].count > 0 and not material.transparent]
        face = self.settings.capture_size
        reach = capture_reach(self.grid)
        fbo = ctx.framebuffer([data.capture, data.reflectance, data.normal], data.capture_depth)
        fbo.use()
        fbo.viewport = (0, 0, *ctx.image(data.capture).size)
        for rect in self._rects(plan, CAPTURE_COLUMNS, 0) or [None]:  # a miss: no light, no reflectance
            fbo.clear(0.0, 0.0, 0.0, reach, depth=ctx.depth.clear_value, viewport=rect)
        gl.enable(moderngl.DEPTH_TEST)
        gl.disable(moderngl.BLEND | moderngl.CULL_FACE)  # both sides of every surface, as the camera's two-sided shading
        gl.depth_func = ctx.depth.nearer
        probes = [int(p) for p in plan.probes]
        positions = self.grid.positions()[probes] - self.grid.origin
        near = 1e-3 * float(np.linalg.norm(self.grid.spacing))
        far = 2.0 * float(np.linalg.norm(self.grid.spacing * np.array(self.grid.counts))) + reach
        views = [face_view_projections(eye, near, far, ctx.depth) for eye in positions]
        materials = ctx.input(self.inputs.materials)
        frame_values = dict(u_ambient=ctx.input(self.inputs.ambient), u_capture_far=reach,
                            **(self._environment().uniforms(ctx, self.grid.origin) if self.environment else {}))
        for index, group, material in items:
            program = self._program(ctx, material)
            set_uniforms(program, **frame_values)
            bind_material(program, material, materials)
            view_proj = program["u_view_proj"]
            eye = program.get("u_capture_eye", None)
            for probe, position, faces in zip(probes, positions, views):
                column, row = probe % CAPTURE_COLUMNS, probe // CAPTURE_COLUMNS
                if eye is not None:
                    eye.value = tuple(float(v) for v in position)
                for side, matrix in enumerate(faces):
                    fbo.viewport = ((column * 6 + side) * face, row * face, face, face)
                    view_proj.write(matrix)
                    ctx.draw_placed(program, objects, index, group)

    def _relight(self, ctx, data: IndirectData, last: Handle, rects: list | None) -> None:
        """The captures' light after one bounce more, from the ``last`` bounce's probes,
        into ``relit``: within ``rects`` (x, y, width, height), or all of it (None)."""
        begin_fullscreen_pass(ctx, data.relit)
        program = ctx.programs.get(FULLSCREEN_VERTEX, RELIGHT_FRAGMENT,
                                   {**self._capture_defines(), **probe_defines(self.grid)})
        bind_texture_units(program)
        IndirectLighting(self.grid, data.irradiance, data.depth).bind(ctx, last)
        ctx.image(data.capture).use(TEXTURE_UNITS["u_capture"])
        ctx.image(data.reflectance).use(TEXTURE_UNITS["u_capture_reflectance"])
        ctx.image(data.normal).use(TEXTURE_UNITS["u_capture_normal"])
        set_uniforms(program, **probe_uniforms(self.grid, self.grid.origin))
        _draw_within(ctx, program, rects)

    def _capture_defines(self) -> dict:
        return {"CAPTURE_SIZE": self.settings.capture_size, "CAPTURE_COLUMNS": CAPTURE_COLUMNS,
                "PROBE_DEPTH_SIZE": DEPTH_TILE, "PROBE_DEPTH_TILES_X": DEPTH_TILES_X}

    def _project(self, ctx, capture: Handle, target: Handle, fragment: str, rects: list | None,
                 column: int = 0) -> None:
        """Reduce the captures (``capture``) to the probes' rows of coefficients or tiles of
        depth, or the coefficients to the irradiance tiles, in ``target``: within ``rects``
        (x, y, width, height; None: all of it); ``column``: the first of a bounce's
        coefficients."""
        begin_fullscreen_pass(ctx, target)
        program = ctx.programs.get(FULLSCREEN_VERTEX, fragment, self._capture_defines())
        bind_texture_units(program)
        ctx.image(capture).use(TEXTURE_UNITS["u_capture"])
        set_uniforms(program, u_probes=self.grid.count, u_column=column)
        _draw_within(ctx, program, rects)


def _runs(probes: np.ndarray, per_row: int) -> list:
    """(first, count) of each run of consecutive ``probes`` (ascending indices) that lie in
    one row of ``per_row``."""
    runs = []
    for probe in (int(p) for p in probes):
        if runs and runs[-1][0] + runs[-1][1] == probe and probe % per_row != 0:
            runs[-1][1] += 1
        else:
            runs.append([probe, 1])
    return [tuple(run) for run in runs]


def _draw_within(ctx, program, rects: list | None) -> None:
    """A full-screen draw of ``program`` under the scissor of each of ``rects``, or one
    over the whole target (None). A scissor drops fragments only: those drawn come out the
    bytes one full draw gives them."""
    if rects is None:
        ctx.fullscreen(program)
        return
    try:
        for rect in rects:
            ctx.gl.scissor = rect
            ctx.fullscreen(program)
    finally:
        ctx.gl.scissor = None
