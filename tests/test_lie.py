"""SE(3) helpers: exp/log identities, adjoint, metrics, SLERP; checked against mink.lie."""

from __future__ import annotations

import itertools
import math

import mink
import numpy as np
import pytest

from redik import lie
from redik.exceptions import InvalidInput, InvalidPose, InvalidRotation


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    quat = rng.normal(size=4)
    return lie.matrix_from_quat(quat / np.linalg.norm(quat))


def random_pose(rng: np.random.Generator) -> np.ndarray:
    return lie.make_pose(random_rotation(rng), rng.uniform(-2, 2, 3))


@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-7, 1e-3, 0.5, 2.0, math.pi - 1e-6, math.pi])
def test_so3_log_inverts_exp_at_every_angle(rng, angle):
    for _ in range(20):
        axis = rng.normal(size=3)
        omega = angle * axis / np.linalg.norm(axis)
        R = lie.so3_exp(omega)
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-14)
        back = lie.so3_log(R)
        if angle < math.pi - 1e-3:
            np.testing.assert_allclose(back, omega, atol=1e-12)
        else:  # ±axis both valid at π: compare the rotations
            np.testing.assert_allclose(lie.so3_exp(back), R, atol=1e-9)
            assert abs(np.linalg.norm(back) - angle) < 1e-8


def test_se3_exp_log_roundtrip_and_match_mink(rng):
    for _ in range(200):
        T = random_pose(rng)
        xi = lie.se3_log(T)
        np.testing.assert_allclose(lie.se3_exp(xi), T, atol=1e-12)
        np.testing.assert_allclose(xi, mink.SE3.from_matrix(T).log(), atol=1e-10)
        xi_small = rng.normal(size=6) * 1e-8
        np.testing.assert_allclose(lie.se3_log(lie.se3_exp(xi_small)), xi_small, atol=1e-20)
        np.testing.assert_allclose(lie.se3_exp(xi), mink.SE3.exp(xi).as_matrix(), atol=1e-12)


def test_adjoint_matches_mink_and_maps_twists(rng):
    for _ in range(50):
        T = random_pose(rng)
        np.testing.assert_allclose(lie.adjoint(T), mink.SE3.from_matrix(T).adjoint(), atol=1e-12)
        xi = rng.normal(size=6)
        # T exp(ξ) T⁻¹ = exp(Ad_T ξ)
        lhs = T @ lie.se3_exp(xi) @ lie.inverse(T)
        np.testing.assert_allclose(lhs, lie.se3_exp(lie.adjoint(T) @ xi), atol=1e-10)
        np.testing.assert_allclose(lie.inverse(T) @ T, np.eye(4), atol=1e-12)


def test_quaternion_roundtrip(rng):
    for _ in range(50):
        R = random_rotation(rng)
        quat = lie.quat_from_matrix(R)
        assert quat[0] >= 0.0
        np.testing.assert_allclose(lie.matrix_from_quat(quat), R, atol=1e-12)


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


def test_exp_coordinate_difference_and_small_euler_difference(rng):
    T_a = random_pose(rng)
    xi = np.array([0.01, -0.02, 0.03, 1e-3, -2e-3, 1.5e-3])
    T_b = T_a @ lie.se3_exp(xi)
    np.testing.assert_allclose(lie.exp_coordinate_difference(T_a, T_b), xi, atol=1e-12)
    p, r = lie.pose_errors(T_a, T_b)
    assert r == pytest.approx(np.linalg.norm(xi[3:]), rel=1e-9)
    assert p == pytest.approx(np.linalg.norm(T_b[:3, 3] - T_a[:3, 3]))
    # For small rotations about x, the xyz Euler difference reads the angle directly.
    R = lie.so3_exp(np.array([0.2, 0.1, -0.3]))
    d = lie.euler_difference(R, R @ lie.so3_exp(np.array([0.0, 0.0, 1e-4])), "xyz")
    assert d[2] == pytest.approx(1e-4, rel=1e-2)


@pytest.mark.parametrize("convention", ["xyz", "zyx", "zyz"])
def test_euler_angles_reconstruct(rng, convention):
    axes = {"x": 0, "y": 1, "z": 2}
    for _ in range(20):
        R = random_rotation(rng)
        angles = lie.euler_angles(R, convention)
        rebuilt = np.eye(3)
        for axis, angle in zip(convention, angles, strict=True):
            omega = np.zeros(3)
            omega[axes[axis]] = angle
            rebuilt = rebuilt @ lie.so3_exp(omega)
        np.testing.assert_allclose(rebuilt, R, atol=1e-10)


def test_slerp_endpoints_and_constant_speed(rng):
    for _ in range(20):
        q_a = lie.quat_from_matrix(random_rotation(rng))
        q_b = lie.quat_from_matrix(random_rotation(rng))
        assert lie.quaternion_geodesic_distance(lie.slerp(q_a, q_b, 0.0), q_a) < 1e-12
        assert lie.quaternion_geodesic_distance(lie.slerp(q_a, q_b, 1.0), q_b) < 1e-7
        total = lie.quaternion_geodesic_distance(q_a, q_b)
        ts = np.linspace(0, 1, 11)
        points = [lie.slerp(q_a, q_b, t) for t in ts]
        steps = [lie.quaternion_geodesic_distance(a, b) for a, b in itertools.pairwise(points)]
        np.testing.assert_allclose(steps, total / 10, rtol=1e-6, atol=1e-12)
        for quat in points:
            assert np.linalg.norm(quat) == pytest.approx(1.0)


def test_interpolate_pose_matches_mink(rng):
    T_a, T_b = random_pose(rng), random_pose(rng)
    for t in (0.0, 0.3, 1.0):
        mine = lie.interpolate_pose(T_a, T_b, t)
        np.testing.assert_allclose(mine[:3, 3], (1 - t) * T_a[:3, 3] + t * T_b[:3, 3])
        R_ref = mink.SO3.from_matrix(T_a[:3, :3]).interpolate(mink.SO3.from_matrix(T_b[:3, :3]), t)
        np.testing.assert_allclose(mine[:3, :3], R_ref.as_matrix(), atol=1e-9)


def test_bad_inputs_raise_clear_errors():
    with pytest.raises(InvalidRotation, match="shape"):
        lie.as_rotation(np.eye(4))
    with pytest.raises(InvalidRotation, match="NaN"):
        lie.as_rotation(np.full((3, 3), np.nan))
    with pytest.raises(InvalidRotation, match="det"):
        lie.as_rotation(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(InvalidRotation, match="not a rotation"):
        lie.as_rotation(2 * np.eye(3))
    bad_row = np.eye(4)
    bad_row[3, 0] = 1.0
    with pytest.raises(InvalidPose, match=r"\[0, 0, 0, 1\]"):
        lie.as_pose(bad_row)
    with pytest.raises(InvalidPose, match="shape"):
        lie.as_pose(np.eye(3))
    with pytest.raises(InvalidPose):
        lie.as_pose(np.diag([1.0, 1.0, -1.0, 1.0]))
    with pytest.raises(InvalidInput, match="unit quaternion"):
        lie.as_quaternion([1.0, 1.0, 0.0, 0.0])
    with pytest.raises(InvalidInput, match="convention"):
        lie.euler_angles(np.eye(3), "abc")
