"""Keyframe interpolation: the formulas of docs/scene-format.md, evaluated in float64."""
from __future__ import annotations

import math

import numpy as np
import pytest

from scenerender.animation import Track


def vec_track(mode, loop=False):
    return Track([0.0, 2.0, 4.0], [[0.0, 0.0, 0.0], [2.0, 4.0, -2.0], [6.0, 4.0, 0.0]], [mode] * 3, loop=loop,
                 kind="vector")


@pytest.mark.parametrize("mode", ["step", "linear", "cosine", "catmull_rom"])
def test_exact_values_at_keys(mode):
    track = vec_track(mode)
    for t, expected in ((0.0, [0, 0, 0]), (2.0, [2, 4, -2]), (4.0, [6, 4, 0])):
        assert np.array_equal(track(t), expected)


def test_linear_midpoint():
    assert np.allclose(vec_track("linear")(1.0), [1.0, 2.0, -1.0])
    assert np.allclose(vec_track("linear")(0.5), [0.5, 1.0, -0.5])  # u = 0.25


def test_cosine_midpoint_and_quarter():
    track = vec_track("cosine")
    assert np.allclose(track(1.0), [1.0, 2.0, -1.0])  # u = 0.5 -> (1 - cos(pi/2)) / 2 = 0.5
    w = (1 - math.cos(0.25 * math.pi)) / 2            # u = 0.25
    assert np.allclose(track(0.5), np.array([2.0, 4.0, -2.0]) * w)


def test_cosine_derivative_is_zero_at_the_segment_ends():
    track = Track([0.0, 1.0], [0.0, 10.0], ["cosine", "cosine"])
    h = 1e-4
    start = (track(h) - track(0.0)) / h
    end = (track(1.0) - track(1.0 - h)) / h
    middle = (track(0.5 + h) - track(0.5 - h)) / (2 * h)
    assert abs(start) < 1e-2 and abs(end) < 1e-2
    assert middle == pytest.approx(10 * math.pi / 2, rel=1e-4)  # peak speed of the ease


def test_step_holds_until_the_next_key():
    track = vec_track("step")
    assert np.array_equal(track(1.999), [0, 0, 0])
    assert np.array_equal(track(2.0), [2, 4, -2])
    assert np.array_equal(track(3.9), [2, 4, -2])


def test_before_first_and_after_last_key_clamp():
    track = Track([1.0, 2.0], [5.0, 7.0], ["linear", "linear"])
    assert track(-100.0) == 5.0 and track(0.999) == 5.0
    assert track(2.0) == 7.0 and track(1e9) == 7.0


def test_loop_wraps_modulo_the_last_key_time():
    track = Track([0.0, 1.0, 2.0], [0.0, 10.0, 0.0], ["linear"] * 3, loop=True)
    assert track(0.5) == pytest.approx(5.0)
    assert track(2.5) == pytest.approx(5.0)
    assert track(4.0) == pytest.approx(0.0)
    assert track(-0.5) == pytest.approx(5.0)
    assert track(100000.5) == pytest.approx(5.0)


def test_catmull_rom_passes_through_its_keys_and_is_smooth():
    times = [0.0, 1.0, 2.5, 3.0]
    values = [[0, 0], [1, 2], [3, 1], [4, 4]]
    track = Track(times, values, ["catmull_rom"] * 4, kind="vector")
    for t, v in zip(times, values):
        assert np.allclose(track(t), v)
    h = 1e-6  # C1: the velocity is continuous across an interior key
    for key in (1.0, 2.5):
        left = (track(key) - track(key - h)) / h
        right = (track(key + h) - track(key)) / h
        assert np.allclose(left, right, atol=1e-3)


def test_catmull_rom_reproduces_a_straight_line_at_constant_speed():
    track = Track([0.0, 1.0, 3.0, 4.0], [0.0, 1.0, 3.0, 4.0], ["catmull_rom"] * 4)
    for t in np.linspace(0.0, 4.0, 17):
        assert track(t) == pytest.approx(t, abs=1e-12)


def test_per_key_interpolation_shapes_only_its_segment():
    track = Track([0.0, 1.0, 2.0], [0.0, 1.0, 2.0], ["step", "linear", "linear"])
    assert track(0.5) == 0.0
    assert track(1.5) == pytest.approx(1.5)


def test_bool_tracks_always_step():
    track = Track([0.0, 1.0, 2.0], [1.0, 0.0, 1.0], ["linear"] * 3, kind="bool")
    assert track(0.99) is True and track(1.0) is False and track(1.5) is False and track(2.0) is True


def test_frame_time_precision_far_into_an_animation():
    """Frame 100000 at 30 fps is as exact as frame 1: times are float64 and fps-exact."""
    track = Track([0.0, 1e6], [0.0, 1e6], ["linear", "linear"])
    for frame in (1, 100000, 1234567):
        t = frame / 30.0
        assert track(t) == pytest.approx(t, rel=1e-15, abs=1e-9)


def test_constant_track():
    track = Track.constant((1.0, 2.0, 3.0), kind="vector")
    assert track.is_constant and np.array_equal(track(123.0), [1, 2, 3])
    assert not vec_track("linear").is_constant


def test_unsorted_or_duplicate_times_are_rejected():
    with pytest.raises(ValueError):
        Track([0.0, 0.0], [1.0, 2.0], ["linear", "linear"])
    with pytest.raises(ValueError):
        Track([1.0, 0.0], [1.0, 2.0], ["linear", "linear"])
