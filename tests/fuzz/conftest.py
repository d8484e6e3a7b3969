"""Shared settings of the fuzz tests: a few deterministic examples in the normal test run,
many random ones under ``make fuzz``.

The profile is chosen by environment:
- default ("ci"): ``SCENERENDER_FUZZ_EXAMPLES`` examples per test (40 unless set),
  derandomized, so every run of the suite tries the same inputs and a failure reproduces;
- ``SCENERENDER_FUZZ=1`` ("fuzz", what ``make fuzz`` sets): random inputs, as many examples
  as ``SCENERENDER_FUZZ_EXAMPLES`` says (5000 unless set), failures remembered in
  hypothesis' example database so the next run tries them first.

An input that ever broke an invariant is kept: scene files in tests/corpus/ (with the
expected message), asset inputs as ``@example`` on the test that found them.
"""
from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

_SLOW_IS_FINE = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much]

settings.register_profile(
    "ci", max_examples=int(os.environ.get("SCENERENDER_FUZZ_EXAMPLES", "40")), derandomize=True,
    deadline=None, database=None, print_blob=True, suppress_health_check=_SLOW_IS_FINE)
settings.register_profile(
    "fuzz", max_examples=int(os.environ.get("SCENERENDER_FUZZ_EXAMPLES", "5000")), derandomize=False,
    deadline=None, print_blob=True, suppress_health_check=_SLOW_IS_FINE)
settings.load_profile("fuzz" if os.environ.get("SCENERENDER_FUZZ") else "ci")
