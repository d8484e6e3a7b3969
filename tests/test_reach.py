"""Placements whose world-space values leave 32-bit floats are refused when the world is
built (scenerender.world.reach), for every frame of an animation at once. No GL needed."""
from __future__ import annotations

import contextlib
import warnings

import numpy as np
import pytest
from click.testing import CliRunner

from scenerender.animation import Track
from scenerender.cli import main
from scenerender.errors import UserError, Warnings
from scenerender.scene.loading import load_scene_text
from scenerender.world.build import build_world
from scenerender.world.frame import FrameEvaluator


@contextlib.contextmanager
def numpy_warnings_fail():
    """An overflow in a float32 cast (a RuntimeWarning) fails the test instead of printing."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        yield


def build(text: str, tmp_path):
    return build_world(load_scene_text(text, tmp_path, []), Warnings())


def refusal(text: str, tmp_path) -> UserError:
    with numpy_warnings_fail(), pytest.raises(UserError) as caught:
        build(text, tmp_path)
    return caught.value


def evaluate_frames(world, times) -> None:
    evaluator = FrameEvaluator(world, (64, 48), None)
    for index, t in enumerate(times):
        evaluator.evaluate(index, t)


BOX = "{primitive: box}"


def test_a_scale_whose_products_overflow_is_refused_at_its_key(tmp_path):
    """1e30 is a float32, but the normal matrix holds products of two scale factors (1e60)."""
    error = refusal(f"objects:\n  - name: huge\n    mesh: {BOX}\n    scale: 1e30\n", tmp_path)
    assert error.key == "objects[0].scale" and error.location.line == 4
    assert "object 'huge'" in error.message and "1e+60 in its normal matrix" in error.message
    assert "beyond 32-bit floats" in error.message


def test_validate_says_so_in_one_line(tmp_path, monkeypatch):
    (tmp_path / "scene.yaml").write_text(f"objects:\n  - mesh: {BOX}\n    scale: [1, 1e20, 1e20]\n")
    monkeypatch.chdir(tmp_path)
    with numpy_warnings_fail():
        result = CliRunner().invoke(main, ["validate", "scene.yaml"])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: scene.yaml:3:5: objects[0].scale: object 'box0': its scale factors")
    assert result.stderr.count("\n") == 1


def test_the_largest_scale_whose_products_fit_is_accepted_and_draws_without_overflow(tmp_path):
    world = build(f"objects:\n  - mesh: {BOX}\n    scale: 1.8e19\n    rotation: [30, 40, 50]\n", tmp_path)
    with numpy_warnings_fail():
        evaluate_frames(world, [0.0])


def test_an_animated_scale_is_refused_for_the_frame_that_would_overflow(tmp_path):
    text = (f"output: {{fps: 1, frames: 3}}\nobjects:\n  - mesh: {BOX}\n"
            "    scale: {keys: [[0, 1], [2, 1e30]]}\n")
    error = refusal(text, tmp_path)  # frame 0 alone would be fine
    assert error.key == "objects[0].scale"


def test_a_catmull_rom_overshoot_beyond_the_keys_is_taken_into_account(tmp_path):
    """Every key is 1.5e19 (products 2.25e38, fine), but the curve overshoots its keys."""
    keys = "[[0, 0.001], [1, 1.5e19], [1.2, 0.001], [3, 1.5e19]]"
    text = f"objects:\n  - mesh: {BOX}\n    scale: {{keys: {keys}, interpolation: catmull_rom}}\n"
    assert refusal(text, tmp_path).key == "objects[0].scale"
    world = build(text.replace("1.5e19", "1e19"), tmp_path)  # overshoots too, within the range
    with numpy_warnings_fail():
        evaluate_frames(world, np.linspace(0.0, 3.0, 301))


@pytest.mark.parametrize("instances", [
    "[{scale: 1e20}]",
    "{random: {count: 3, seed: 1, position: {min: [0, 0, 0], max: [1, 1, 1]}, scale: {min: 1e19, max: 1e20}}}",
])
def test_an_object_scale_times_an_instance_scale_is_refused_at_instances(tmp_path, instances):
    error = refusal(f"objects:\n  - mesh: {BOX}\n    scale: 1e19\n    instances: {instances}\n", tmp_path)
    assert error.key == "objects[0].instances"
    assert "beyond 32-bit floats" in error.message


def test_instances_that_shrink_a_large_object_are_fine(tmp_path):
    text = f"objects:\n  - mesh: {BOX}\n    scale: 1e30\n    instances: [{{scale: 1e-20}}, {{scale: 1e-25}}]\n"
    world = build(text, tmp_path)
    with numpy_warnings_fail():
        evaluate_frames(world, [0.0])


def test_vertices_pushed_beyond_32_bit_floats_are_refused_at_the_object(tmp_path):
    text = "objects:\n  - mesh: {primitive: box}\n  - name: far\n    mesh: {primitive: box, size: 1e38}\n" \
           "    position: [3e38, 0, 0]\n"
    error = refusal(text, tmp_path)
    assert error.key == "objects[1]" and error.location.line == 3
    assert "object 'far': its vertices can reach" in error.message


def test_the_magnitude_bound_holds_at_every_time_for_every_interpolation():
    rng = np.random.default_rng(5)
    for _ in range(200):
        count = int(rng.integers(2, 7))
        times = np.cumsum(rng.uniform(0.01, 3.0, count))
        values = rng.normal(0, 10, (count, 3)) * rng.choice([1.0, 1e-3, 1e3], (count, 1))
        modes = list(rng.choice(["step", "linear", "cosine", "catmull_rom"], count))
        track = Track(times, values, modes, loop=bool(rng.integers(2)), kind="vector")
        bound = track.magnitude_bound()
        samples = np.array([track(t) for t in np.linspace(times[0] - 1, times[-1] + 1, 500)])
        assert (np.abs(samples) <= bound * (1 + 1e-12)).all()
