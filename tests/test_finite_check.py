"""SCENERENDER_CHECK_FINITE=1: a render fails on any NaN or Inf reaching the linear colour."""
from __future__ import annotations

import numpy as np
import pytest

from scenerender.rendering.renderer import ENV_CHECK_FINITE, NonFiniteOutput, first_non_finite

SCENE = """
render: {size: [48, 32], samples: 1}
camera: {position: [0, 1.5, 3], target: [0, 0, 0], fov: 50}
lights:
  - {type: directional, direction: [-0.3, -1, -0.2], intensity: INTENSITY}
  - {type: directional, direction: [0.3, -1, -0.2], intensity: INTENSITY}
objects:
  - mesh: {primitive: sphere, radius: 0.8}
"""


def test_first_non_finite_names_the_count_and_the_first_pixel():
    linear = np.zeros((4, 5, 3), dtype=np.float32)
    assert first_non_finite(linear) is None
    linear[2, 3, 1] = np.nan
    linear[3, 0, 0] = np.inf
    assert first_non_finite(linear) == "2 pixel(s) with NaN or Inf in the linear colour, the first at x 3, y 2"


def test_check_fails_a_frame_whose_light_overflows_to_inf(render_scene, monkeypatch):
    """Two lights of 3e38 (each a valid float32) sum to Inf in the shader: without the
    check the frame quietly saturates to white, with it the render fails."""
    overflowing = SCENE.replace("INTENSITY", "3e38")
    assert render_scene(overflowing).max() == 255
    monkeypatch.setenv(ENV_CHECK_FINITE, "1")
    render_scene(SCENE.replace("INTENSITY", "1"))  # finite: passes
    with pytest.raises(NonFiniteOutput, match="frame 0: .* NaN or Inf"):
        render_scene(overflowing)
