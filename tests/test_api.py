"""The public Python API: load, Scene.from_dict, Renderer, render, render_to."""
from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

import scenerender
from scenerender.cli import main

from conftest import SCENES

SMALL = ["render.size=[48,36]", "render.samples=1"]


def test_load_reads_and_validates_a_scene():
    scene = scenerender.load(SCENES / "primitives.yaml", overrides=SMALL)
    assert scene.size == (48, 36)
    assert scene.name == "primitives"
    assert scene.frame_count >= 1 and scene.fps > 0
    assert "48x36" in repr(scene)


def test_scene_error_carries_file_line_and_key(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("objects:\n  - mesh: {primitive: sphre}\n")
    with pytest.raises(scenerender.SceneError) as caught:
        scenerender.load(path)
    error = caught.value
    assert error.location.file.endswith("bad.yaml")
    assert error.location.line == 2
    assert error.key == "objects[0].mesh.primitive"
    assert "did you mean 'sphere'" in str(error)


def test_from_dict_validates_like_a_file():
    with pytest.raises(scenerender.SceneError) as caught:
        scenerender.Scene.from_dict({"objects": [{"mesh": {"primitive": "box"}, "scale": -1}]})
    assert caught.value.key == "objects[0].scale"
    assert "built in code" in str(caught.value)


@pytest.mark.gl
def test_from_dict_with_a_trimesh_mesh_and_arrays(gl):
    trimesh = pytest.importorskip("trimesh")
    triangle = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]]))
    scene = scenerender.Scene.from_dict({
        "render": {"size": [40, 30], "samples": 1, "background": [0, 0, 0]},
        "camera": {"position": [0, 0, 4], "target": [0, 0, 0]},
        "objects": [{"mesh": trimesh.creation.icosphere(subdivisions=2), "position": [-0.8, 0, 0]},
                    {"mesh": triangle, "position": [0.5, -0.5, 0]}],
    })
    with scenerender.Renderer(scene, gl=gl) as renderer:
        pixels = renderer.render(0).pixels
    assert pixels.shape == (30, 40, 3) and pixels.dtype == np.uint8
    lit = pixels.max(axis=2) > 0
    assert lit[:, :18].any() and lit[:, 22:].any()  # sphere on the left, triangle on the right


def test_from_dict_rejects_bad_arrays():
    with pytest.raises(scenerender.SceneError, match="face index"):
        scenerender.Scene.from_dict({"objects": [{"mesh": (np.zeros((3, 3)), np.array([[0, 1, 5]]))}]})


@pytest.mark.gl
def test_renderer_renders_three_frames(gl):
    scene = scenerender.load(SCENES / "garden.yaml", overrides=SMALL)
    with scenerender.Renderer(scene, gl=gl) as renderer:
        frames = [renderer.render(i) for i in range(3)]
    assert [f.index for f in frames] == [0, 1, 2]
    assert [f.time for f in frames] == [i / scene.fps for i in range(3)]
    assert all(f.pixels.shape == (36, 48, 3) for f in frames)
    assert not np.array_equal(frames[0].pixels, frames[2].pixels)  # the light moves


@pytest.mark.gl
def test_render_iterates_frames_on_its_own_context():
    scene = scenerender.load(SCENES / "primitives.yaml", overrides=SMALL)
    frames = list(scenerender.render(scene, frames=range(2)))
    assert [f.index for f in frames] == [0, 1]
    assert frames[0].linear is None  # only on request: it needs a float target


@pytest.mark.gl
def test_linear_colours_on_request(gl):
    scene = scenerender.load(SCENES / "primitives.yaml", overrides=SMALL)
    with scenerender.Renderer(scene, gl=gl, want_linear=True) as renderer:
        frame = renderer.render(0)
    assert frame.linear.shape == (36, 48, 3) and frame.linear.dtype == np.float32
    encoded = np.where(frame.linear <= 0.0031308, 12.92 * frame.linear,
                       1.055 * np.clip(frame.linear, 0.0031308, None) ** (1 / 2.4) - 0.055)
    assert np.abs(np.clip(encoded, 0, 1) * 255 - frame.pixels).max() <= 1


@pytest.mark.gl
def test_render_to_writes_what_the_cli_writes(tmp_path):
    args = ["--frames", "0:2", "--size", "48x36", "--samples", "1"]
    result = CliRunner().invoke(main, ["render", str(SCENES / "primitives.yaml"), "-o", str(tmp_path / "cli"), *args])
    assert result.exit_code == 0, result.output
    summary = scenerender.render_to(SCENES / "primitives.yaml", tmp_path / "api",
                                    overrides=SMALL, frames="0:2")
    assert summary.rendered == 2
    names = sorted(p.name for p in (tmp_path / "cli").glob("*.png"))
    assert names == ["frame_0000.png", "frame_0001.png"]
    for name in names:
        assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "api" / name).read_bytes()
