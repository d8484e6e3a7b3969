"""The ``scenerender`` command line: messages, exit codes and end-to-end runs.

Exit codes: 0 ok, 1 bug (or ``diff`` found a difference), 2 bad input, 3 environment.
Tests marked ``gl`` render (tiny frames) and need an EGL context; Mesa llvmpipe is enough.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from conftest import skip_without_gl
from scenerender.cli import main

GOOD = "render: {size: [32, 24]}\nobjects:\n  - mesh: {primitive: box}\n"
BAD = ("render:\n  size: [32, 24]\n  shading: blin_phong\n"
       "objects:\n  - mesh: {primitive: bx}\n  - mesh: {primitive: box}\n    visible: yes\n")
BAD_LINES = [
    "error: bad.yaml:3:3: render.shading: expected one of phong, blinn_phong, pbr, unlit, got 'blin_phong' "
    "(did you mean 'blinn_phong'?)",
    "error: bad.yaml:5:12: objects[0].mesh.primitive: unknown primitive 'bx' (did you mean 'box'?) "
    "(one of plane, box, sphere, cylinder, prism, cone)",
    "error: bad.yaml:7:5: objects[1].visible: expected true or false, got 'yes'",
]


@pytest.fixture
def scenes(tmp_path, monkeypatch):
    """Work in tmp_path with good.yaml and bad.yaml there (messages show relative names)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "good.yaml").write_text(GOOD, encoding="utf-8")
    (tmp_path / "bad.yaml").write_text(BAD, encoding="utf-8")
    return tmp_path


def cli(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def run_module(*args, cwd):
    return subprocess.run([sys.executable, "-m", "scenerender", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=60)


def frame_files(folder) -> list[str]:
    """The frames a render wrote: less its hidden run manifest and the frames' cameras
    (cameras.json beside frames, <video>.cameras.json beside a video)."""
    return sorted(p.name for p in folder.iterdir() if not p.name.startswith(".") and not p.name.endswith("cameras.json"))


def write_png(path, pixels):
    Image.fromarray(np.asarray(pixels, np.uint8), "RGB").save(path)


# ---------------------------------------------------------------------------------------
# validate


def test_validate_good_scene(scenes):
    result = cli("validate", "good.yaml")
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("ok: good.yaml")
    assert "1 objects" in result.stdout and "32x24" in result.stdout and "1 frame(s)" in result.stdout
    assert result.stderr == ""


def test_validate_bad_scene_one_line_per_error(scenes):
    result = cli("validate", "bad.yaml")
    assert result.exit_code == 2
    assert result.stdout == ""
    assert result.stderr.splitlines() == BAD_LINES
    assert "Traceback" not in result.output


def test_validate_reports_duplicate_key(scenes):
    (scenes / "dup.yaml").write_text("render:\n  samples: 4\n  samples: 8\n", encoding="utf-8")
    result = cli("validate", "dup.yaml")
    assert result.exit_code == 2
    assert result.stderr == "error: dup.yaml:3:3: duplicate key 'samples' (first given on line 2)\n"


def test_validate_missing_scene_file(scenes):
    result = cli("validate", "nope.yaml")
    assert result.exit_code == 2
    assert result.stderr == "error: nope.yaml: scene file not found\n"


def test_validate_yaml_syntax_error(scenes):
    (scenes / "broken.yaml").write_text("render:\n  size: [1, 2\n", encoding="utf-8")
    result = cli("validate", "broken.yaml")
    assert result.exit_code == 2
    assert result.stderr.startswith("error: broken.yaml:3:")
    assert "YAML syntax error" in result.stderr
    assert len(result.stderr.splitlines()) == 1


def test_validate_with_set(scenes):
    result = cli("validate", "good.yaml", "--set", "render.size=[64, 48]", "--set", "output.frames=5")
    assert result.exit_code == 0, result.output
    assert "64x48" in result.stdout and "5 frame(s)" in result.stdout


def test_validate_bad_set_value(scenes):
    result = cli("validate", "good.yaml", "--set", "render.samples=lots")
    assert result.exit_code == 2
    assert result.stderr == ("error: --set render.samples=lots: render.samples: "
                             "expected a whole number, got 'lots'\n")


def test_validate_missing_mesh_file(scenes):
    (scenes / "m.yaml").write_text("objects:\n  - mesh: models/duck.obj\n", encoding="utf-8")
    result = cli("validate", "m.yaml")
    assert result.exit_code == 2
    assert result.stderr == "error: m.yaml:2:5: objects[0].mesh: file not found: models/duck.obj\n"


def test_validate_end_to_end(scenes):
    good = run_module("validate", "good.yaml", cwd=scenes)
    assert good.returncode == 0, good.stderr
    assert good.stdout.startswith("ok: good.yaml")
    bad = run_module("validate", "bad.yaml", cwd=scenes)
    assert bad.returncode == 2
    assert bad.stderr.splitlines() == BAD_LINES
    assert "Traceback" not in bad.stderr


# ---------------------------------------------------------------------------------------
# schema and graph


def test_schema_prints_json(scenes):
    result = cli("schema")
    assert result.exit_code == 0
    schema = json.loads(result.stdout)
    assert schema["title"] == "scenerender scene"
    assert {"render", "output", "camera", "lights", "materials", "objects"} <= set(schema["properties"])


def test_schema_to_file(scenes):
    result = cli("schema", "-o", "schema.json")
    assert result.exit_code == 0
    assert result.stdout == ""
    assert "objects" in json.loads((scenes / "schema.json").read_text(encoding="utf-8"))["properties"]


@pytest.mark.parametrize("destination", ["afile/schema.json", "afile/sub/schema.json", "/proc/schema.json"])
def test_schema_to_an_unwritable_place(scenes, destination):
    if destination.startswith("/proc") and not os.path.isdir("/proc/self"):
        pytest.skip("no /proc here")
    (scenes / "afile").write_text("mine")
    result = cli("schema", "-o", destination)
    assert result.exit_code == 2, result.output
    line, = result.stderr.splitlines()
    assert line.startswith("error: ") and ": cannot write: " in line and line.endswith("write elsewhere with -o)")
    assert (scenes / "afile").read_text() == "mine"


def test_graph_lists_passes(scenes):
    result = cli("graph", "good.yaml")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0].startswith("render graph of good.yaml: mode shaded, 32x24, 4x MSAA")
    assert lines[0].endswith(", 1 frame(s)")
    for name in ("opaque", "resolve", "output_transform", "readback"):
        assert any(name in line for line in lines), name


def test_graph_shows_the_exposure_and_tone_map_in_the_output_pass(scenes):
    result = cli("graph", "good.yaml", "--set", "render.tone_map=agx", "--set", "render.exposure=0.5")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    output, = [line for line in lines if "resolve+output_transform" in line]
    assert output.endswith("4x MSAA, exposure +0.5, agx tone map, srgb")
    assert "exposure" in lines[lines.index(output) + 1]  # the input it reads
    assert any(line.split() == ["exposure", "static"] for line in lines)


def test_graph_size_and_samples_options(scenes):
    result = cli("graph", "good.yaml", "--size", "20x10", "--samples", "1")
    assert result.exit_code == 0, result.output
    assert "20x10" in result.stdout.splitlines()[0]
    assert "4x MSAA" not in result.stdout


def test_graph_shows_the_samples_the_device_gives(scenes):
    """64 samples are allowed in a scene, but a device offers fewer: the graph says what runs."""
    from scenerender.run.graph_report import device_max_samples

    offered = device_max_samples()
    result = cli("graph", "good.yaml", "--samples", "64")
    assert result.exit_code == 0, result.output
    if offered is not None:
        assert f"{offered}x MSAA (64 asked; this device offers {offered})" in result.stdout.splitlines()[0]
        assert "64x MSAA" not in result.stdout
    else:
        assert "no GL device to ask" in result.stdout


def test_graph_dot(scenes):
    result = cli("graph", "good.yaml", "--dot")
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("digraph")
    assert result.stdout.rstrip().endswith("}")
    assert "opaque" in result.stdout


def test_graph_bad_scene(scenes):
    result = cli("graph", "bad.yaml")
    assert result.exit_code == 2
    assert result.stderr.splitlines() == BAD_LINES


# ---------------------------------------------------------------------------------------
# render: option errors found before any GL work


@pytest.mark.parametrize("size", ["10x", "x10", "10", "axb", "10x-3", "²x10", "9" * 5000 + "x10"])
@pytest.mark.parametrize("command", ["render", "graph", "reference", "bench"])
def test_bad_size(scenes, command, size):
    """'²' is a digit to str.isdigit but not to int(), and int() refuses 5000 digits."""
    result = cli(command, "good.yaml", "-o", "out", "--size", size) if command != "graph" else \
        cli(command, "good.yaml", "--size", size)
    assert result.exit_code == 2
    assert "Invalid value for '--size': expected WIDTHxHEIGHT" in result.stderr
    assert "internal error" not in result.stderr
    assert not (scenes / "out").exists()


def test_render_empty_frame_range(scenes):
    result = cli("render", "good.yaml", "-o", "out", "--frames", "5:3")
    assert result.exit_code == 2
    assert result.stderr == "error: --frames: '5:3' selects no frames; the scene has frames 0..0\n"
    assert not (scenes / "out").exists()


def test_render_bad_set_path(scenes):
    result = cli("render", "good.yaml", "-o", "out", "--set", "objects[3].position=[0,0,0]")
    assert result.exit_code == 2
    assert result.stderr == "error: --set objects[3].position=[0,0,0]: no item 3 at 'objects'\n"


def test_render_set_without_value(scenes):
    result = cli("render", "good.yaml", "-o", "out", "--set", "render.samples")
    assert result.exit_code == 2
    assert "--set expects key=value" in result.stderr


def test_render_bad_scene(scenes):
    result = cli("render", "bad.yaml", "-o", "out")
    assert result.exit_code == 2
    assert result.stderr.splitlines() == BAD_LINES
    assert not (scenes / "out").exists()


def test_render_missing_scene(scenes):
    result = cli("render", "nope.yaml", "-o", "out")
    assert result.exit_code == 2
    assert "scene file not found" in result.stderr


@pytest.mark.parametrize("args", [["--samples", "0"], ["--samples", "65"], ["--format", "bmp"]])
def test_render_bad_option_values(scenes, args):
    result = cli("render", "good.yaml", "-o", "out", *args)
    assert result.exit_code == 2
    assert not (scenes / "out").exists()


SAMPLES_MESSAGE = "render.samples: MSAA samples must be one of 1, 2, 4, 8, 16, 32, 64 (1 = off), got 3"


@pytest.mark.parametrize("command", ["validate", "render"])
def test_a_sample_count_no_device_offers_is_bad_input_for_validate_and_render(scenes, command):
    """3 samples passed validate, then failed in render as an internal error (the driver
    refuses counts that are not powers of two) after making the output folder."""
    (scenes / "three.yaml").write_text(GOOD.replace("size: [32, 24]", "size: [32, 24], samples: 3"), encoding="utf-8")
    result = cli(command, "three.yaml", *(["-o", "out"] if command == "render" else []))
    assert result.exit_code == 2, result.output
    assert result.stderr == f"error: three.yaml:1:26: {SAMPLES_MESSAGE}\n"
    assert not (scenes / "out").exists()


@pytest.mark.parametrize("args, message", [
    (["--samples", "3"], "Error: Invalid value for '--samples': " + SAMPLES_MESSAGE.removeprefix("render.samples: ")),
    (["--set", "render.samples=3"], f"error: --set render.samples=3: {SAMPLES_MESSAGE}"),
])
def test_a_sample_count_from_the_command_line_is_checked_like_the_file(scenes, args, message):
    result = cli("render", "good.yaml", "-o", "out", *args)
    assert result.exit_code == 2, result.output
    assert result.stderr.splitlines()[-1] == message
    assert not (scenes / "out").exists()


# ---------------------------------------------------------------------------------------
# diff


def test_diff_identical_images(scenes):
    pixels = np.zeros((12, 16, 3), np.uint8)
    pixels[3:6, 4:9] = (200, 100, 50)
    write_png(scenes / "a.png", pixels)
    write_png(scenes / "b.png", pixels)
    result = cli("diff", "a.png", "b.png")
    assert result.exit_code == 0
    assert result.stdout == "PASS: 1 frame(s) match (identical); judged by colour alone: neither side has object ids\n"


def test_diff_different_images(scenes):
    a = np.zeros((12, 16, 3), np.uint8)
    b = a.copy()
    b[0:6, 0:8] = 255
    write_png(scenes / "a.png", a)
    write_png(scenes / "b.png", b)
    result = cli("diff", "a.png", "b.png", "--report", "report.html")
    assert result.exit_code == 1
    assert result.stdout.startswith("CHANGED b.png: worst 8x8 tile")
    assert "FAIL: 1 of 1 frame(s) changed, 0 missing, 0 extra; judged by colour alone" in result.stdout
    assert result.stdout.endswith("\nreport: report.html\n")
    assert "data:image/png;base64," in (scenes / "report.html").read_text()


def test_diff_tolerances_decide(scenes):
    a = np.full((10, 10, 3), 100, np.uint8)
    write_png(scenes / "a.png", a)
    write_png(scenes / "b.png", a + 3)
    assert cli("diff", "a.png", "b.png").exit_code == 1           # 3 levels: 2 past the tolerance
    assert cli("diff", "a.png", "b.png", "--aa-tolerance", "3").exit_code == 0


def test_diff_different_sizes(scenes):
    """A different size means the render changed: exit 1, not bad input."""
    write_png(scenes / "a.png", np.zeros((10, 10, 3)))
    write_png(scenes / "b.png", np.zeros((10, 12, 3)))
    result = cli("diff", "a.png", "b.png")
    assert result.exit_code == 1
    assert result.stdout.startswith("CHANGED b.png: size differs: 10x10 vs 12x10\n")


def test_diff_unreadable_image(scenes):
    write_png(scenes / "a.png", np.zeros((10, 10, 3)))
    (scenes / "b.png").write_bytes(b"not an image")
    result = cli("diff", "a.png", "b.png")
    assert result.exit_code == 2
    assert result.stderr.startswith("error: b.png: cannot read image")
    assert "Traceback" not in result.output


def test_diff_missing_file(scenes):
    write_png(scenes / "a.png", np.zeros((10, 10, 3)))
    assert cli("diff", "a.png", "nope.png").exit_code == 2


# ---------------------------------------------------------------------------------------
# help and version


def test_help_of_every_command():
    names = sorted(main.commands)
    assert {"render", "validate", "schema", "graph", "info", "diff"} <= set(names)
    top = cli("--help")
    assert top.exit_code == 0
    for name in names:
        assert name in top.stdout
        result = cli(name, "--help")
        assert result.exit_code == 0, name
        assert result.stdout.startswith(f"Usage: main {name}") or f" {name} " in result.stdout.splitlines()[0]
        assert "-h, --help" in result.stdout


def test_short_help_and_version():
    assert cli("render", "-h").exit_code == 0
    result = cli("--version")
    assert result.exit_code == 0
    assert result.stdout.startswith("scenerender, version ")


# ---------------------------------------------------------------------------------------
# rendering (needs GL)


@pytest.mark.gl
def test_render_png_then_keep_complete_frames(scenes):
    result = cli("render", "good.yaml", "-o", "out")
    skip_without_gl(result.exit_code, result.stderr)
    assert result.exit_code == 0, result.output
    assert frame_files(scenes / "out") == ["frame_0000.png"]
    with Image.open(scenes / "out" / "frame_0000.png") as image:
        assert image.size == (32, 24)
        pixels = np.asarray(image.convert("RGB"))
    assert pixels.std() > 0  # the box is drawn over the background
    assert "rendered 1 frame" in result.stderr

    again = cli("render", "good.yaml", "-o", "out")
    assert again.exit_code == 0
    assert "nothing to do" in again.stderr

    forced = cli("render", "good.yaml", "-o", "out", "--overwrite", "-q")
    assert forced.exit_code == 0
    assert forced.stderr == ""


@pytest.mark.gl
def test_render_frame_range_and_size(scenes):
    result = cli("render", "good.yaml", "-o", "out", "--set", "output.frames=5", "--frames", "1:3",
                 "--size", "16x12", "--samples", "1", "--format", "tga", "-q")
    skip_without_gl(result.exit_code, result.stderr)
    assert result.exit_code == 0, result.output
    assert frame_files(scenes / "out") == ["frame_0001.tga", "frame_0002.tga"]
    with Image.open(scenes / "out" / "frame_0001.tga") as image:
        assert image.size == (16, 12)


@pytest.mark.gl
def test_render_gif_end_to_end(scenes):
    result = run_module("render", "good.yaml", "-o", "out", "--format", "gif", "--set", "output.frames=3",
                        "--set", "objects[0].rotation={keys: [[0, [0, 0, 0]], [0.1, [0, 90, 0]]]}", cwd=scenes)
    skip_without_gl(result.returncode, result.stderr)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    assert frame_files(scenes / "out") == ["good.gif"]
    with Image.open(scenes / "out" / "good.gif") as image:
        assert image.size == (32, 24)
        assert image.n_frames == 3


def test_missing_egl_is_one_line_with_the_fix_and_exit_3(tmp_path, monkeypatch):
    import moderngl

    scene = tmp_path / "s.yaml"
    scene.write_text("objects:\n  - mesh: {primitive: box}\n")

    def no_egl(*args, **kwargs):
        raise Exception("libEGL.so.1: cannot open shared object file: No such file or directory")

    monkeypatch.setattr(moderngl, "create_context", no_egl)
    result = CliRunner().invoke(main, ["render", str(scene), "-o", str(tmp_path / "out" / "shots"), "-q"])
    assert result.exit_code == 3
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: cannot create an OpenGL")
    assert "libEGL.so.1" in lines[0] and "apt-get install" in lines[0] and "Traceback" not in result.output
    assert not (tmp_path / "out").exists()  # the folders the run made are taken away again
    (tmp_path / "kept").mkdir()
    again = CliRunner().invoke(main, ["render", str(scene), "-o", str(tmp_path / "kept"), "-q"])
    assert again.exit_code == 3 and (tmp_path / "kept").is_dir()  # one that was there stays


def test_llvmpipe_gets_two_threads_more_than_cores_unless_the_user_set_them(monkeypatch):
    """The context is made with LP_NUM_THREADS = cores + 2 where it is unset (Mesa reads it
    when the context is made); a user's own value is kept."""
    import moderngl

    from scenerender.gpu import gl_context as context
    from scenerender.machine import available_cores

    seen = []
    monkeypatch.setattr(moderngl, "create_context", lambda **kwargs: seen.append(os.environ.get("LP_NUM_THREADS")))
    monkeypatch.delenv("LP_NUM_THREADS", raising=False)
    context.create_context()
    monkeypatch.setenv("LP_NUM_THREADS", "1")
    context.create_context()
    assert seen == [str(available_cores() + 2), "1"]


@pytest.mark.parametrize("command", [["render", "good.yaml", "-o", ""], ["render", "", "-o", "out"],
                                     ["diff", "", "out"], ["reference", "good.yaml", "-o", ""]])
def test_an_empty_path_is_a_usage_error(scenes, command):
    result = cli(*command)
    assert result.exit_code == 2, result.output
    assert "an empty path names no file or folder" in result.output
    assert not list(scenes.glob("*.png")) and not list(scenes.glob("*.tga"))  # nothing written here


def test_a_pasted_value_does_not_fill_the_message(scenes):
    result = cli("render", "good.yaml", "-o", "out", "--set", "render.mode=" + "a" * 5000)
    assert result.exit_code == 2
    assert len(result.stderr) < 800, result.stderr
    assert "characters left out" in result.stderr and "expected one of shaded" in result.stderr


@pytest.mark.parametrize("command", ["render", "schema", "reference", "bench", "diff"])
def test_every_output_option_says_it_creates_missing_folders(command):
    """`-o /new/dir/x` makes every missing folder on the way: the help says so."""
    from scenerender.cli import MAKES_PARENTS

    assert MAKES_PARENTS in " ".join(cli(command, "--help").output.split())


def test_schema_output_makes_its_missing_folders(tmp_path):
    target = tmp_path / "new" / "dir" / "scene.schema.json"
    assert cli("schema", "-o", target).exit_code == 0
    assert target.is_file()
