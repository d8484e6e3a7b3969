"""The per-pass profile (`scenerender render --profile`): its table, and the timings a
profiling GraphRenderer records (static passes once, every other pass every frame)."""
from __future__ import annotations

from scenerender.rendering.profile import CPU_SETUP, format_table, summarise

SCENE = """
render: {size: [48, 32], samples: 4}
output: {frames: 3}
camera: {position: {keys: [[0, [0, 2, 5]], [1, [2, 2, 5]]]}, target: [0, 0, 0]}
lights: [{name: sun, type: spot, position: [1, 4, 1], direction: [-0.3, -1, -0.2], shadows: true}]
objects:
  - mesh: {primitive: box}
"""


def test_table_lists_static_passes_once_and_sums_every_frame():
    timings = {CPU_SETUP: [0.001] * 3, "shadow:sun": [0.050], "opaque": [0.010, 0.012, 0.011]}
    rows = summarise(timings, frames=3, static_names={"shadow:sun"})
    assert [(r.name, r.runs, r.once) for r in rows] == [(CPU_SETUP, 3, False), ("shadow:sun", 1, True),
                                                        ("opaque", 3, False)]
    table = format_table(rows, frames=3)
    assert "| shadow:sun | 1 | 50.00 (once) |" in table
    assert "| opaque | 3 | 11.00 | 33.0 |" in table
    assert "**12.00**" in table  # per frame: CPU setup + opaque, not the static shadow pass


def test_a_map_kept_in_some_frames_counts_its_mean_per_frame():
    """A dynamic pass that kept its result in two of four frames: its median when drawn,
    and its mean over the four frames in the per-frame total."""
    timings = {"shadow:sun": [0.020, 0.020], "opaque": [0.010] * 4}
    table = format_table(summarise(timings, frames=4, static_names=set()), frames=4)
    assert "| shadow:sun | 2 | 20.00 (in 2 of 4 frames) | 40.0 |" in table
    assert "**20.00**" in table  # 10 ms opaque + 40 ms of sun map over 4 frames


def test_profiling_renderer_times_each_pass(gl, tmp_path):
    from scenerender.errors import Warnings
    from scenerender.rendering.profile import profile_report
    from scenerender.rendering.renderer import GraphRenderer
    from scenerender.scene.loading import load_scene_text
    from scenerender.world.build import build_world

    world = build_world(load_scene_text(SCENE, tmp_path, []), Warnings())
    renderer = GraphRenderer(world, gl, profile=True)
    try:
        for index in range(3):
            renderer.render(index)
        report = profile_report(renderer, 3)
    finally:
        renderer.release()
    assert len(renderer.timings["shadow:sun"]) == 1 and len(renderer.timings["opaque"]) == 3
    assert "| shadow:sun | 1 |" in report and "(once)" in report and "| readback | 3 |" in report


def test_render_profile_flag_prints_the_table(gl, tmp_path):
    from click.testing import CliRunner

    from scenerender.cli import main

    (tmp_path / "scene.yaml").write_text(SCENE.replace("frames: 3", "frames: 2, format: png"), encoding="utf-8")
    result = CliRunner().invoke(main, ["render", str(tmp_path / "scene.yaml"), "-o", str(tmp_path / "out"),
                                       "-q", "--profile"])
    assert result.exit_code == 0, result.output
    assert "per-pass profile over 2 frame(s)" in result.stdout and "| opaque | 2 |" in result.stdout
    assert len(list((tmp_path / "out").glob("*.png"))) == 2
