"""`render --check REF_DIR` and `--update-references`: references per GL renderer, written
only on purpose, compared after every render."""
from __future__ import annotations

import shutil

import pytest
from click.testing import CliRunner

from scenerender.cli import main
from scenerender.run.references import renderer_key

SCENE = """\
render: {size: [32, 24], samples: 1}
output: {frames: 2}
objects:
  - mesh: {primitive: box}
    material: {diffuse: [0.8, 0.2, 0.2]}
"""


@pytest.mark.parametrize("text, key", [
    ("llvmpipe (LLVM 15.0.6, 256 bits)", "llvmpipe"),
    ("NVIDIA H100 80GB HBM3/PCIe/SSE2", "nvidia"),
    ("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.7, DRM 3.54)", "amd"),
    ("Mesa Intel(R) UHD Graphics 630 (CFL GT2)", "intel"),
    ("Apple M2", "apple"),
    ("Some Future GPU", "some"),
    (None, "unknown"),
])
def test_renderer_key(text, key):
    assert renderer_key(text) == key


@pytest.fixture
def project(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "scene.yaml").write_text(SCENE)
    return tmp_path


def render(*args):
    return CliRunner().invoke(main, ["render", "scene.yaml", "-o", "out", *args])


def recolour(project):
    (project / "scene.yaml").write_text(SCENE.replace("0.8, 0.2, 0.2", "0.2, 0.2, 0.8"))


pytestmark = pytest.mark.gl


def test_check_without_references_is_an_error_not_a_pass(project):
    result = render("--check", "ref")
    assert result.exit_code == 2
    assert "no references" in result.stderr and "--update-references" in result.stderr


def test_update_then_check_passes_then_a_change_fails_with_a_report(project):
    created = render("--check", "ref", "--update-references")
    assert created.exit_code == 0, created.output
    assert "2 added" in created.stderr
    assert sorted(p.name for p in (project / "ref").glob("*.png")) == ["frame_0000.png", "frame_0001.png"]
    assert (project / "ref" / ".scenerender.json").is_file()  # provenance travels with them

    same = render("--check", "ref")
    assert same.exit_code == 0, same.output
    assert "PASS" in same.stderr

    recolour(project)
    changed = render("--check", "ref")
    assert changed.exit_code == 1
    assert "frame_0000.png" in changed.stderr and "FAIL" in changed.stderr
    report = project / "out" / "report.html"
    assert report.is_file() and "data:image/png;base64" in report.read_text()

    updated = render("--check", "ref", "--update-references")
    assert updated.exit_code == 0
    assert "2 changed" in updated.stderr
    assert render("--check", "ref").exit_code == 0


def test_references_for_this_renderer_win_over_the_fallback(project):
    assert render("--check", "ref", "--update-references").exit_code == 0
    shutil.copytree(project / "ref", project / "ref" / "llvmpipe")
    recolour(project)
    render("--check", "ref/llvmpipe", "--update-references")  # the llvmpipe set now holds the new colour
    result = render("--check", "ref")
    assert result.exit_code == 0, result.output  # compared with ref/llvmpipe/, not ref/


def test_update_removes_references_the_output_no_longer_has(project):
    assert render("--check", "ref", "--update-references").exit_code == 0
    (project / "ref" / "frame_0007.png").write_bytes((project / "ref" / "frame_0000.png").read_bytes())
    assert render("--check", "ref").exit_code == 1  # a frame missing from the output is a failure
    result = render("--check", "ref", "--update-references")
    assert "1 removed" in result.stderr
    assert not (project / "ref" / "frame_0007.png").exists()


def test_update_references_needs_check(project):
    result = render("--update-references")
    assert result.exit_code == 2
    assert "--check" in result.output


@pytest.mark.parametrize("check", ["out", "out/", "./out/../out"])
@pytest.mark.parametrize("update", [False, True])
def test_the_output_is_never_its_own_reference(project, check, update):
    """Compared with itself a render always passes (and an update finds "no change"), so
    -o and --check naming one folder is refused before anything is rendered over it."""
    assert render().exit_code == 0
    before = {p.name: p.read_bytes() for p in (project / "out").iterdir()}
    recolour(project)  # the next render would change every frame
    result = render("--check", check, *(["--update-references"] if update else []))
    assert result.exit_code == 2, result.output
    line, = result.stderr.splitlines()
    assert line.startswith("error: --check: out is where this render writes (-o)")
    assert "-o out/ --check ref/" in line
    assert {p.name: p.read_bytes() for p in (project / "out").iterdir()} == before


def test_a_video_is_never_its_own_reference(project):
    result = CliRunner().invoke(main, ["render", "scene.yaml", "-o", "out/clip.gif", "--check", "out"])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: --check: out/clip.gif is where this render writes (-o)")


def test_the_renderers_own_folder_is_never_the_output(project):
    """-o ref/llvmpipe --check ref compares ref/llvmpipe with itself once it exists."""
    from scenerender.run.references import recorded_renderer

    assert render().exit_code == 0
    key = renderer_key(recorded_renderer(project / "out"))
    result = CliRunner().invoke(main, ["render", "scene.yaml", "-o", f"ref/{key}", "--check", "ref"])
    assert result.exit_code == 2, result.output
    assert f"ref/{key} is where this render writes (-o)" in result.stderr


def test_references_that_cannot_be_written_name_check(project):
    (project / "afile").write_text("mine")
    result = render("--check", "afile/ref", "--update-references", "-q")
    assert result.exit_code == 2, result.output
    line, = result.stderr.splitlines()
    assert line == ("error: afile/ref: cannot write: not a directory (a file stands where a folder is needed; "
                    "write elsewhere with --check)")
