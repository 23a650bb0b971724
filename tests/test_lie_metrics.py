"""redik.lie.metrics: the pose errors of the solvers and the orientation metrics of the course."""

from __future__ import annotations

import math

import numpy as np
import pytest

from redik import lie
from tests.samples import random_pose, random_rotation


def test_rotation_metrics_agree(rng):
    for angle in [1e-6, 1e-3, 0.1, 1.0, 3.0]:
        R_a = random_rotation(rng)
        axis = rng.normal(size=3)
        R_b = R_a @ lie.so3_exp(angle * axis / np.linalg.norm(axis))
        q_a, q_b = lie.quat_from_matrix(R_a), lie.quat_from_matrix(R_b)
        assert lie.rotation_angle(R_a, R_b) == pytest.approx(angle, rel=1e-9)
        assert lie.quaternion_geodesic_distance(q_a, q_b) == pytest.approx(angle, rel=1e-9)
        assert lie.quaternion_geodesic_distance(q_a, -q_b) == pytest.approx(angle, rel=1e-9)
        assert lie.quaternion_chordal_distance(q_a, -q_b) == pytest.approx(
            2 * math.sin(angle / 4), rel=1e-8
        )
        # The trace formula is only good to ~sqrt(eps) at small angles.
        assert lie.rotation_angle_trace(R_a, R_b) == pytest.approx(angle, abs=3e-8)


def test_trace_formula_loses_precision_where_log_does_not():
    R_b = lie.so3_exp(np.array([0.0, 0.0, 1e-9]))
    assert lie.rotation_angle(np.eye(3), R_b) == pytest.approx(1e-9, rel=1e-6)
    assert lie.rotation_angle_trace(np.eye(3), R_b) == 0.0  # cos(1e-9) rounds to 1


def test_body_error_twist_and_small_euler_difference(rng):
    T_a = random_pose(rng)
    xi = np.array([0.01, -0.02, 0.03, 1e-3, -2e-3, 1.5e-3])
    T_b = T_a @ lie.se3_exp(xi)
    np.testing.assert_allclose(lie.body_error_twist(T_a, T_b), xi, atol=1e-12)
    p, r = lie.pose_errors(T_a, T_b)
    assert r == pytest.approx(np.linalg.norm(xi[3:]), rel=1e-9)
    assert p == pytest.approx(np.linalg.norm(T_b[:3, 3] - T_a[:3, 3]))
    # For small rotations about x, the xyz Euler difference reads the angle directly.
    R = lie.so3_exp(np.array([0.2, 0.1, -0.3]))
    d = lie.euler_difference(R, R @ lie.so3_exp(np.array([0.0, 0.0, 1e-4])), "xyz")
    assert d[2] == pytest.approx(1e-4, rel=1e-2)


# The course's two orientations (000, "Position and Orientation Error for Minimum-Coordinate
# Representation"; no numbers there, these are chosen): exponential coordinates that differ by
# (0.3, 0.3, 0.3).
R_1 = lie.so3_exp(np.array([0.2, -0.4, 0.3]))
R_2 = lie.so3_exp(np.array([0.5, -0.1, 0.6]))


def test_exp_coordinate_distance_is_the_course_e_r_not_the_relative_angle():
    # e_R = ‖r1 − r2‖ = 0.3·√3, while the rotation between them is 2 arccos|q1·q2|.
    assert lie.exp_coordinate_distance(R_1, R_2) == pytest.approx(0.3 * math.sqrt(3), abs=1e-14)
    assert round(lie.exp_coordinate_distance(R_1, R_2), 4) == 0.5196
    q_1, q_2 = lie.quat_from_matrix(R_1), lie.quat_from_matrix(R_2)
    relative = 2 * math.acos(abs(q_1 @ q_2))
    assert round(relative, 4) == 0.5134
    assert lie.rotation_angle(R_1, R_2) == pytest.approx(relative, abs=1e-12)
    assert lie.quaternion_geodesic_distance(q_1, q_2) == pytest.approx(relative, abs=1e-12)
    assert lie.rotation_angle_trace(R_1, R_2) == pytest.approx(relative, abs=1e-12)
    chordal = min(np.linalg.norm(q_1 - q_2), np.linalg.norm(q_1 + q_2))
    assert lie.quaternion_chordal_distance(q_1, q_2) == pytest.approx(chordal, abs=1e-15)
    assert chordal == pytest.approx(2 * math.sin(relative / 4), abs=1e-12)


def test_exp_coordinate_distance_is_the_angle_only_about_a_common_axis(rng):
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    R_a, R_b = lie.so3_exp(0.4 * axis), lie.so3_exp(-1.3 * axis)
    assert lie.exp_coordinate_distance(R_a, R_b) == pytest.approx(1.7, abs=1e-12)
    assert lie.rotation_angle(R_a, R_b) == pytest.approx(1.7, abs=1e-12)
    assert lie.exp_coordinate_distance(R_1, R_1) == 0.0


def test_euler_difference_is_the_course_difference_of_angles_wrapped():
    d = lie.euler_difference(R_1, R_2, "zyx")
    expected = lie.euler_angles(R_2, "zyx") - lie.euler_angles(R_1, "zyx")
    np.testing.assert_allclose(d, expected, atol=1e-15)  # small: nothing to wrap
    assert round(float(np.linalg.norm(d)), 4) == 0.4569
    flipped = lie.so3_exp([0, 0, 3.0]), lie.so3_exp([0, 0, -3.0])
    np.testing.assert_allclose(lie.euler_difference(*flipped, "xyz"), [0, 0, 2 * math.pi - 6])
