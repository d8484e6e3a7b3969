"""What keeps a green run honest: a skip .ci/allowed-skips does not list (a module missing
from a clean install, say) fails the run, the listed reasons still pass, and a
DeprecationWarning raised from scenerender's own code is an error under pytest."""
from __future__ import annotations

import os
import subprocess
import sys
import warnings

import pytest

from conftest import ROOT


def _run_probe(reason: str, *options: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, SCENERENDER_SKIP_PROBE=reason,
               SCENERENDER_ALLOWED_SKIPS=str(ROOT / ".ci" / "allowed-skips"))
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *options,
                           str(ROOT / "tests" / "skip_probe.py")], cwd=ROOT, env=env, capture_output=True, text=True)


# `make test` and CI run the suite on pytest-xdist workers, where the skip is reported to
# the controlling process from a worker: the guard must see it there too.
@pytest.mark.parametrize("options", [(), ("-n", "2")], ids=["one process", "two workers"])
def test_a_skip_for_a_missing_module_fails_the_run(options):
    result = _run_probe("missing module", *options)
    assert result.returncode == 1, result.stdout
    assert "1 skip(s) not listed in" in result.stdout
    assert "could not import 'a_module_no_install_has'" in result.stdout


def test_a_listed_skip_passes():
    result = _run_probe("root reads any file")
    assert result.returncode == 0, result.stdout


def test_a_deprecation_in_scenerenders_code_is_an_error():
    with pytest.raises(DeprecationWarning):
        warnings.warn_explicit("old call", DeprecationWarning, "scenerender/x.py", 1, module="scenerender.x")

