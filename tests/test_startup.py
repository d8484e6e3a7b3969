"""A one-frame render starts fast: its process imports only what rendering needs.

A CI job that renders many short scenes pays the start-up of every process, and most of a
one-frame render is start-up (docs/performance.md, "Start-up"). Reading a GLB must not
import trimesh or SciPy (tests/test_gltf_geometry.py); here the whole command, a glTF scene
and the smallest scene, must not import any of the modules below, which only other
commands or options use.
"""
from __future__ import annotations

import gc
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from click.testing import CliRunner

from conftest import skip_without_gl
from scenerender.cli import (COMMAND_GC_THRESHOLD, FULL_EXIT_VARIABLE, OPENBLAS_THREADS_VARIABLE,
                             PYDANTIC_PLUGINS_VARIABLE, main)
from scenerender.scene import load_scene
from scenerender.version import __version__

ROOT = Path(__file__).resolve().parent.parent
PROPS = ROOT / "scenes" / "assets" / "models" / "pbr_props.glb"

NOT_ON_THE_RENDER_PATH = (
    "trimesh", "scipy",                     # meshes NumPy cannot read (mesh/loader.py)
    "rich", "matplotlib", "skimage",        # not dependencies of a render
    "OpenEXR",                              # --format exr, .exr textures and environments
    "imageio", "imageio_ffmpeg",            # videos
    "dask", "distributed", "multiprocessing",  # --workers, --scheduler (run/workers.py)
    "html",                                 # the diff report
    "PIL",                                  # images: textures, JPG and TGA frames, resuming them
    "scenerender.run.references",           # --check
    "scenerender.run.workers",
    "scenerender.compare.metrics",          # image comparison: --check and `diff`
    "scenerender.compare.report",
    "scenerender.raytrace",                 # `reference`
    "scenerender.tools",                    # `bench`
    # passes of features the scenes here lack (rendering/pipeline.py imports them when added)
    "scenerender.rendering.passes.ambient_occlusion", "scenerender.rendering.passes.bloom",
    "scenerender.rendering.passes.depth_of_field", "scenerender.rendering.passes.motion_blur",
    "scenerender.rendering.passes.views", "scenerender.rendering.passes.environment",
    "scenerender.rendering.passes.shadow",  # no light of these scenes casts shadows
    "scenerender.rendering.passes.object_ids",  # --object-ids (and --check)
    "scenerender.mesh.obj", "scenerender.mesh.mtl",  # OBJ files (mesh/loader.py)
)

# Runs the command in this process, then prints every module it imported.
RUN_AND_LIST = textwrap.dedent("""
    import sys
    from scenerender.cli import main
    try:
        main(sys.argv[1:])
    except SystemExit as exit:
        if exit.code:
            raise
    print(" ".join(sorted(sys.modules)))
""")


def modules_of_one_frame(scene: Path, tmp_path: Path, *options: str) -> set[str]:
    command = [sys.executable, "-c", RUN_AND_LIST, "render", str(scene), "-o", str(tmp_path / "out"), "-q",
               "--size", "160x120", "--frames", "0:1", *options]
    result = subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
    skip_without_gl(result.returncode, result.stderr)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "out" / "frame_0000.png").is_file()
    return set(result.stdout.split())


def imported_needlessly(modules: set[str]) -> list[str]:
    return [name for name in NOT_ON_THE_RENDER_PATH
            if name in modules or any(module.startswith(name + ".") for module in modules)]


@pytest.mark.parametrize("scene", ["minimal", "glb"])
def test_a_one_frame_render_imports_only_what_it_needs(scene, tmp_path):
    if scene == "glb":  # textured: Pillow decodes its images
        path = tmp_path / "glb.yaml"
        path.write_text(f"render: {{shading: pbr}}\nobjects:\n  - mesh: {PROPS.as_posix()}\n", encoding="utf-8")
        options, needed = ("--asset-root", str(PROPS.parent)), ["PIL"]
    else:
        path, options, needed = ROOT / "benchmarks" / "scenes" / "minimal.yaml", (), []
    assert imported_needlessly(modules_of_one_frame(path, tmp_path, *options)) == needed


def test_the_check_finds_what_was_imported():
    assert imported_needlessly({"numpy", "multiprocessing.pool", "scenerender.raytrace.rays"}) == [
        "multiprocessing", "scenerender.raytrace"]
    assert imported_needlessly({"numpy", "htmlmin", "scenerender.compare.rule"}) == []


def test_a_command_in_a_callers_process_leaves_its_collector_settings(monkeypatch):
    # a command collects garbage less often while it runs (cli.COMMAND_GC_THRESHOLD), and a
    # caller that runs it in its own process (CliRunner, here) gets its settings back
    seen = []
    monkeypatch.setattr("scenerender.run.model_scene.load_scene", _recording_threshold(seen), raising=True)
    before = gc.get_threshold()
    result = CliRunner().invoke(main, ["validate", str(ROOT / "benchmarks" / "scenes" / "minimal.yaml")])
    assert result.exit_code == 0, result.output
    assert seen == [COMMAND_GC_THRESHOLD]
    assert gc.get_threshold() == before != COMMAND_GC_THRESHOLD


def _recording_threshold(seen):
    def load_and_record(*args, **kwargs):
        seen.append(gc.get_threshold())
        return load_scene(*args, **kwargs)

    return load_and_record


BUILT_AT_IMPORT = textwrap.dedent("""
    from scenerender.scene.model.materials import MaterialSpec
    from scenerender.scene.model.objects import ObjectSpec, Range3, ScaleRange
    from scenerender.scene.model.output import OutputSettings
    from scenerender.scene.model.render import RenderSpec, ShadowSettings
    from scenerender.scene.model.scene import SceneSpec
    models = (SceneSpec, RenderSpec, ShadowSettings, OutputSettings, ObjectSpec, Range3, ScaleRange, MaterialSpec)
    print(" ".join(model.__name__ for model in models if model.__pydantic_complete__))
""")


def test_importing_the_scene_model_builds_no_validator():
    # each class's validator would compile the sections inside it again; loading a scene
    # builds SceneSpec's alone (a default made as an instance at import builds its class's)
    result = subprocess.run([sys.executable, "-c", BUILT_AT_IMPORT], capture_output=True, text=True, check=True,
                            cwd=ROOT)
    assert result.stdout.split() == []


# The process entry point: the command runs, exit handlers run, and the interpreter is not
# torn down (cli.entry_point). A module global's __del__ runs only at a full teardown.
ENTRY_POINT = textwrap.dedent("""
    import atexit
    import sys
    import threading
    import time

    class Teardown:
        def __del__(self):
            sys.stderr.write("torn down\\n")

    kept = Teardown()
    atexit.register(lambda: sys.stderr.write("exit handler ran\\n"))
    if "--with-thread" in sys.argv:
        sys.argv.remove("--with-thread")
        threading.Thread(target=lambda: (time.sleep(0.5), sys.stderr.write("thread finished\\n"))).start()
    from scenerender.cli import entry_point
    sys.argv[0] = "scenerender"
    entry_point()
""")


def run_entry_point(*args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", ENTRY_POINT, *args], capture_output=True, text=True, cwd=ROOT,
                          env=env)


def test_the_entry_point_exits_without_tearing_the_interpreter_down(tmp_path, monkeypatch):
    monkeypatch.delenv(FULL_EXIT_VARIABLE, raising=False)
    minimal = str(ROOT / "benchmarks" / "scenes" / "minimal.yaml")
    quick = run_entry_point("validate", minimal)
    assert quick.returncode == 0, quick.stderr
    assert quick.stderr.splitlines() == ["exit handler ran"]
    full = run_entry_point("validate", minimal, env={**os.environ, FULL_EXIT_VARIABLE: "1"})
    assert full.returncode == 0, full.stderr
    assert full.stderr.splitlines() == ["exit handler ran", "torn down"]


def test_the_quick_exit_keeps_exit_codes_and_output(tmp_path, monkeypatch):
    monkeypatch.delenv(FULL_EXIT_VARIABLE, raising=False)
    bad = tmp_path / "bad.yaml"
    bad.write_text("objects: [{mesh: {primitive: nothing}}]\n", encoding="utf-8")
    result = run_entry_point("validate", str(bad))
    assert result.returncode == 2
    assert "nothing" in result.stderr and "torn down" not in result.stderr
    version = run_entry_point("--version")
    assert version.returncode == 0 and version.stdout.strip().endswith(__version__)


def test_a_thread_still_running_is_waited_for(monkeypatch):
    monkeypatch.delenv(FULL_EXIT_VARIABLE, raising=False)
    result = run_entry_point("--version", "--with-thread")
    assert result.returncode == 0, result.stderr
    assert "thread finished" in result.stderr.splitlines()


def test_a_one_frame_render_through_the_entry_point_writes_its_frame(tmp_path, monkeypatch):
    monkeypatch.delenv(FULL_EXIT_VARIABLE, raising=False)
    out = tmp_path / "out"
    result = run_entry_point("render", str(ROOT / "benchmarks" / "scenes" / "minimal.yaml"), "-o", str(out), "-q",
                             "--size", "160x120", "--frames", "0:1")
    skip_without_gl(result.returncode, result.stderr)
    assert result.returncode == 0, result.stderr
    assert "torn down" not in result.stderr
    assert (out / "frame_0000.png").stat().st_size > 0


# What the entry point leaves to NumPy: the command prints OpenBLAS's thread setting as
# the process saw it, and whether NumPy was loaded before the entry point set it.
BLAS_SETTING = textwrap.dedent("""
    import atexit
    import os
    import sys

    from scenerender.cli import entry_point

    loaded_early = "numpy" in sys.modules
    atexit.register(lambda: print(os.environ.get("OPENBLAS_NUM_THREADS"), loaded_early, "numpy" in sys.modules))
    sys.argv[0] = "scenerender"
    entry_point()
""")


def printed_at_exit(script: str, variable: str, given: str | None) -> list[str]:
    """The words ``script`` (one of the entry point's runs above) prints as its process
    ends, run with the environment ``variable`` unset (``given`` None) or set to ``given``."""
    env = {key: value for key, value in os.environ.items() if key != variable}
    if given is not None:
        env[variable] = given
    result = subprocess.run([sys.executable, "-c", script, "validate",
                             str(ROOT / "benchmarks" / "scenes" / "minimal.yaml")],
                            capture_output=True, text=True, cwd=ROOT, env=env)
    assert result.returncode == 0, result.stderr
    return result.stdout.split()


@pytest.mark.parametrize("given, expected", [(None, "1"), ("3", "3")])
def test_the_entry_point_starts_openblas_with_one_thread_unless_told(given, expected):
    assert printed_at_exit(BLAS_SETTING, OPENBLAS_THREADS_VARIABLE, given)[-3:] == [expected, "False", "True"]


PLUGIN_SETTING = textwrap.dedent("""
    import atexit
    import importlib.metadata
    import os
    import sys

    from scenerender.cli import entry_point

    scans = []  # pydantic's plugin search walks importlib.metadata.distributions()
    every_distribution = importlib.metadata.distributions
    importlib.metadata.distributions = lambda *a, **k: scans.append(1) or every_distribution(*a, **k)
    atexit.register(lambda: print(os.environ.get("PYDANTIC_DISABLE_PLUGINS"), bool(scans)))
    sys.argv[0] = "scenerender"
    entry_point()
""")


@pytest.mark.parametrize("given, expected", [(None, ["1", "False"]), ("", ["True"])])
def test_the_entry_point_skips_pydantic_s_plugin_search_unless_told(given, expected):
    """pydantic's search of every package's entry points for plugins, as the scene model's
    validator is built, is skipped, unless the user set PYDANTIC_DISABLE_PLUGINS (here to
    the empty string: plugins on, and pydantic looked)."""
    assert printed_at_exit(PLUGIN_SETTING, PYDANTIC_PLUGINS_VARIABLE, given)[-len(expected):] == expected


def test_the_egl_context_names_its_libraries_and_falls_back_to_glcontexts_search(monkeypatch):
    # naming libGL and libEGL saves glcontext two `ldconfig -p` runs; where those names do
    # not load, glcontext's own search (ctypes.util.find_library) gets its turn
    import moderngl

    from scenerender.gpu import gl_context

    monkeypatch.setattr(gl_context.sys, "platform", "linux")
    monkeypatch.delenv("SCENERENDER_GL_BACKEND", raising=False)
    calls = []

    def first_name_fails(**kwargs):
        calls.append(sorted(k for k in kwargs if k.startswith("lib")))
        if "libegl" in kwargs:
            raise Exception("libEGL.so.1: cannot open shared object file")
        return "context"

    monkeypatch.setattr(moderngl, "create_context", first_name_fails)
    assert gl_context.create_context() == "context"
    assert calls == [["libegl", "libgl"], []]
    calls.clear()
    monkeypatch.setattr(moderngl, "create_context", lambda **kwargs: calls.append(kwargs) or "context")
    gl_context.create_context()
    assert [call.get("libegl") for call in calls] == ["libEGL.so.1"]


BUILT_BY_A_SCENE = textwrap.dedent("""
    import sys
    from scenerender.scene.loading import load_scene_text
    from scenerender.scene.model import lights, meshes
    load_scene_text("lights: [{type: directional}]\\nobjects: [{mesh: {primitive: box}}]\\n", ".")
    models = (lights.DirectionalLight, lights.PointLight, lights.EnvironmentLight, meshes.BoxPrimitive,
              meshes.SpherePrimitive)
    print(" ".join(model.__name__ for model in models if model.__pydantic_complete__))
""")


def test_a_scene_builds_the_validators_of_the_light_and_primitive_types_it_uses_alone():
    # each member of a union chosen by `type:` or `primitive:` is validated by its own
    # validator, built when a scene first uses it (scene/model/unions.py)
    result = subprocess.run([sys.executable, "-c", BUILT_BY_A_SCENE], capture_output=True, text=True, check=True,
                            cwd=ROOT)
    assert result.stdout.split() == ["DirectionalLight", "BoxPrimitive"]


def test_collections_pause_until_started_and_end_as_they_were(monkeypatch):
    from scenerender.run import collection

    monkeypatch.setattr(collection, "_paused", False)
    monkeypatch.setattr(collection, "_froze", False)
    assert gc.isenabled() and gc.get_freeze_count() == 0
    try:
        collection.pause_until_started()
        assert not gc.isenabled()
        collection.startup_done()
        assert gc.isenabled() and gc.get_freeze_count() > 0  # start-up's objects are not walked again
        collection.end_pause()
        assert gc.isenabled() and gc.get_freeze_count() == 0
        gc.disable()  # a caller's own choice stands
        collection.pause_until_started()
        collection.startup_done()
        collection.end_pause()
        assert not gc.isenabled()
    finally:
        gc.unfreeze()
        gc.enable()


def test_a_render_collects_nothing_until_its_first_frame_and_leaves_the_caller_as_it_was(tmp_path, monkeypatch):
    from scenerender.run import loop, session

    seen = {}
    load = session.load

    def load_and_record(*args, **kwargs):
        seen["loading"] = gc.isenabled()
        return load(*args, **kwargs)

    class Recording:
        def __init__(self, renderer):
            self.renderer = renderer

        def render(self, index):
            seen.setdefault("frames", []).append(gc.isenabled())
            return self.renderer.render(index)

        def take_notes(self):
            return self.renderer.take_notes()

    render_into = loop.render_into
    monkeypatch.setattr("scenerender.run.job.load", load_and_record)
    monkeypatch.setattr("scenerender.run.job.render_into",
                        lambda renderer, *args, **kwargs: render_into(Recording(renderer), *args, **kwargs))
    result = CliRunner().invoke(main, ["render", str(ROOT / "benchmarks" / "scenes" / "minimal.yaml"), "-o",
                                       str(tmp_path / "out"), "-q", "--size", "32x24", "--set", "output.frames=3"])
    skip_without_gl(result.exit_code, result.output)
    assert result.exit_code == 0, result.output
    assert seen == {"loading": False, "frames": [False, True, True]}
    assert gc.isenabled() and gc.get_freeze_count() == 0
