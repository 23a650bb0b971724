"""redik.lie.so3: exp and log at every angle, quaternions, SLERP, the inverse left Jacobian."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from redik import lie
from tests.samples import random_rotation


@pytest.mark.parametrize(
    "angle", [0.0, 1e-300, 1e-16, 1e-12, 1e-7, 1e-3, 0.5, 2.0, math.pi - 1e-6, math.pi]
)
def test_so3_log_inverts_exp_at_every_angle(rng, angle):
    for _ in range(20):
        axis = rng.normal(size=3)
        omega = angle * axis / np.linalg.norm(axis)
        R = lie.so3_exp(omega)
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-14)
        back = lie.so3_log(R)
        if angle <= 1e-3:  # relative: below 2e-15 rad MuJoCo's quat2Vel loses the axis
            assert np.abs(back - omega).max() <= 1e-14 * angle
        elif angle < math.pi - 1e-3:
            np.testing.assert_allclose(back, omega, atol=1e-12)
        else:  # ±axis both valid at π: compare the rotations
            np.testing.assert_allclose(lie.so3_exp(back), R, atol=1e-9)
            assert abs(np.linalg.norm(back) - angle) < 1e-8


def test_quaternion_roundtrip(rng):
    for _ in range(50):
        R = random_rotation(rng)
        quat = lie.quat_from_matrix(R)
        assert quat[0] >= 0.0
        np.testing.assert_allclose(lie.matrix_from_quat(quat), R, atol=1e-12)


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


def test_apply_inverse_v_inverts_v_and_is_the_so3_inverse_left_jacobian(rng):
    for angle in (0.0, 1e-9, 1e-7, 2e-6, 0.999e-3, 1.001e-3, 0.5, 2.0, np.pi - 1e-6):
        axis = rng.standard_normal(3)
        omega, p = angle * axis / np.linalg.norm(axis), rng.standard_normal(3)
        W = lie.skew(omega)
        t2 = angle**2  # MR (3.86); its coefficients by their series where they cancel
        a = 0.5 - t2 / 24 + t2**2 / 720 if angle < 1e-2 else (1 - math.cos(angle)) / t2
        b = (
            1 / 6 - t2 / 120 + t2**2 / 5040
            if angle < 1e-2
            else (angle - math.sin(angle)) / t2 / angle
        )
        V = np.eye(3) + a * W + b * W @ W
        v = lie.apply_inverse_v(*omega, *p)
        np.testing.assert_allclose(V @ v, p, rtol=0, atol=1e-12 * max(1.0, 1.0 / (np.pi - angle)))
        # One formula: V(ω)⁻¹ is J_l⁻¹(ω) on SO(3), the block of the SE(3) one.
        np.testing.assert_allclose(lie.so3_left_jacobian_inverse(omega) @ p, v, atol=1e-14)
