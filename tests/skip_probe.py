"""Run only by tests/test_ci_skips.py, in a pytest of its own (the name keeps it out of a
normal run): skips for the reason SCENERENDER_SKIP_PROBE gives."""
import os

import pytest


def test_probe():
    reason = os.environ["SCENERENDER_SKIP_PROBE"]
    if reason == "missing module":
        pytest.importorskip("a_module_no_install_has")
    pytest.skip(reason)
