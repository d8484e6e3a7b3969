"""Frames are never stale: a re-run keeps a frame only when the run manifest shows it was
made from the same scene, assets, options and version, and the file is the one written."""
from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from scenerender.cli import main

pytestmark = pytest.mark.gl

SCENE = """\
render: {size: [32, 24], samples: 1}
output: {frames: 3}
objects:
  - mesh: models/tri.obj
    material: {diffuse: [0.8, 0.2, 0.2]}
"""

OBJ = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n"


@pytest.fixture
def project(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "tri.obj").write_text(OBJ)
    (tmp_path / "scene.yaml").write_text(SCENE)
    return tmp_path


def render(*args):
    result = CliRunner().invoke(main, ["render", "scene.yaml", "-o", "out", *args])
    assert result.exit_code == 0, result.output
    return result.stderr


def frame_bytes(folder) -> dict:
    """The frame files (not the hidden manifest, nor the cameras beside them)."""
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())
            if not p.name.startswith(".") and p.name != "cameras.json"}


def test_unchanged_scene_renders_nothing_again(project):
    first = render()
    assert "rendered 3 frames" in first
    before = {p.name: p.stat().st_mtime_ns for p in (project / "out").iterdir()}
    second = render()
    assert "nothing to do" in second
    assert {p.name: p.stat().st_mtime_ns for p in (project / "out").iterdir()} == before


@pytest.mark.parametrize("edit, reason", [
    (lambda p: (p / "scene.yaml").write_text(SCENE.replace("0.8, 0.2, 0.2", "0.2, 0.8, 0.2")), "the scene file"),
    (lambda p: (p / "models" / "tri.obj").write_text(OBJ.replace("v 0 1 0", "v 0.5 1 0")), "models/tri.obj changed"),
], ids=["colour", "asset-bytes"])
def test_an_edited_input_renders_every_frame_again(project, edit, reason):
    render()
    old = frame_bytes(project / "out")
    edit(project)
    again = render()
    assert "rendered 3 frames" in again
    assert reason in again  # one line says what changed
    new = frame_bytes(project / "out")
    assert new.keys() == old.keys()
    assert all(new[name] != old[name] for name in new)


@pytest.mark.parametrize("args", [["--set", "objects[0].material.diffuse=[0.1,0.1,0.9]"], ["--size", "40x30"],
                                  ["--samples", "4"]], ids=["override", "size", "samples"])
def test_changed_options_render_every_frame_again(project, args):
    render()
    old = frame_bytes(project / "out")
    again = render(*args)
    assert "rendered 3 frames" in again
    assert "options" in again
    assert frame_bytes(project / "out") != old


def test_a_frame_altered_on_disk_is_rendered_again(project):
    render()
    frame = project / "out" / "frame_0001.png"
    original = frame.read_bytes()
    frame.write_bytes(original[:-1] + b"\0")  # still decodes? it does not matter: the hash differs
    again = render()
    assert "rendered 1 frame " in again and "2 already there" in again
    assert frame.read_bytes() == original


def test_frames_of_an_older_scene_outside_the_range_are_removed(project):
    render()
    (project / "scene.yaml").write_text(SCENE.replace("0.8, 0.2, 0.2", "0.2, 0.8, 0.2"))
    render("--frames", "0:1")
    assert list(frame_bytes(project / "out")) == ["frame_0000.png"]


def test_frames_without_a_manifest_are_not_trusted(project):
    render()
    (project / "out" / ".scenerender.json").unlink()
    assert "rendered 3 frames" in render()


def test_video_is_rendered_again_after_a_change(project):
    render("--format", "gif")
    video = project / "out" / "scene.gif"
    old = video.read_bytes()
    assert "nothing to do" in render("--format", "gif")
    (project / "scene.yaml").write_text(SCENE.replace("0.8, 0.2, 0.2", "0.2, 0.8, 0.2"))
    assert "rendered 3 frames" in render("--format", "gif")
    assert video.read_bytes() != old


def test_manifest_records_provenance(project):
    render()
    manifest = json.loads((project / "out" / ".scenerender.json").read_text())
    import scenerender

    assert manifest["scenerender"] == scenerender.__version__
    assert manifest["gl"]["renderer"]
    assert set(manifest["frames"]) == {"frame_0000.png", "frame_0001.png", "frame_0002.png"}
    (run,) = manifest["runs"].values()
    assert "asset:models/tri.obj" in run["inputs"]


def test_scenes_sharing_a_folder_keep_each_others_frames(project):
    (project / "other.yaml").write_text(SCENE.replace("output: {frames: 3}", 'output: {frames: 2, name: "other_{frame}"}'))
    render()
    result = CliRunner().invoke(main, ["render", "other.yaml", "-o", "out"])
    assert result.exit_code == 0, result.output
    (project / "other.yaml").write_text(SCENE.replace("output: {frames: 3}", 'output: {frames: 1, name: "other_{frame}"}'))
    assert CliRunner().invoke(main, ["render", "other.yaml", "-o", "out"]).exit_code == 0
    assert list(frame_bytes(project / "out")) == ["frame_0000.png", "frame_0001.png", "frame_0002.png", "other_0.png"]
    assert "nothing to do" in render()


def test_a_single_image_output_is_fingerprinted_too(project):
    (project / "scene.yaml").write_text(SCENE.replace("output: {frames: 3}", "output: {frames: 1}"))
    result = CliRunner().invoke(main, ["render", "scene.yaml", "-o", "still.png"])
    assert result.exit_code == 0, result.output
    assert (project / ".still.png.scenerender.json").is_file()
    again = CliRunner().invoke(main, ["render", "scene.yaml", "-o", "still.png"])
    assert "nothing to do" in again.stderr
    (project / "scene.yaml").write_text(SCENE.replace("output: {frames: 3}", "output: {frames: 1}").replace("0.8,", "0.5,"))
    assert "rendered 1 frame" in CliRunner().invoke(main, ["render", "scene.yaml", "-o", "still.png"]).stderr


# A manifest the product cannot use (cut short, edited by hand, written by something else)
# is as good as absent: one warning naming it, and every frame is rendered again.
GARBAGE_MANIFESTS = {
    "frames-a-number": b'{"format": 1, "frames": 5}',
    "run-a-string": b'{"format": 1, "runs": {"scene.yaml": "abc"}}',
    "frame-entry-a-list": b'{"format": 1, "frames": {"frame_0000.png": [1, 2]}}',
    "inputs-null": b'{"format": 1, "runs": {"scene.yaml": {"run": "x", "inputs": null}}}',
    "bytes-as-text": b'{"format": 1, "frames": {"frame_0000.png": {"bytes": "12", "sha256": "x"}}}',
    "nested-100000": b"[" * 100_000 + b"]" * 100_000,
    "not-utf8": b'{"format": 1, "scenerender": "\xff"}',
    "not-json": b'{"format": 1,',
    "nan": b'{"format": 1, "frames": {"f": {"bytes": NaN}}}',
    "a-list": b"[1, 2]",
    "other-format": b'{"format": 2}',
}


@pytest.mark.parametrize("garbage", GARBAGE_MANIFESTS.values(), ids=GARBAGE_MANIFESTS.keys())
def test_a_garbage_manifest_is_treated_as_absent_with_a_warning(project, garbage):
    render()
    (project / "out" / ".scenerender.json").write_bytes(garbage)
    again = render()
    assert "rendered 3 frames" in again
    warnings = [line for line in again.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1 and ".scenerender.json" in warnings[0] and "rendered again" in warnings[0], again
    assert "nothing to do" in render()  # the run wrote a good one back


def test_a_huge_manifest_is_not_read(project, monkeypatch):
    render()
    monkeypatch.setattr("scenerender.run.manifest.MANIFEST_MAX_BYTES", 1000)
    manifest = project / "out" / ".scenerender.json"
    manifest.write_bytes(manifest.read_bytes() + b" " * 1000)
    again = render()
    assert "rendered 3 frames" in again and "over the limit of 1,000" in again
