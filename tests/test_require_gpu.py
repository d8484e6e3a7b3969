"""Which GL renderer a run used, and `--require-gpu`: a driver that finds no GPU falls back to a
CPU rasteriser without a word (the most reported problem of headless rendering), so a run
names its renderer in its first line of progress and in its manifest, and `--require-gpu`
(or SCENERENDER_REQUIRE_GPU=1) makes a software renderer an exit-3 error saying what to do."""
from __future__ import annotations

import json
from types import SimpleNamespace

import pytest
from click.testing import CliRunner

import scenerender
from conftest import scene as api_scene
from scenerender.cli import main
from scenerender.errors import EnvironmentProblem
from scenerender.gpu.gl_context import is_software, refuse_software, renderer_name

SCENE = "render: {size: [16, 12], samples: 1}\nobjects:\n  - mesh: {primitive: box}\n"


@pytest.fixture
def scene_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SCENERENDER_REQUIRE_GPU", raising=False)
    (tmp_path / "scene.yaml").write_text(SCENE, encoding="utf-8")
    return tmp_path / "scene.yaml"


@pytest.fixture
def on_the_cpu(gl) -> bool:
    """Whether this machine's GL renderer is a CPU rasteriser (llvmpipe in CI)."""
    return is_software(renderer_name(gl))


def cli(*args, **env):
    return CliRunner().invoke(main, [str(a) for a in args], env=env or None)


def fake_context(renderer: str):
    return SimpleNamespace(info={"GL_RENDERER": renderer})


@pytest.mark.parametrize("renderer, software", [
    ("llvmpipe (LLVM 15.0.6, 256 bits)", True), ("softpipe", True),
    ("Mesa swrast", True), ("NVIDIA GeForce RTX 4090/PCIe/SSE2", False), ("AMD Radeon RX 7900 XTX (radeonsi)", False),
    ("Mesa Intel(R) UHD Graphics 630 (CFL GT2)", False),
])
def test_software_renderers_are_told_from_gpus(renderer, software):
    assert is_software(renderer) is software
    if software:
        with pytest.raises(EnvironmentProblem, match="a GPU is required.*draws on the CPU.*--gpus all"):
            refuse_software(fake_context(renderer))
    else:
        refuse_software(fake_context(renderer))


def test_require_gpu_on_a_software_renderer_exits_3_and_writes_nothing(scene_file, on_the_cpu):
    result = cli("render", scene_file, "-o", "out/new", "--frames", "0:2", "--require-gpu")
    if not on_the_cpu:  # a GPU machine: the option changes nothing
        assert result.exit_code == 0, result.output
        return
    assert result.exit_code == 3, result.output
    assert result.stderr.startswith("error: a GPU is required, but the GL renderer is 'llvmpipe")
    assert "leave out --require-gpu" in result.stderr and "\n" not in result.stderr.rstrip("\n")
    assert not (scene_file.parent / "out").exists()


def test_the_variable_requires_a_gpu_like_the_option(scene_file, on_the_cpu):
    required = cli("render", scene_file, "-o", "out", "--frames", "0", SCENERENDER_REQUIRE_GPU="1")
    assert required.exit_code == (3 if on_the_cpu else 0), required.output
    assert cli("render", scene_file, "-o", "out", "--frames", "0", SCENERENDER_REQUIRE_GPU="0").exit_code == 0


def test_the_api_requires_a_gpu_on_request(gl, on_the_cpu, monkeypatch):
    scene = api_scene(SCENE)
    if not on_the_cpu:
        pytest.skip("the refusal needs a software renderer; tested above on fake ones")
    with pytest.raises(EnvironmentProblem, match="a GPU is required"):
        scenerender.Renderer(scene, gl=gl, require_gpu=True)
    assert gl.info["GL_RENDERER"]  # the caller's context is left alone
    monkeypatch.setenv("SCENERENDER_REQUIRE_GPU", "1")
    with pytest.raises(EnvironmentProblem):
        scenerender.Renderer(scene, gl=gl)
    with scenerender.Renderer(scene, gl=gl, require_gpu=False) as renderer:  # the argument wins
        assert renderer.gl_renderer == renderer_name(gl)


@pytest.mark.parametrize("frames", ["0:3", "0"])
def test_the_first_line_of_progress_names_the_renderer_and_the_manifest_records_it(scene_file, gl, frames):
    name = renderer_name(gl)
    where = "software, on the CPU" if is_software(name) else "on the GPU"
    result = cli("render", scene_file, "-o", "out", "--frames", frames)
    assert result.exit_code == 0, result.output
    assert result.stderr.splitlines()[0] == f"GL renderer: {name} ({where})"
    manifest = json.loads((scene_file.parent / "out" / ".scenerender.json").read_text(encoding="utf-8"))
    assert manifest["gl"]["renderer"] == name and manifest["gl"]["software"] is is_software(name)


def test_quiet_runs_leave_the_renderer_line_out(scene_file):
    result = cli("render", scene_file, "-o", "out", "--frames", "0:2", "-q")
    assert result.exit_code == 0 and "GL renderer" not in result.stderr
