"""Shared test helpers: one OpenGL context per test session, and small render helpers.

GL tests need an OpenGL 4.3 context over EGL; on a machine without a GPU that is Mesa's
llvmpipe. Without one they fail with the reason (set SCENERENDER_SKIP_GL=1 to skip them).
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "scenes"


# ---------------------------------------------------------------------------------------
# Skips a run may accept. With SCENERENDER_ALLOWED_SKIPS naming a file of reasons (CI's is
# .ci/allowed-skips), any other skip fails the run: a test skipped for a module a clean
# install lacks would otherwise pass unseen.

_skips: list[tuple[str, str]] = []


def pytest_runtest_logreport(report):
    if report.skipped and isinstance(report.longrepr, tuple):
        _skips.append((report.nodeid, str(report.longrepr[2]).removeprefix("Skipped: ")))


def _allowed_skip_reasons(path: Path) -> list[str]:
    lines = (line.split("#", 1)[0].strip() for line in path.read_text(encoding="utf-8").splitlines())
    return [line for line in lines if line]


def pytest_sessionfinish(session, exitstatus):
    listing = os.environ.get("SCENERENDER_ALLOWED_SKIPS")
    if not listing:
        return
    allowed = _allowed_skip_reasons(Path(listing))
    unexpected = [(test, reason) for test, reason in _skips
                  if not any(reason.startswith(prefix) for prefix in allowed)]
    if unexpected:
        reporter = session.config.pluginmanager.get_plugin("terminalreporter")
        reporter.write_line(f"{len(unexpected)} skip(s) not listed in {listing}:", red=True)
        for test, reason in unexpected:
            reporter.write_line(f"  {test}: {reason}")
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


@pytest.fixture(scope="session")
def gl():
    if os.environ.get("SCENERENDER_SKIP_GL"):
        pytest.skip("SCENERENDER_SKIP_GL is set")
    from scenerender.errors import EnvironmentProblem
    from scenerender.gpu.gl_context import create_context

    try:
        ctx = create_context()
    except EnvironmentProblem as exc:
        pytest.fail(f"no OpenGL context for the GL tests: {exc}")
    yield ctx
    ctx.release()


def skip_without_gl(exit_code: int, stderr: str) -> None:
    """For tests that render through the command line, where exit code 3 is any problem
    with the environment: skips a missing OpenGL context, and only where the gl fixture
    would (SCENERENDER_SKIP_GL set). Any other exit 3, ffmpeg failing say, is left to fail
    the test's own check of the exit code."""
    if exit_code == 3 and "cannot create an OpenGL" in stderr and os.environ.get("SCENERENDER_SKIP_GL"):
        pytest.skip(f"no OpenGL context here: {stderr.strip()}")


@pytest.fixture(autouse=True, scope="session")
def _private_mesh_cache(tmp_path_factory):
    """Tests (and the processes they start) neither read nor fill the user's mesh cache."""
    previous = os.environ.get("SCENERENDER_CACHE_DIR")
    os.environ["SCENERENDER_CACHE_DIR"] = str(tmp_path_factory.mktemp("mesh-cache"))
    yield
    if previous is None:
        os.environ.pop("SCENERENDER_CACHE_DIR", None)
    else:
        os.environ["SCENERENDER_CACHE_DIR"] = previous


def load(text_or_path, overrides=(), base_dir=None):
    """A LoadedScene from YAML text (paths relative to ``base_dir`` or scenes/) or a file."""
    from scenerender.scene import load_scene
    from scenerender.scene.loading import load_scene_text

    if isinstance(text_or_path, Path):
        return load_scene(text_or_path, list(overrides))
    return load_scene_text(text_or_path, base_dir or SCENES, list(overrides))


def scene(text_or_path, overrides=(), base_dir=None, warnings=None):
    """A ``scenerender.Scene`` from YAML text (paths relative to ``base_dir`` or scenes/) or
    a file; warnings go into ``warnings`` (a ``scenerender.errors.Warnings``) when given."""
    import scenerender

    options = {}
    if warnings is not None:
        options = {"strict": warnings.strict,
                   "on_warning": lambda line: warnings.items.append(line.removeprefix("warning: "))}
    if isinstance(text_or_path, Path):
        return scenerender.load(text_or_path, list(overrides), **options)
    return scenerender.Scene.from_yaml(text_or_path, base_dir or SCENES, list(overrides), **options)


def render(gl, text_or_path, overrides=(), frames=(0,), base_dir=None, warnings=None, **renderer_options):
    """Render ``frames`` of a scene on the shared context -> list of (H, W, 3) uint8."""
    import scenerender

    with scenerender.Renderer(scene(text_or_path, overrides, base_dir, warnings), gl=gl,
                              **renderer_options) as renderer:
        return [renderer.render(i).pixels for i in frames]


def render_one(gl, text_or_path, overrides=(), frame=0, **kwargs) -> np.ndarray:
    return render(gl, text_or_path, overrides, frames=(frame,), **kwargs)[0]


@pytest.fixture
def render_scene(gl):
    """render_scene(text_or_path, overrides=(), frame=0) -> (H, W, 3) uint8."""
    def _render(text_or_path, overrides=(), frame=0, **kwargs):
        return render_one(gl, text_or_path, overrides, frame, **kwargs)
    return _render


# The modules with the longest tests or xdist groups (tens of seconds each on CI's 2
# cores), longest first. Under pytest-xdist they are handed out first, so the last tests
# either worker runs are short ones and the two finish together; in collection order they
# came last and one worker waited a minute for the other.
LONGEST_FIRST = ("test_cpu_without_avx2.py", "test_perturbation.py", "test_verdict_cases.py", "test_memory.py",
                 "test_environment_light.py", "test_edge_accuracy.py", "test_tone_curve.py", "test_report_browser.py",
                 "test_pytest_plugin.py", "test_ci_guards.py")


def pytest_collection_modifyitems(config, items):
    """Tests using the GL context are marked ``gl`` so ``-m "not gl"`` leaves them out. On
    an xdist worker, the modules of LONGEST_FIRST come first (every worker orders alike)."""
    for item in items:
        if "gl" in getattr(item, "fixturenames", ()) or "render_scene" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.gl)
    if hasattr(config, "workerinput"):
        rank = {name: index for index, name in enumerate(LONGEST_FIRST)}
        items.sort(key=lambda item: rank.get(item.path.name, len(rank)))  # stable: module order kept otherwise
