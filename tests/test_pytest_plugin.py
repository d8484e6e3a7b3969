"""The scene_regression fixture, used by a test file inside a pytester run: a first run
without references fails, --scenerender-update writes them, a match passes, a change fails
naming the frame, its numbers and the report."""
from __future__ import annotations

import os

import pytest

from conftest import ROOT

pytest_plugins = ["pytester"]
pytestmark = pytest.mark.gl

SCENE = """\
render: {size: [32, 24], samples: 1}
output: {frames: 2}
objects:
  - mesh: {primitive: sphere}
    material: {diffuse: [0.8, 0.2, 0.2]}
"""

TEST_FILE = """\
def test_ball(scene_regression):
    scene_regression.check("ball.yaml")
"""


@pytest.fixture
def suite(pytester, monkeypatch):
    # the subprocess imports scenerender (and the plugin) from this checkout, not from
    # wherever the package is installed
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    pytester.makefile(".yaml", ball=SCENE)
    pytester.makepyfile(test_scene=TEST_FILE)
    return pytester


def run(suite, *args):
    # a subprocess: the plugin makes its own GL context, apart from this session's
    return suite.runpytest_subprocess("-p", "no:cacheprovider", *args)


def test_first_run_without_references_fails_and_says_how_to_create_them(suite):
    result = run(suite)
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*no references*--scenerender-update*"])
    assert not (suite.path / "scene_references").exists()  # nothing written silently


def test_update_writes_references_then_the_test_passes(suite):
    run(suite, "--scenerender-update").assert_outcomes(passed=1)
    references = suite.path / "scene_references" / "test_ball"
    assert sorted(p.name for p in references.glob("*.png")) == ["frame_0000.png", "frame_0001.png"]
    run(suite).assert_outcomes(passed=1)


def test_a_change_fails_naming_frame_numbers_and_report(suite):
    run(suite, "--scenerender-update").assert_outcomes(passed=1)
    suite.makefile(".yaml", ball=SCENE.replace("0.8, 0.2, 0.2", "0.2, 0.2, 0.8"))
    result = run(suite)
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*scene test_ball: frames differ*", "*CHANGED frame_0000.png: *mean*",
                                 "*report: *report.html*"])


def test_object_ids_are_kept_by_default_with_the_references_and_name_a_change(suite):
    two = SCENE + """\
  - name: box1  # a named object keeps its name when it moves (an unnamed one is named by its place)
    mesh: {primitive: box, size: [0.5, 0.5, 0.5]}
    position: [1.2, 0, 0]
    material: {diffuse: [0.2, 0.8, 0.2]}
"""
    suite.makefile(".yaml", ball=two)
    run(suite, "--scenerender-update").assert_outcomes(passed=1)  # check("ball.yaml"): no flag
    kept = suite.path / "scene_references" / "test_ball" / ".object_ids"
    assert sorted(p.name for p in kept.iterdir()) == ["behind", "frame_0000.png", "frame_0001.png", "objects.json"]
    run(suite).assert_outcomes(passed=1)
    suite.makefile(".yaml", ball=two.replace("position: [1.2, 0, 0]", "position: [1.2, 0.3, 0]"))
    result = run(suite)
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*CHANGED frame_0000.png: *box1 moved*by object:*box1: *"])


def test_object_ids_false_judges_by_colour_alone_and_says_so(suite):
    suite.makepyfile(test_scene="""\
def test_ball(scene_regression):
    scene_regression.check("ball.yaml", object_ids=False)
""")
    run(suite, "--scenerender-update").assert_outcomes(passed=1)
    assert not (suite.path / "scene_references" / "test_ball" / ".object_ids").exists()
    suite.makefile(".yaml", ball=SCENE.replace("0.8, 0.2, 0.2", "0.2, 0.2, 0.8"))
    result = run(suite)
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*judged by colour alone*"])
