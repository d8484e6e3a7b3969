"""Animated renders end to end: frame-exact partial renders, resume, videos, and one set of
GPU resources for a whole run."""
from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from conftest import SCENES, load
from scenerender.errors import Warnings
from scenerender.run.job import RenderOptions, run_render

SMALL = ["render.size=[96, 64]"]

ANIMATED = """
render: {size: [96, 64], samples: 4, shadows: {size: 256}}
output: {fps: 10, frames: 12}
camera:
  position: {keys: [[0, [0, 2, 5]], [1.1, [3, 2, 3]]], interpolation: catmull_rom}
  target: [0, 0.5, 0]
lights:
  - {type: directional, direction: [-0.4, -1, -0.3], shadows: true}
  - type: point
    position: {keys: [[0, [-2, 2, 1]], [1.1, [2, 2, 1]]], interpolation: cosine}
    color: [1, 0.6, 0.3]
    attenuation: [1, 0.3, 0.2]
    enabled: {keys: [[0, true], [0.5, false], [0.8, true]]}
objects:
  - mesh: {primitive: plane, size: 6}
    cast_shadows: false
  - mesh: {primitive: box, size: 0.8}
    position: {keys: [[0, [0, 0.4, 0]], [1.1, [1, 0.4, -1]]]}
    rotation: {keys: [[0, [0, 0, 0]], [1.1, [0, 90, 0]]], interpolation: linear}
    material: {diffuse: {keys: [[0, [0.9, 0.2, 0.2]], [1.1, [0.2, 0.2, 0.9]]]}}
"""


def write_scene(tmp_path, text=ANIMATED):
    path = tmp_path / "anim.yaml"
    path.write_text(text)
    return path


def frames_of(folder):
    return sorted(p.name for p in folder.glob("frame_*.png"))


def pixels(path):
    return np.asarray(Image.open(path).convert("RGB"))


@pytest.mark.gl
def test_a_frame_rendered_alone_equals_that_frame_of_the_full_run(tmp_path):
    scene = write_scene(tmp_path)
    run_render(scene, RenderOptions(output=tmp_path / "full", quiet=True), echo=lambda *_: None)
    for k in (0, 5, 11):
        out = tmp_path / f"only{k}"
        run_render(scene, RenderOptions(output=out, frames=f"{k}:{k + 1}", quiet=True), echo=lambda *_: None)
        assert frames_of(out) == [f"frame_{k:04d}.png"]
        assert np.array_equal(pixels(out / f"frame_{k:04d}.png"), pixels(tmp_path / "full" / f"frame_{k:04d}.png"))


@pytest.mark.gl
def test_frames_differ_over_the_animation(tmp_path):
    scene = write_scene(tmp_path)
    run_render(scene, RenderOptions(output=tmp_path / "out", quiet=True), echo=lambda *_: None)
    names = frames_of(tmp_path / "out")
    assert len(names) == 12
    first, last = pixels(tmp_path / "out" / names[0]), pixels(tmp_path / "out" / names[-1])
    assert np.abs(first.astype(int) - last.astype(int)).mean() > 5


@pytest.mark.gl
def test_resume_keeps_complete_frames_and_redoes_broken_ones(tmp_path):
    scene = write_scene(tmp_path)
    out = tmp_path / "out"
    run_render(scene, RenderOptions(output=out, frames="0:6", quiet=True), echo=lambda *_: None)
    stamps = {p.name: (p.stat().st_mtime_ns, p.read_bytes()) for p in out.glob("*.png")}
    broken = out / "frame_0003.png"
    broken.write_bytes(broken.read_bytes()[:200])  # as if a copy had been cut short
    summary = run_render(scene, RenderOptions(output=out, quiet=True), echo=lambda *_: None)
    assert summary.rendered == 7 and summary.skipped == 5  # frames 3 and 6..11
    assert summary.frames == [3, 6, 7, 8, 9, 10, 11]
    for name, (mtime, data) in stamps.items():
        if name != "frame_0003.png":
            assert (out / name).stat().st_mtime_ns == mtime and (out / name).read_bytes() == data
    assert pixels(broken).shape == (64, 96, 3)
    again = run_render(scene, RenderOptions(output=out, quiet=True), echo=lambda *_: None)
    assert again.rendered == 0 and again.skipped == 12
    forced = run_render(scene, RenderOptions(output=out, frames="0:2", overwrite=True, quiet=True),
                        echo=lambda *_: None)
    assert forced.rendered == 2


@pytest.mark.gl
@pytest.mark.parametrize("fmt", ["mp4", "gif"])
def test_video_reads_back_with_the_right_frame_count_and_size(tmp_path, fmt):
    scene = write_scene(tmp_path)
    summary = run_render(scene, RenderOptions(output=tmp_path, format=fmt, quiet=True), echo=lambda *_: None)
    video = tmp_path / f"anim.{fmt}"
    assert summary.rendered == 12 and video.is_file()
    assert not list(tmp_path.glob("*.partial*"))
    if fmt == "mp4":
        import imageio_ffmpeg

        reader = imageio_ffmpeg.read_frames(str(video))
        meta = next(reader)
        count = sum(1 for _ in reader)
        assert tuple(meta["size"]) == (96, 64) and meta["fps"] == 10 and count == 12
    else:
        from PIL import ImageSequence

        with Image.open(video) as gif:
            frames = list(ImageSequence.Iterator(gif))
            assert gif.size == (96, 64) and len(frames) == 12


@pytest.mark.gl
def test_an_existing_video_is_kept_unless_overwrite(tmp_path):
    scene = write_scene(tmp_path)
    first = run_render(scene, RenderOptions(output=tmp_path, format="gif", quiet=True), echo=lambda *_: None)
    video = tmp_path / f"{scene.stem}.gif"
    made = (video.read_bytes(), video.stat().st_ino)  # a rewrite renames a new file into place
    again = run_render(scene, RenderOptions(output=tmp_path, format="gif", quiet=True), echo=lambda *_: None)
    assert first.rendered > 0 and again.rendered == 0
    assert (video.read_bytes(), video.stat().st_ino) == made  # not written again
    forced = run_render(scene, RenderOptions(output=tmp_path, format="gif", quiet=True, overwrite=True),
                        echo=lambda *_: None)
    assert forced.rendered == first.rendered and video.stat().st_ino != made[1]


def test_gpu_resources_stay_the_same_over_many_frames(gl):
    """One context, one set of resources: nothing is created per frame after the first."""
    from scenerender.rendering.renderer import GraphRenderer
    from scenerender.world.build import build_world

    world = build_world(load(SCENES / "showcase.yaml", SMALL), Warnings())
    renderer = GraphRenderer(world, gl)
    try:
        renderer.render(0)
        before = (len(renderer.scene._vaos), renderer.programs.count, renderer.scene.textures.count,
                  len(renderer.backend.run.framebuffers._fbos), len(renderer.scene._extras))
        for i in range(1, 40, 3):
            renderer.render(i)
        after = (len(renderer.scene._vaos), renderer.programs.count, renderer.scene.textures.count,
                 len(renderer.backend.run.framebuffers._fbos), len(renderer.scene._extras))
        assert before == after
    finally:
        renderer.release()


def test_static_shadow_maps_render_once_for_a_flythrough(gl):
    """The lantern's cube map depends only on still lights and casters: rendered once. So
    is the sun's, which covers the casters' whole footprint for the run
    (world.directional_views); with a pine 60 m out that would take too large a map, and
    the sun's map follows the moving camera."""
    import scenerender

    scene = scenerender.load(SCENES / "showcase.yaml", SMALL)
    with scenerender.Renderer(scene, gl=gl, profile=True) as renderer:
        for i in range(4):
            renderer.render(i)
        timings = renderer.timings
    assert len(timings["shadow:lantern"]) == 1
    assert len(timings["shadow:sun"]) == 1 and len(timings["opaque"]) == 4
    far_pine = scenerender.load(SCENES / "showcase.yaml", [*SMALL, "objects[9].instances[0].position=[60, 0, 0]"])
    with scenerender.Renderer(far_pine, gl=gl, profile=True) as renderer:
        for i in range(4):
            renderer.render(i)
        timings = renderer.timings
    assert len(timings["shadow:lantern"]) == 1 and len(timings["shadow:sun"]) == 4


@pytest.mark.gl
def test_cli_progress_summary_and_quiet(tmp_path):
    scene = write_scene(tmp_path)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run([sys.executable, "-m", "scenerender", "render", str(scene), "-o", str(tmp_path / "o"),
                          "--frames", "0:3"], capture_output=True, text=True, env=env, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stderr.strip().splitlines()[-1].startswith("rendered 3 frames in ")
    quiet = subprocess.run([sys.executable, "-m", "scenerender", "render", str(scene), "-o", str(tmp_path / "q"),
                            "--frames", "0:3", "-q"], capture_output=True, text=True, env=env, timeout=120)
    assert quiet.returncode == 0 and quiet.stderr == "" and quiet.stdout == ""


def test_frame_names_pad_past_9999(tmp_path):
    from scenerender.run.output import make_sink

    loaded = load(write_scene(tmp_path, ANIMATED.replace("frames: 12", "frames: 12000")))
    sink = make_sink(loaded, "png", tmp_path, (96, 64))
    names = [sink.path_for(i).name for i in (0, 9999, 10000, 11999)]
    assert names == ["frame_00000.png", "frame_09999.png", "frame_10000.png", "frame_11999.png"]
    assert names == sorted(names)
