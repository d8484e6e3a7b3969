"""Long GPU work in steps (rendering.steps): a render of the environment's prefilter at the
scene format's largest size, or of sub-frames, stops on SIGTERM within a second or so and
leaves nothing; the steps draw the same bytes as one draw (the prefilter, the visibility
maps and lookups); a pass stopped between steps is drawn again whole by the next render;
the work tells its progress; ``--limit prefilter_lookups`` refuses it before any work."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import scenerender
from conftest import skip_without_gl
from scenerender.cli import main
from scenerender.errors import display_path
from scenerender.rendering import steps as steps_module
from scenerender.rendering.pass_context import PassContext
from scenerender.rendering.passes import environment, shadow
from scenerender.rendering.renderer import GraphRenderer
from scenerender.rendering.steps import BLOCK_ROWS, TILE_COLUMNS, Step, steps_over
from scenerender.run import progress as progress_module
from scenerender.run.interrupts import Interrupted
from scenerender.run.progress import Progress
from scenerender.scene.model.lights import prefilter_lookups
from scenerender.world.environment_files import write_hdr

ROOT = Path(__file__).resolve().parent.parent
SCENE = """render: {{size: [64, 48], shading: pbr}}
lights:
  - {{type: environment, image: sky.hdr, prefilter_size: {size}, samples: {samples}, visibility: false}}
objects:
  - mesh: {{primitive: sphere}}
    material: {{metallic: 1, roughness: 0.4}}
"""


def write_scene(folder: Path, size: int, samples: int) -> Path:
    """A sphere under an environment light with the prefilter's ``size`` and ``samples``, its
    sky (a gradient with a bright patch, 64x32) made here."""
    rows = np.linspace(0.0, 1.0, 32)[:, None, None]
    sky = np.broadcast_to(0.2 + 0.8 * rows * np.array([0.4, 0.6, 1.0]), (32, 64, 3)).copy()
    sky[5:9, 38:42] = (40.0, 36.0, 30.0)
    write_hdr(folder / "sky.hdr", sky.astype(np.float32))
    (folder / "scene.yaml").write_text(SCENE.format(size=size, samples=samples), encoding="utf-8")
    return folder / "scene.yaml"


# ---------------------------------------------------------------------------------------
# the steps


@pytest.mark.parametrize("rect, per_pixel, budget", [
    ((0, 0, 2048, 1024), 1, 5_000_000),        # whole bands of rows
    ((0, 1024, 2048, 1024), 4096, 5_000_000),  # pieces of 4-row bands
    ((0, 64, 128, 64), 64, 4096),              # a piece per 64-column tile
    ((3, 5, 70, 9), 1000, 100),                # over budget at the smallest piece; sides not multiples
])
def test_steps_cover_each_pixel_once_within_the_budget(rect, per_pixel, budget):
    steps = steps_over(rect, per_pixel, budget)
    x, y, width, height = rect
    covered = np.zeros((y + height + 8, x + width + 8), dtype=np.int32)
    for step in steps:
        left, top, w, h = step.rect
        covered[top:top + h, left:left + w] += 1
        assert step.work == w * h * per_pixel
        assert step.work <= budget or (w <= TILE_COLUMNS and h <= BLOCK_ROWS)  # the smallest piece
    assert (covered[y:y + height, x:x + width] == 1).all() and covered.sum() == width * height


def test_the_prefilter_steps_count_the_lookups_the_limit_counts():
    for size, samples in [(8, 1), (128, 512), (2048, 4096), (100, 7)]:
        layout = (6, size, max(size // 2, 1))
        assert sum(step.work for step in environment.prefilter_steps(layout, samples)) == prefilter_lookups(size, samples)


def specular_image(gl, scene_path: Path, monkeypatch, one_draw: bool, budget: int | None = None) -> tuple[bytes, int, int]:
    """The prefiltered image's bytes (rgba16f), the count of steps drawn and of waits
    between them (the progress told at each): in one draw over the whole image
    (``one_draw``) or in steps of at most ``budget`` lookups."""
    drawn = []
    if one_draw:
        def prefilter_steps(layout, samples):
            return [Step((0, 0, layout[1], layout[2] * layout[0]), 1)]
    else:
        prefilter_steps = environment.prefilter_steps
    monkeypatch.setattr(environment, "prefilter_steps", lambda *args: drawn.extend(prefilter_steps(*args)) or drawn)
    if budget is not None:
        monkeypatch.setattr(steps_module, "STEP_LOOKUPS", budget)
    reports = []
    renderer = GraphRenderer(scenerender.load(scene_path).world, gl, report_work=lambda *report: reports.append(report))
    try:
        renderer.render(0)
        index = next(i for i, name, _ in renderer.compiled.resources() if name == "environment_specular")
        assert reports[0][1] == 0.0 and reports[-1][1] == 1.0
        return renderer.backend.images[index].read(), len(drawn), len(reports) - 2
    finally:
        renderer.release()
        monkeypatch.undo()


@pytest.mark.gl
def test_the_prefilter_in_steps_draws_the_bytes_of_one_draw(gl, tmp_path, monkeypatch):
    # A scissor drops fragments and changes none: the same bytes, not a bound (the
    # image is the 16-bit floats the shading reads). 4,096 lookups a step at 128 px and
    # 64 samples: the mirror level in bands of 32 rows, the rough ones in 64x4 pieces.
    scene_path = write_scene(tmp_path, 128, 64)
    whole, drawn, waits = specular_image(gl, scene_path, monkeypatch, one_draw=True)
    assert (drawn, waits) == (1, 0)
    stepped, drawn, waits = specular_image(gl, scene_path, monkeypatch, one_draw=False, budget=4096)
    assert drawn == 2 + 5 * 2 * 16
    assert waits == drawn - 1  # each step reaches the budget alone: a wait between any two
    assert stepped == whole
    # the comparison sees a change of one sample in 64
    fewer = write_scene(tmp_path, 128, 63)
    assert specular_image(gl, fewer, monkeypatch, one_draw=False, budget=4096)[0] != whole


# ---------------------------------------------------------------------------------------
# a signal during the prefilter


def read_stderr(process: subprocess.Popen, lines: list, renderer_made: threading.Event) -> None:
    for line in process.stderr:
        lines.append(line.rstrip("\n"))
        if line.startswith("GL renderer"):
            renderer_made.set()


FILM = """render: {size: [64, 48], film_samples: 1024, motion_blur: sub_frames, depth_of_field: sub_frames}
camera: {position: [0, 1, 5], target: [0, 0, 0], shutter: 0.5, aperture: 2.8, focus_distance: 5}
output: {frames: 12, fps: 24}
objects:
  - mesh: {primitive: box}
    rotation: {keys: [[0, [0, 0, 0]], [1, [30, 180, 0]]]}
"""


def write_film_scene(folder: Path) -> Path:
    """12 frames, each the mean of 1,024 sub-frames (a shutter and a lens): 1.5 to 3 s a frame."""
    (folder / "film.yaml").write_text(FILM, encoding="utf-8")
    return folder / "film.yaml"


def kill_all(process: subprocess.Popen) -> None:
    """Kill the render and any worker of it (its process group)."""
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    process.wait()


def write_frames_scene(folder: Path) -> Path:
    """The largest prefilter in a scene of 4 frames, for 2 workers to share."""
    path = write_scene(folder, 2048, 4096)
    path.write_text(path.read_text(encoding="utf-8").replace("shading: pbr}", "shading: pbr}\noutput: {frames: 4}"),
                    encoding="utf-8")
    return path


@pytest.mark.gl
@pytest.mark.slow
@pytest.mark.parametrize("make_scene, options", [
    (lambda folder: write_scene(folder, 2048, 4096), ()),
    (write_film_scene, ()),
    (write_frames_scene, ("--workers", "2")),
], ids=["largest_prefilter", "sub_frames", "workers"])
def test_sigterm_2_s_into_long_work_exits_143_within_3_seconds(tmp_path, make_scene, options):
    # The scene format's largest prefilter (2048 px, 4096 samples: 10 to 20 minutes on a
    # 2-core CPU) drawn in one go held SIGTERM back until it ended; sub-frames wait for
    # each other's readback; workers were waited for to the end of their chunk. SIGTERM
    # 2 s after the renderer line (which comes as the first frame starts; with workers,
    # only once a chunk is done: 8 s after the start), exit 143 well within 3 s, one line,
    # no temporary file, and only frames finished before it (none of the prefilter's).
    scene_path = make_scene(tmp_path)
    command = [sys.executable, "-m", "scenerender", "render", str(scene_path), "-o", str(tmp_path / "out"), *options]
    # a process group of its own: its workers are killed with it where the test fails
    process = subprocess.Popen(command, cwd=ROOT, stderr=subprocess.PIPE, text=True,
                               env={**os.environ, "PYTHONUNBUFFERED": "1"}, start_new_session=True)
    lines, renderer_made = [], threading.Event()
    reader = threading.Thread(target=read_stderr, args=(process, lines, renderer_made), daemon=True)
    reader.start()
    if not options and not renderer_made.wait(60):
        kill_all(process)
        skip_without_gl(process.returncode, "\n".join(lines))
        pytest.fail(f"no renderer line within 60 s: {lines}")
    time.sleep(8.0 if options else 2.0)
    if process.poll() is not None:
        kill_all(process)
        pytest.fail(f"the render ended before the signal: {lines}")
    sent = time.monotonic()
    process.send_signal(signal.SIGTERM)
    try:
        code = process.wait(timeout=3.0)
    except subprocess.TimeoutExpired:
        kill_all(process)
        pytest.fail(f"still running 3 s after SIGTERM: {lines}")
    took = time.monotonic() - sent
    reader.join(5)
    assert code == 143, lines
    assert took < 3.0
    assert lines[-1] == "error: interrupted by SIGTERM; frames already finished are complete, nothing partial was left"
    assert not any("Traceback" in line for line in lines)
    out = tmp_path / "out"
    left = sorted(p.name for p in out.iterdir() if p.name != ".scenerender.json") if out.exists() else []
    assert not any(".partial" in name for name in left)
    if scene_path.name == "scene.yaml" and not options:
        assert left == []
        # and it said how long it would take (its pace known after a second)
        assert any(line.startswith("prefiltering the environment (2048 px, 4096 samples): about ")
                   and line.endswith(" s on this renderer") for line in lines), lines
    elif options:
        assert left == []
    else:
        assert len(left) < 12 + 1  # the frames finished, and their cameras.json


@pytest.mark.gl
def test_the_visibility_maps_and_lookups_in_steps_draw_the_same_frame(gl, tmp_path, monkeypatch):
    # The environment's visibility: maps drawn with a wait between any two (CHECKPOINT_TEXELS
    # 1), the lookups of each place in 64x4 pieces (STEP_LOOKUPS 1): the same bytes as
    # the default render, where a frame this small waits for nothing before its readback.
    scene_path = write_scene(tmp_path, 32, 16)
    overrides = ["lights[0].visibility=true", "lights[0].visibility_directions=8",
                 "objects[0].position=[0, 1, 0]", "objects[1]={mesh: {primitive: plane, size: 6}}",
                 "camera={position: [0, 2, 5], target: [0, 0.5, 0]}", "render.size=[96, 64]"]
    waited = []
    monkeypatch.setattr(PassContext, "checkpoint", lambda ctx: waited.append(ctx.pass_name))
    default = render_linear(gl, scene_path, overrides)
    assert waited == []
    monkeypatch.setattr(steps_module, "STEP_LOOKUPS", 1)
    monkeypatch.setattr(shadow, "CHECKPOINT_TEXELS", 1)
    stepped = render_linear(gl, scene_path, overrides)
    assert waited.count("shadow:environment0 visibility") == 15  # between any two of 16 maps (8 regions in halves)
    assert waited.count("environment_visibility") >= 4
    assert np.array_equal(stepped, default)


MOVING_LIGHT = ["lights[1]={type: point, position: {keys: [[0, [1, 3, 1]], [1, [-1, 3, 2]]]}, intensity: 5, "
                "shadows: true}", "output.frames=3", "output.fps=2"]


@pytest.mark.gl
@pytest.mark.parametrize("stop_in, frame", [("environment_prefilter", 0), ("shadow:point1", 1)])
def test_a_render_stopped_mid_pass_leaves_nothing_the_next_render_reuses(gl, tmp_path, monkeypatch, stop_in, frame):
    # A signal stops a pass between two of its steps. Through the API the renderer can be
    # asked for the frame again: the prefilter (static, drawn in the first frame) and a
    # moving light's shadow maps (kept while the light stands still) are drawn again,
    # whole, not taken as done: the frame is the bytes of a renderer never stopped.
    scene_path = write_scene(tmp_path, 64, 64)
    overrides = ["lights[0].visibility=false", *MOVING_LIGHT]
    monkeypatch.setattr(steps_module, "STEP_LOOKUPS", 4096)
    monkeypatch.setattr(shadow, "CHECKPOINT_TEXELS", 1)
    with scenerender.Renderer(scenerender.load(scene_path, overrides), gl=gl) as renderer:
        expected = [renderer.render(i).pixels for i in range(frame + 1)][-1]
    waits = []
    wait = PassContext.checkpoint

    def stop_at_the_second(ctx):
        if ctx.pass_name == stop_in:
            waits.append(ctx.pass_name)
            if len(waits) == 2:
                raise Interrupted(signal.SIGTERM)
        wait(ctx)

    with scenerender.Renderer(scenerender.load(scene_path, overrides), gl=gl) as renderer:
        for index in range(frame):
            renderer.render(index)
        monkeypatch.setattr(PassContext, "checkpoint", stop_at_the_second)
        with pytest.raises(Interrupted):
            renderer.render(frame)
        monkeypatch.setattr(PassContext, "checkpoint", wait)
        assert np.array_equal(renderer.render(frame).pixels, expected)


def render_linear(gl, scene_path: Path, overrides: list) -> np.ndarray:
    """Frame 0's linear colours, (H, W, 3) float32."""
    with scenerender.Renderer(scenerender.load(scene_path, overrides), gl=gl, want_linear=True) as renderer:
        return renderer.render(0).linear


# ---------------------------------------------------------------------------------------
# progress and the limit


class Clock:
    def __init__(self):
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_long_work_says_its_estimate_then_what_is_left(monkeypatch, capsys):
    clock = Clock()
    monkeypatch.setattr(progress_module.time, "perf_counter", clock)
    progress = Progress(1, stream=sys.stderr, interval=5.0)
    what = "prefiltering the environment (2048 px, 4096 samples)"
    progress.work(what, 0.0)
    clock.now += 0.5
    progress.work(what, 0.001)  # under a second: no estimate yet
    clock.now += 0.5
    progress.work(what, 0.01)   # 1 s for 1 %: about 100 s
    clock.now += 2.0
    progress.work(what, 0.03)   # within the interval: nothing
    clock.now += 3.0
    progress.work(what, 0.06)   # 6 s for 6 %: 94 s left
    clock.now += 1.0
    progress.work(what, 1.0)
    assert capsys.readouterr().err.splitlines() == [
        f"{what}: about 100 s on this renderer",
        f"{what}: 6% done, about 94 s left",
    ]


def test_short_work_and_quiet_runs_say_nothing(monkeypatch, capsys):
    clock = Clock()
    monkeypatch.setattr(progress_module.time, "perf_counter", clock)
    for progress, fraction in [(Progress(1, stream=sys.stderr), 0.5), (Progress(1, quiet=True, stream=sys.stderr), 0.01)]:
        progress.work("prefiltering", 0.0)
        clock.now += 1.5
        progress.work("prefiltering", fraction)  # 3 s in all; 150 s but -q
    assert capsys.readouterr().err == ""


def test_the_prefilter_limit_refuses_the_scene_before_rendering(tmp_path):
    scene_path = write_scene(tmp_path, 2048, 4096)
    result = CliRunner().invoke(main, ["render", str(scene_path), "-o", str(tmp_path / "out"),
                                       "--limit", "prefilter_lookups=1000000000"])
    assert result.exit_code == 2, result.output
    assert result.stderr.strip() == (
        f"error: {display_path(scene_path)}:3:63: lights[0].samples: the prefilter's count of texture lookups at 2048 px and "
        "4096 samples is 42,951,770,112, over the limit of 1,000,000,000 (raise with --limit prefilter_lookups=N)")
    assert not (tmp_path / "out").exists()
    # the default lets the scene format's largest through
    assert CliRunner().invoke(main, ["validate", str(scene_path)]).exit_code == 0
