"""Model matrices (T Rz Ry Rx S), normal matrices, and the camera's numerical edge cases."""
from __future__ import annotations

import math

import numpy as np
import pytest

from scenerender.world.camera import (
    fit_near_far, framing_position, look_rotation, orthographic, perspective, yaw_pitch_forward,
)
from scenerender.world.transforms import (
    euler_rotation, model_matrices, model_matrix, normal_matrices, rotation_x, rotation_y, rotation_z,
    transformed_bounds,
)


def test_euler_order_is_x_then_y_then_z():
    r = euler_rotation([90, 90, 0])
    # X first: +Y -> +Z; then Y by 90: +Z -> +X
    assert np.allclose(r @ [0, 1, 0], [1, 0, 0], atol=1e-12)
    assert np.allclose(euler_rotation([10, 20, 30]), rotation_z(30) @ rotation_y(20) @ rotation_x(10))


def test_model_matrix_is_t_rz_ry_rx_s():
    m = model_matrix([1, 2, 3], [10, 20, 30], [2, 3, 4])
    t = np.eye(4)
    t[:3, 3] = [1, 2, 3]
    r = np.eye(4)
    r[:3, :3] = rotation_z(30) @ rotation_y(20) @ rotation_x(10)
    s = np.diag([2, 3, 4, 1.0])
    assert np.allclose(m, t @ r @ s)


def test_batched_matrices_match_single_ones():
    rng = np.random.default_rng(3)
    p, r, s = rng.normal(size=(5, 3)), rng.uniform(-180, 180, (5, 3)), rng.uniform(0.1, 3, (5, 3))
    batch = model_matrices(p, r, s)
    for i in range(5):
        assert np.allclose(batch[i], model_matrix(p[i], r[i], s[i]))


def test_normals_stay_perpendicular_under_non_uniform_scale():
    m = model_matrix([0, 0, 0], [0, 0, 30], [1, 4, 1])
    tangent, normal = np.array([1.0, 1.0, 0.0]), np.array([1.0, -1.0, 0.0])  # perpendicular
    n = normal_matrices(m[None])[0] @ normal
    t = m[:3, :3] @ tangent
    assert abs(np.dot(n, t)) < 1e-12
    naive = m[:3, :3] @ normal  # what using the model matrix itself would give
    assert abs(np.dot(naive / np.linalg.norm(naive), t / np.linalg.norm(t))) > 0.1


def test_normal_matrix_matches_the_inverse_transpose_direction():
    m = model_matrix([5, 6, 7], [33, -12, 71], [0.5, 2, 3])
    ours = normal_matrices(m[None])[0]
    reference = np.linalg.inv(m[:3, :3]).T
    assert np.allclose(ours / np.linalg.norm(ours), reference / np.linalg.norm(reference))


def test_mirroring_keeps_normals_pointing_out():
    m = model_matrix([0, 0, 0], [0, 0, 0], [-1, 1, 1])
    assert np.allclose(normal_matrices(m[None])[0] @ [1, 0, 0], [-1, 0, 0])


def test_zero_scale_gives_finite_normal_matrices():
    m = model_matrix([0, 0, 0], [0, 0, 0], [1, 0, 1])
    n = normal_matrices(m[None])[0]
    assert np.all(np.isfinite(n))
    assert np.allclose(n @ [0, 1, 0], [0, 1, 0])  # the flattened box's top still faces up


def test_transformed_bounds_of_a_rotated_box():
    box = np.array([[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]])
    b = transformed_bounds(box, model_matrix([10, 0, 0], [0, 45, 0], 1.0)[None])
    assert np.allclose(b, [[10 - math.sqrt(2), -1, -math.sqrt(2)], [10 + math.sqrt(2), 1, math.sqrt(2)]])


# -- camera ----------------------------------------------------------------------------

def test_look_rotation_is_orthonormal_and_looks_down_minus_z():
    r = look_rotation([0, 0, -1], [0, 1, 0])
    assert np.allclose(r, np.eye(3))
    r = look_rotation([1, -2, 0.3], [0, 1, 0])
    assert np.allclose(r @ r.T, np.eye(3), atol=1e-12)
    assert np.allclose(-r[2], np.array([1, -2, 0.3]) / np.linalg.norm([1, -2, 0.3]))


@pytest.mark.parametrize("forward", [[0, -1, 0], [0, 1, 0], [0, -1, 1e-13], [1e-12, 1, 0]])
def test_looking_along_up_is_finite_and_continuous(forward):
    r = look_rotation(forward, [0, 1, 0])
    assert np.all(np.isfinite(r))
    assert np.allclose(r @ r.T, np.eye(3), atol=1e-9)
    # continuity with a camera tilted just short of straight down/up from looking at -Z
    sign = -1 if forward[1] < 0 else 1
    nearly = look_rotation([0, sign * 1.0, -1e-4], [0, 1, 0])
    assert np.allclose(r, nearly, atol=1e-3)


@pytest.mark.parametrize("forward", [[0, 0, 0], [0, 0, -0.0], [math.nan, 0, 0], [math.inf, 1, 0]])
def test_no_direction_at_all_looks_down_minus_z(forward):
    """A camera on its target (forward = target - position = 0) has nothing to look along:
    the rotation used to be all NaN."""
    assert np.array_equal(look_rotation(forward, [0, 1, 0]), np.eye(3))


@pytest.mark.parametrize("forward", [[1e-200, 0, 0], [0, -3e-320, 0], [1e300, 1e300, 0]])
def test_a_tiny_or_huge_forward_keeps_its_direction(forward):
    """Squaring 1e-200 in the length gives 0 (and 1e300 gives inf): the rotation used to be NaN."""
    r = look_rotation(forward, [0, 1, 0])
    assert np.all(np.isfinite(r)) and np.allclose(r @ r.T, np.eye(3), atol=1e-12)
    assert np.allclose(-r[2], np.sign(forward) / np.linalg.norm(np.sign(forward)))


def test_looking_down_puts_minus_z_at_the_top_of_the_image():
    r = look_rotation([0, -1, 0], [0, 1, 0])
    assert np.allclose(r[1], [0, 0, -1])  # screen up


def test_any_up_vector_works_when_looking_along_it():
    r = look_rotation([0, 0, -1], [0, 0, 1])
    assert np.all(np.isfinite(r)) and np.allclose(r @ r.T, np.eye(3), atol=1e-12)


def test_yaw_minus_90_looks_down_minus_z_and_pitch_is_clamped():
    assert np.allclose(yaw_pitch_forward(-90, 0), [0, 0, -1], atol=1e-12)
    assert np.allclose(yaw_pitch_forward(-90, 120), yaw_pitch_forward(-90, 89))
    assert np.allclose(yaw_pitch_forward(0, -200), yaw_pitch_forward(0, -89))


def test_projections_map_near_and_far_to_the_depth_range():
    p = perspective(60, 1.5, 0.5, 100)
    for z, ndc in ((-0.5, -1.0), (-100.0, 1.0)):
        clip = p @ [0, 0, z, 1]
        assert clip[2] / clip[3] == pytest.approx(ndc)
    o = orthographic(4.0, 2.0, 1.0, 11.0)
    assert (o @ [4.0, 2.0, -1.0, 1.0])[:3] == pytest.approx([1.0, 1.0, -1.0])


def test_near_far_enclose_the_bounds_with_a_bounded_ratio():
    bounds = np.array([[-1.0, -1.0, -11.0], [1.0, 1.0, -9.0]])
    near, far = fit_near_far(bounds, np.zeros(3), np.eye(3), False)
    assert 8.5 < near < 9.0 and 11.0 < far < 11.5
    # camera inside the bounds: near stays positive and at most 10^4 below far (the
    # fixed-point depth fallback's cap)
    near, far = fit_near_far(np.array([[-50.0] * 3, [50.0] * 3]), np.zeros(3), np.eye(3), False, 1e4)
    assert near > 0 and far / near <= 10000.0 + 1e-6


def test_near_far_without_a_ratio_cap_reach_the_nearest_corner():
    """Reversed-Z float depth: near follows the nearest bound however far the farthest is."""
    bounds = np.array([[-0.01, -0.01, -0.06], [0.01, 0.01, -0.05]])
    backdrop = np.array([[-1e4, -1e4, -5e4], [1e4, 1e4, -5e4]])
    everything = np.array([np.minimum(bounds[0], backdrop[0]), np.maximum(bounds[1], backdrop[1])])
    near, far = fit_near_far(everything, np.zeros(3), np.eye(3), False)
    assert far >= 5e4 and near > 0
    capped_near, _ = fit_near_far(everything, np.zeros(3), np.eye(3), False, 1e4)
    assert capped_near > 5.0  # the cap would clip a box 5 cm away


def test_near_far_are_the_same_far_from_the_origin():
    """Camera-relative fitting: a scene 1e6 away gets the same planes as at the origin."""
    bounds = np.array([[-1.0, -1.0, -11.0], [1.0, 1.0, -9.0]])
    offset = np.array([1e6, -2e6, 3e6])
    a = fit_near_far(bounds, np.zeros(3), np.eye(3), False)
    b = fit_near_far(bounds + offset, offset, np.eye(3), False)
    assert a == pytest.approx(b, rel=1e-9)


def test_framing_sees_the_whole_bounding_sphere():
    bounds = np.array([[-2.0, 0.0, -1.0], [2.0, 3.0, 1.0]])
    position, target = framing_position(bounds, 60.0, 4 / 3)
    radius = np.linalg.norm(bounds[1] - bounds[0]) / 2
    distance = np.linalg.norm(position - target)
    assert radius / distance <= math.sin(math.radians(30)) + 1e-9
    assert np.allclose(target, [0, 1.5, 0])


def test_spot_lights_default_to_smaller_maps_with_wider_filters():
    """Measured: a spot's 1024 px map with pcf 5 matches 2048 px with pcf 3 at half the time
    (scenerender/world/light_states.py); anything the scene sets explicitly wins."""
    from scenerender.scene.loading import load_scene_text
    from scenerender.world.light_states import light_defs

    text = """
lights:
  - {type: spot, position: [0, 3, 0], direction: [0, -1, 0], shadows: true}
  - {type: point, position: [0, 3, 0], shadows: true}
  - {type: spot, position: [0, 3, 0], direction: [0, -1, 0], shadows: {size: 512}}
objects: []
"""
    def shadows(extra=""):
        spec = load_scene_text(extra + text, ".").spec
        return [(d.shadow.size, d.shadow.pcf) for d in light_defs(spec.lights, spec.render.shadows)]

    assert shadows() == [(1024, 5), (2048, 3), (512, 5)]
    assert shadows("render: {shadows: {size: 4096}}\n") == [(4096, 5), (4096, 3), (512, 5)]
