"""The perturbation suite (scenerender.compare.perturbation): under DEFAULT_RULE every noise
case passes and every change case fails, and every metric the rule judges by separates
the two. Each scene's base is rendered once per module, at 160x120."""
from __future__ import annotations

import pytest

from conftest import render_one
from scenerender.compare import DEFAULT_RULE
from scenerender.compare import perturbation as suite


@pytest.fixture(scope="module")
def scores(gl):
    def render(path, overrides, frame):
        return render_one(gl, path, overrides, frame)

    # FLIP is left out: the rule does not use it, and it is the slowest metric
    return {(s.scene, s.case): s for s in suite.run_suite(render, with_flip=False)}


CASE_IDS = [(case.name, name) for case in suite.CASES for name in suite.NOISE + suite.CHANGES]


@pytest.mark.parametrize("scene,case", CASE_IDS, ids=[f"{s}:{c}" for s, c in CASE_IDS])
def test_default_rule_judges(scores, scene, case):
    score = scores[(scene, case)]
    failures = DEFAULT_RULE.failures(score.metrics)
    if score.noise:
        assert not failures, f"{scene}: noise '{case}' fails the default rule: {failures}"
    else:
        assert failures, f"{scene}: change '{case}' passes the default rule: {score.metrics}"


def test_the_rule_metrics_separate_noise_from_change(scores):
    margins = {m.metric: m for m in suite.margins(list(scores.values()))}
    for metric in ("worst_tile_aa", "unexplained_mean"):
        assert margins[metric].separates, margins[metric]
    # and the limits lie between the worst noise and the closest change of that metric
    assert margins["worst_tile_aa"].noise_worst < DEFAULT_RULE.max_tile
    assert margins["unexplained_mean"].noise_worst < DEFAULT_RULE.max_unexplained_mean \
        < margins["unexplained_mean"].change_best


def test_margin_table_lists_every_metric(scores):
    table = suite.margin_table(list(scores.values()))
    for label, _ in suite.METRICS.values():
        if label.startswith("FLIP"):
            continue  # not computed here
        assert label.replace("|", "\\|") in table
