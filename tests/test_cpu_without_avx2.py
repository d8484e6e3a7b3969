"""Rendering on CPUs without AVX2. There llvmpipe picks 4-wide (128-bit) vectors or, with
AVX, 8-wide ones; an emulated CPU of each kind (qemu's user-mode emulator, with the CPU
models Nehalem: SSE4.2, no AVX, and SandyBridge: AVX, no AVX2) renders one frame of every
example scene (Nehalem) and of primitives (SandyBridge), each matching the native render
under the diff rule. Forcing 128-bit vectors on a CPU that
has AVX2 corrupts Mesa 22's heap, so scenerender lifts that setting."""
from __future__ import annotations

import json
import os
import platform
import shutil
import subprocess
import sys

import pytest
from click.testing import CliRunner

from conftest import ROOT
from scenerender.cli import main
from scenerender.compare import compare_paths
from scenerender.gpu import gl_context as context

QEMU = shutil.which("qemu-x86_64")


CASES = [*((scene, "Nehalem", "128 bits") for scene in ("showcase.yaml", "garden.yaml", "island.yaml",
                                                        "foggy_road.yaml", "viewer_modes.yaml", "primitives.yaml")),
         ("primitives.yaml", "SandyBridge", "256 bits")]

# Run under qemu, once per CPU model: the CLI command of _args for each scene named on the
# command line (SCENE OUT pairs), one after another in this one emulated Python, each exit
# code and output written to the JSON file named first. Python and its imports start once
# per CPU model, not once per scene: under emulation that start-up is seconds of each render.
EMULATED_RENDERS = """
import json, sys
from click.testing import CliRunner
from scenerender.cli import main
results, pairs = {}, sys.argv[2:]
for scene, out in zip(pairs[0::2], pairs[1::2]):
    run = CliRunner().invoke(main, ["render", scene, "-o", out, *%r])
    results[scene] = [run.exit_code, run.output[-2000:] + repr(run.exception or "")]
with open(sys.argv[1], "w") as file:
    json.dump(results, file)
"""
OPTIONS = ["--frames", "0:1", "--size", "160x120", "--format", "png"]


def _render(out, scene):
    """The CLI's render of one frame on this CPU, in this process."""
    run = CliRunner().invoke(main, ["render", str(ROOT / "scenes" / scene), "-o", str(out), *OPTIONS])
    assert run.exit_code == 0, run.output[-2000:]


@pytest.fixture(scope="module")
def emulated(tmp_path_factory):
    """emulated(scene, cpu) -> the folder of that scene's frame rendered on the emulated
    ``cpu`` (every scene of CASES for that CPU rendered in one qemu process, on first use)."""
    done = {}

    def folder(scene, cpu):
        if cpu not in done:
            root = tmp_path_factory.mktemp(f"emulated-{cpu}")
            scenes = [name for name, model, _ in CASES if model == cpu]
            pairs = [str(arg) for name in scenes for arg in (ROOT / "scenes" / name, root / name)]
            env = dict(os.environ)
            # an OpenBLAS core type named for the real CPU would run instructions the emulated one lacks
            env.pop("OPENBLAS_CORETYPE", None)
            env.pop("LP_NATIVE_VECTOR_WIDTH", None)
            results = root / "results.json"
            run = subprocess.run([QEMU, "-cpu", cpu, sys.executable, "-c", EMULATED_RENDERS % (OPTIONS,),
                                  str(results), *pairs], env=env, capture_output=True, text=True, timeout=900, cwd=ROOT)
            done[cpu] = (root, run, json.loads(results.read_text()) if results.is_file() else {})
        root, run, results = done[cpu]
        key = str(ROOT / "scenes" / scene)
        assert run.returncode == 0 and key in results, run.stderr[-2000:]
        code, output = results[key]
        assert code == 0, output
        return root / scene

    return folder


@pytest.mark.skipif(platform.machine() != "x86_64", reason="not an x86-64 machine: no x86 CPU to emulate")
@pytest.mark.skipif(QEMU is None, reason="qemu-x86_64 is not installed (apt-get install qemu-user)")
@pytest.mark.gl
@pytest.mark.slow
@pytest.mark.xdist_group("cpu_without_avx2")  # one worker: each emulated CPU's process renders its scenes once
@pytest.mark.parametrize("scene, cpu, width", CASES)
def test_a_cpu_without_avx2_renders_what_this_one_does(gl, tmp_path, emulated, scene, cpu, width):
    _render(tmp_path / "native", scene)
    out = emulated(scene, cpu)
    manifest = (out / ".scenerender.json").read_text()
    assert width in manifest  # the emulated CPU really gave llvmpipe that vector width
    result = compare_paths(tmp_path / "native", out)
    assert result.passed, result.summary_lines()


def test_forced_narrow_vectors_are_lifted_on_a_cpu_with_avx2(tmp_path, monkeypatch, capsys):
    with_avx2 = tmp_path / "avx2"
    with_avx2.write_text("processor : 0\nflags : fpu sse4_2 avx avx2 fma\n")
    without = tmp_path / "sse"
    without.write_text("processor : 0\nflags : fpu sse4_2\n")
    monkeypatch.setenv("LP_NATIVE_VECTOR_WIDTH", "128")
    assert not context.lift_forced_narrow_vectors(without)
    assert os.environ["LP_NATIVE_VECTOR_WIDTH"] == "128"  # left alone where llvmpipe would pick it anyway
    assert context.lift_forced_narrow_vectors(with_avx2)
    assert "LP_NATIVE_VECTOR_WIDTH" not in os.environ
    assert "LP_NATIVE_VECTOR_WIDTH=128 ignored" in capsys.readouterr().err
    monkeypatch.setenv("LP_NATIVE_VECTOR_WIDTH", "256")
    assert not context.lift_forced_narrow_vectors(with_avx2)


@pytest.mark.gl
def test_a_forced_128_bit_width_on_this_cpu_renders(tmp_path, monkeypatch):
    """The plane that crashed: with the setting lifted it renders (on a CPU without AVX2 the
    setting is llvmpipe's own choice and is kept)."""
    scene = tmp_path / "plane.yaml"
    scene.write_text("scenerender: 1\nrender: {size: [64, 48], samples: 1}\n"
                     "lights:\n  - {type: directional, direction: [0, -1, -0.3]}\n"
                     "objects:\n  - mesh: {primitive: plane, size: 4}\n")
    env = dict(os.environ, LP_NATIVE_VECTOR_WIDTH="128")
    run = subprocess.run([sys.executable, "-m", "scenerender", "render", str(scene), "-o", str(tmp_path / "out")],
                         env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr[-2000:]
