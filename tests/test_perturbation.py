"""The perturbation corpus (scenerender.tools.perturbation): under DEFAULT_RULE, with the
object ids every render keeps, every noise case passes and every change fails (KNOWN_MISSES
is empty); the rule before the shift test (the neighbourhood ranges alone) passed the thin
and small changes the shift test now catches, and the colours alone pass the five the object
ids catch. Each scene's base is rendered once per module (160x120 for the example scenes,
320x240 for the edits of primitives and the detail scene)."""
from __future__ import annotations

import subprocess
import sys

import pytest

from conftest import ROOT
from scenerender.compare import DEFAULT_RULE, compare_paths
from scenerender.compare.metrics import measure, shift_residual, worst_window_bias
from scenerender.tools import perturbation as suite

# One worker runs the whole module under `make test` (pytest-xdist's --dist loadgroup): its
# scores fixture renders and scores the corpus once, the slowest setup in the suite, and
# split over two workers each of them made it.
pytestmark = pytest.mark.xdist_group("perturbation")


@pytest.fixture(scope="module")
def scores(gl):
    # FLIP is left out: the rule does not use it, and it is the slowest metric
    return {(s.scene, s.case): s for s in suite.run_suite(suite.api_render_fn(gl), with_flip=False)}


CASE_IDS = [(case.name, name) for case in suite.CASES for name in (*suite.NOISE, *case.changes())]


@pytest.mark.parametrize("scene,case", CASE_IDS, ids=[f"{s}:{c}" for s, c in CASE_IDS])
def test_default_rule_judges(scores, scene, case):
    score = scores[(scene, case)]
    failures = score.failures(DEFAULT_RULE)
    if score.noise:
        assert not failures, f"{scene}: noise '{case}' fails the default rule: {failures}"
    elif (scene, case) not in suite.KNOWN_MISSES:
        assert failures, f"{scene}: change '{case}' passes the default rule: {score.metrics}"


# the false passes of the rule before the shift test: thin, tiny and small-shape changes
FORMERLY_PASSED = [("detail", "1-px pole added"), ("detail", "1-px pole removed"),
                   ("showcase", "small lantern glow dropped"), ("primitives 320", "cylinder 10% smaller"),
                   ("primitives 320", "box turned 5 degrees"), ("primitives 320", "cone 9% shorter"),
                   ("primitives 320", "cylinder 5% smaller")]


@pytest.mark.parametrize("scene,case", FORMERLY_PASSED, ids=[f"{s}:{c}" for s, c in FORMERLY_PASSED])
def test_the_ranges_alone_passed_what_the_shift_test_catches(scores, scene, case):
    metrics = scores[(scene, case)].metrics
    assert not suite.RANGE_ONLY.failures(metrics), "the neighbourhood ranges alone already catch it"
    assert DEFAULT_RULE.failures(metrics), "and the default rule does not"


CAUGHT_BY_IDS = sorted(suite.CAUGHT_BY_OBJECT_IDS)


@pytest.mark.parametrize("scene,case", CAUGHT_BY_IDS, ids=[f"{s}:{c}" for s, c in CAUGHT_BY_IDS])
def test_the_colours_alone_passed_what_the_object_ids_catch(scores, scene, case):
    """The five changes no shift statistic separates from a quarter-pixel jitter: the colour
    limits before the still region passed them; the object ids fail them, at least twice an
    object limit; and the still region limit, in a frame that did not move, catches all but
    the sphere moved 5 cm (its move reads as the frame's, 0.04 px, past 1/128)."""
    score = scores[(scene, case)]
    assert not suite.WITHOUT_STILL.failures(score.metrics), "the colours alone already caught it"
    still = score.metrics.still_region > DEFAULT_RULE.max_still_region
    assert still == ((scene, case) != ("primitives 320", "sphere moved 5 cm")), score.metrics
    assert DEFAULT_RULE.object_failures(score.objects), "and the object ids do not"
    ratios = [score.value(metric) / getattr(DEFAULT_RULE, limit) for metric, limit in suite.RULE_METRICS.items()
              if metric in suite.OBJECT_METRICS]
    assert max(ratios) >= 2, (scene, case, score.objects)


def test_every_limit_sits_twice_above_the_worst_noise(scores):
    noise = [s for s in scores.values() if s.noise]
    for metric, limit in suite.RULE_METRICS.items():
        worst = max(s.value(metric) for s in noise)
        assert worst * 2 <= getattr(DEFAULT_RULE, limit), (metric, worst)


COLOUR_LIMITS = {metric: limit for metric, limit in suite.RULE_METRICS.items() if metric not in suite.OBJECT_METRICS}


def test_the_colours_alone_fail_each_change_at_twice_a_limit(scores):
    """Without object ids, every change but the five only the ids catch fails a colour limit
    by twice that limit or more: with the limits twice above the worst noise, each such
    change lies four times or more from the noise on the metric that fails it."""
    for (scene, case), score in scores.items():
        if score.noise or (scene, case) in suite.CAUGHT_BY_OBJECT_IDS:
            continue
        ratios = [score.value(metric) / getattr(DEFAULT_RULE, limit) for metric, limit in COLOUR_LIMITS.items()]
        assert max(ratios) >= 2, (scene, case, score.metrics)


# the shift statistic of the rule before 12x12 windows: a quarter of the local contrast and a
# quarter of the second difference forgiven, 8x8 windows, at most 5 levels
PREVIOUS_SHIFT = {"shares": (0.25, 0.25), "window": 8, "limit": 5.0}


def test_the_previous_shift_statistic_passed_the_weakest_change_the_new_one_catches(gl):
    """A cylinder 5% smaller (its silhouette 1-2 px in) is the weakest change the shift limit
    alone catches; the previous statistic scored it under its limit, and under the worst
    noise too (3.3 levels against 3.7 for the detail scene jittered a quarter pixel)."""
    case = next(c for c in suite.CASES if c.name == "primitives 320")
    render = suite.api_render_fn(gl)
    base = render(case.path, case.base(), case.frame).pixels
    smaller = render(case.path, case.base() + case.changes()["cylinder 5% smaller"], case.frame).pixels
    metrics, _ = measure(base, smaller, DEFAULT_RULE.aa_tolerance, with_flip=False, with_ssim=False)
    assert metrics.shift_tile >= 2 * DEFAULT_RULE.max_shift_tile and DEFAULT_RULE.failures(metrics)
    assert not suite.RANGE_ONLY.failures(metrics), "the neighbourhood ranges catch it already"
    residual, _ = shift_residual(base, smaller, DEFAULT_RULE.aa_tolerance, shares=PREVIOUS_SHIFT["shares"])
    assert worst_window_bias(residual, PREVIOUS_SHIFT["window"]) <= PREVIOUS_SHIFT["limit"]


def test_no_change_is_a_known_miss_any_more():
    assert suite.KNOWN_MISSES == frozenset()
    names = {(case.name, name) for case in suite.CASES for name in case.changes()}
    assert suite.CAUGHT_BY_OBJECT_IDS <= names


def test_margin_table_lists_every_metric(scores):
    table = suite.margin_table(list(scores.values()))
    for label, _ in suite.METRICS.values():
        if label.startswith("FLIP"):
            continue  # not computed here
        assert label.replace("|", "\\|") in table


@pytest.mark.gl
def test_two_workers_against_one_process_is_noise_that_passes(tmp_path):
    """The corpus's last noise case: the detail scene's frames rendered by --workers 2 pass
    (they are byte-identical) against one process's."""
    def render(out, *extra):
        scene = ROOT / "tests" / "diff_corpus" / "detail.yaml"
        run = subprocess.run([sys.executable, "-m", "scenerender", "render", str(scene), "-o", str(out),
                              "--set", "output.fps=4", "--set", "output.duration=1", "--size", "160x120", *extra],
                             capture_output=True, text=True, timeout=120, cwd=ROOT)
        assert run.returncode == 0, run.stderr
    render(tmp_path / "one")
    render(tmp_path / "two", "--workers", "2")
    result = compare_paths(tmp_path / "one", tmp_path / "two")
    assert result.passed and len(result.frames) == 4
    assert all(frame.metrics.max_abs == 0 for frame in result.frames)
