"""The wheel carries the GLSL sources inside the package, and the installed layout finds them."""
from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    pytest.importorskip("hatchling")
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run([sys.executable, "-m", "pip", "wheel", str(ROOT), "--no-deps", "--no-build-isolation",
                    "-q", "-w", str(out)], check=True, capture_output=True, timeout=300)
    return next(out.glob("scenerender-*.whl"))


def test_wheel_contains_every_shader(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    sources = sorted(p.relative_to(ROOT / "shaders").as_posix() for p in (ROOT / "shaders").rglob("*")
                     if p.is_file())
    assert sources, "no shaders in the repository?"
    for source in sources:
        assert f"scenerender/shaders/{source}" in names


def test_installed_layout_finds_the_packaged_shaders(wheel, tmp_path):
    zipfile.ZipFile(wheel).extractall(tmp_path)
    probe = ("import scenerender.gpu.shaders as s, pathlib; d = s.shader_dir(); "
             "print(d); assert (d / 'mesh' / 'forward.frag').is_file(); print(len(s.assemble('mesh/forward.frag', {})))")
    run = subprocess.run([sys.executable, "-c", probe], cwd=tmp_path, capture_output=True, text=True,
                         env={"PYTHONPATH": str(tmp_path), "PATH": ""}, timeout=60)
    assert run.returncode == 0, run.stderr
    assert str(tmp_path / "scenerender" / "shaders") in run.stdout


def test_the_version_is_the_one_the_package_is_built_with():
    """The manifest, the mesh cache and diff record scenerender.version; pip reads
    pyproject.toml. They must say the same."""
    import re

    from scenerender.version import __version__

    pyproject = (Path(__file__).resolve().parent.parent / "pyproject.toml").read_text(encoding="utf-8")
    assert re.search(r'^version = "([^"]+)"', pyproject, re.M).group(1) == __version__


def test_wheel_carries_the_preview_page_and_the_installed_layout_serves_it(wheel, tmp_path):
    """The page is real files under scenerender/preview/static/, read through the package."""
    names = set(zipfile.ZipFile(wheel).namelist())
    page = sorted(p.name for p in (ROOT / "scenerender" / "preview" / "static").iterdir())
    assert page == ["index.html", "preview.css", "preview.js"]
    assert {f"scenerender/preview/static/{name}" for name in page} <= names
    pytest.importorskip("starlette")
    zipfile.ZipFile(wheel).extractall(tmp_path)
    probe = "from scenerender.preview.server import static_files; print(sorted(static_files()))"
    run = subprocess.run([sys.executable, "-c", probe], cwd=tmp_path, capture_output=True, text=True,
                         env={"PYTHONPATH": str(tmp_path), "PATH": ""}, timeout=60)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == str(page)
