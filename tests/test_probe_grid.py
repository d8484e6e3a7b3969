"""Where render.indirect's probes stand (world/probe_grid.py): the default spacing gives any
scene the probe count of an 8-a-side cube, spread along its own shape. No GL."""
from __future__ import annotations

import numpy as np
import pytest

from scenerender.world.probe_grid import MAX_PROBES, probe_grid


@pytest.mark.parametrize("bounds, counts", [
    # the Cornell box as its bounds come out (float32 rounding on the floor): 8 a side
    ([[-1.0, -2.384185793236071e-08, -1.0], [1.0, 2.0, 1.0]], (8, 8, 8)),
    # a 16 m ground with boxes up to 1.6 m: along the ground, not one layer 2 m apart
    ([[-8.0, 0.0, -8.0], [8.0, 1.6, 8.0]], (18, 2, 18)),
    # a flat scene: the mean of its two sides, one layer
    ([[-1.0, 0.0, -1.0], [1.0, 0.0, 1.0]], (8, 1, 8)),
])
def test_the_default_spacing_spreads_a_cubes_probes_over_the_scene(bounds, counts):
    assert probe_grid(np.array(bounds), None).counts == counts


def test_a_spacing_too_fine_is_widened_to_the_cap():
    grid = probe_grid(np.array([[-8.0, 0.0, -8.0], [8.0, 1.6, 8.0]]), 0.1)
    assert grid.count <= MAX_PROBES
    assert grid.count > MAX_PROBES // 2
