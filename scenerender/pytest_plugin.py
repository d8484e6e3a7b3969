"""pytest plugin: render a scene in a test and compare every frame with stored references.

    def test_garden(scene_regression):
        scene_regression.check("scenes/garden.yaml", overrides=["render.size=[160,120]"], frames="0:3")

References live beside the test file in ``scene_references/<test name>/`` (or
``scene_references/<test name>/<renderer>/``, e.g. ``llvmpipe/``, when that folder exists).
They are written only on purpose: ``pytest --scenerender-update`` writes or rewrites them;
a test without references fails and says so. A failure names each changed frame with its
numbers and the path of an HTML report with the pictures.

The plugin is registered through the ``pytest11`` entry point when scenerender is installed.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest


def pytest_addoption(parser):
    group = parser.getgroup("scenerender", "scene rendering regression tests")
    group.addoption("--scenerender-update", action="store_true", default=False,
                    help="write or rewrite the reference frames of scene_regression tests (then commit them)")


class SceneRegression:
    """The ``scene_regression`` fixture's object; one ``check`` per scene (or name)."""

    def __init__(self, test_file: Path, test_name: str, work_dir: Path, update: bool):
        self.test_dir = test_file.parent
        self.test_name = test_name
        self.work_dir = work_dir
        self.update = update

    def check(self, scene, overrides=(), frames: str | None = None, name: str | None = None, rule=None,
              object_ids: bool = True):
        """Render ``scene`` (a path, relative to the test file's folder or the working
        directory, or a ``scenerender.Scene``) and compare its frames with the references.

        overrides: ``--set`` style strings (``"render.size=[160,120]"``); frames: "A:B";
        name: the reference folder's name (default: the test's name; give one per scene
        when a test checks several); rule: a ``scenerender.compare.DiffRule``; object_ids
        (default on): keep the frames' object ids with the references too, so changes are
        named and judged by object (a video cannot hold them, and a reference without ids
        is judged by colour alone, which the failure and the report say); False: colour alone.
        Returns the ``references.CheckResult``; fails the test on any change.
        """
        from scenerender.api import Scene, render_to
        from scenerender.run.job import WHERE_POSSIBLE
        from scenerender.run.references import check_output, has_references, reference_path

        label = _safe_name(name or self.test_name)
        output = self.work_dir / label
        options = {"frames": frames}
        if not isinstance(scene, Scene):
            scene = self._scene_path(scene)
            options["overrides"] = list(overrides)
        elif overrides:
            raise ValueError("overrides apply when a scene is loaded: pass them to scenerender.load")
        render_to(scene, output, overwrite=True, object_ids=WHERE_POSSIBLE if object_ids else False, **options)
        target, root = _only_output(output), self.test_dir / "scene_references" / label
        reference = reference_path(target, root)
        if not self.update and not has_references(reference):
            pytest.fail(f"scene {label}: no references in {reference}; run pytest "
                        "--scenerender-update to write them, look at them, and commit them", pytrace=False)
        summary_lines: list[str] = []
        result = check_output(target, root, update=self.update, echo=summary_lines.append, rule=rule)
        if not result.passed and not self.update:
            changed = [line for line in summary_lines if not line.startswith(("PASS", "report:"))]
            pytest.fail(f"scene {label}: frames differ from the references in {result.reference}\n  "
                        + "\n  ".join(changed)
                        + f"\n  report: {result.report}\n  (if the change is intended: pytest --scenerender-update)",
                        pytrace=False)
        return result

    def _scene_path(self, scene) -> Path:
        path = Path(scene)
        beside_test = self.test_dir / path
        return beside_test if not path.is_absolute() and beside_test.exists() else path


def _safe_name(text: str) -> str:
    """A test id as a folder name: test_x[case-1] -> test_x-case-1."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", text).strip("-.") or "scene"


def _only_output(folder: Path) -> Path:
    """The render output in ``folder``: the folder of frames, or its one video file."""
    from scenerender.compare.sources import VIDEO_SUFFIXES

    videos = [p for p in folder.iterdir() if p.suffix.lower() in VIDEO_SUFFIXES]
    return videos[0] if len(videos) == 1 else folder


@pytest.fixture
def scene_regression(request, tmp_path) -> SceneRegression:
    """Render scenes and compare them with references stored beside the test file."""
    return SceneRegression(Path(str(request.node.fspath)), request.node.name, tmp_path,
                           request.config.getoption("--scenerender-update"))
