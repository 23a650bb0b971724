"""redik.lie.se3: exp/log, adjoint, interpolation, inverse left Jacobian, Jacobian references."""

from __future__ import annotations

import math

import mink
import numpy as np
import pytest

from redik import lie
from redik.core.exceptions import InvalidInput
from tests.samples import random_pose


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


def test_interpolate_pose_matches_mink(rng):
    T_a, T_b = random_pose(rng), random_pose(rng)
    for t in (0.0, 0.3, 1.0):
        mine = lie.interpolate_pose(T_a, T_b, t)
        np.testing.assert_allclose(mine[:3, 3], (1 - t) * T_a[:3, 3] + t * T_b[:3, 3])
        R_ref = mink.SO3.from_matrix(T_a[:3, :3]).interpolate(mink.SO3.from_matrix(T_b[:3, :3]), t)
        np.testing.assert_allclose(mine[:3, :3], R_ref.as_matrix(), atol=1e-9)


def series_left_jacobian_inverse(xi: np.ndarray) -> np.ndarray:
    """(Σ ad^k/(k+1)!)⁻¹: the definition, summed to convergence."""
    ad = np.zeros((6, 6))
    ad[:3, :3] = ad[3:, 3:] = lie.skew(xi[3:])
    ad[:3, 3:] = lie.skew(xi[:3])
    J, power = np.zeros((6, 6)), np.eye(6)
    for k in range(40):
        J += power / math.factorial(k + 1)
        power = power @ ad
    return np.linalg.inv(J)


@pytest.mark.parametrize("angle", [0.0, 1e-9, 1e-4, 0.999e-3, 1.001e-3, 0.1, 1.0, 2.5, 3.1])
def test_left_jacobian_inverse_closed_form_matches_its_series_and_mink(angle, rng):
    xi = rng.normal(size=6)
    xi[3:] *= angle / np.linalg.norm(xi[3:])
    reference = series_left_jacobian_inverse(xi)
    np.testing.assert_allclose(lie.se3_left_jacobian_inverse(xi), reference, atol=1e-12)
    so3 = lie.so3_left_jacobian_inverse(xi[3:])
    np.testing.assert_allclose(so3, reference[3:, 3:], atol=1e-12)
    if angle >= 0.1:  # below, mink's closed form divides by 1 − cos θ (5e-9 off at 1e-4,
        # 8e-4 at 1e-7, inf at 1e-9), and returns the identity on SE(3) for θ < 1.5e-8
        np.testing.assert_allclose(so3, mink.SO3.ljacinv(xi[3:]), atol=1e-12)
        np.testing.assert_allclose(
            lie.se3_left_jacobian_inverse(xi), mink.SE3.ljacinv(xi), atol=1e-11
        )


@pytest.mark.parametrize("batch", [(), (5,), (2, 3)])
def test_world_jacobian_to_matches_the_adjoint_relations(batch, rng):
    n = 4
    J = rng.standard_normal((6, n, *batch))
    R = np.einsum("ij,...->ij...", lie.so3_exp(rng.standard_normal(3)), np.ones(batch))
    p = rng.standard_normal((3, *batch))
    body = lie.world_jacobian_to("body", J, R, p)
    space = lie.world_jacobian_to("space", J, R, p)
    for index in np.ndindex(*batch):
        at = (slice(None), slice(None), *index)
        Ri, Ji = R[at], J[at]
        T = lie.make_pose(Ri, p[(slice(None), *index)])
        # world (ṗ, ω) → body (Rᵀṗ, Rᵀω) → space = Ad_T body.
        expected_body = np.vstack((Ri.T @ Ji[:3], Ri.T @ Ji[3:]))
        np.testing.assert_allclose(body[at], expected_body, atol=1e-12)
        np.testing.assert_allclose(space[at], lie.adjoint(T) @ expected_body, atol=1e-12)
    np.testing.assert_array_equal(lie.world_jacobian_to("world", J, R, p), J)
    for reference, expected in (("body", body), ("space", space)):
        in_place = J.copy()
        lie.world_jacobian_to(reference, in_place, R, p, out=in_place)
        np.testing.assert_allclose(in_place, expected, atol=1e-15)
    with pytest.raises(InvalidInput, match="reference"):
        lie.world_jacobian_to("hybrid", J, R, p)


def test_poses_form_a_group_and_the_adjoint_is_a_homomorphism(rng):
    for _ in range(50):
        T_1, T_2, T_3 = random_pose(rng), random_pose(rng), random_pose(rng)
        product = T_1 @ T_2
        R = product[:3, :3]
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-14)  # closure
        np.testing.assert_array_equal(product[3], [0, 0, 0, 1])
        np.testing.assert_allclose((T_1 @ T_2) @ T_3, T_1 @ (T_2 @ T_3), atol=1e-14)
        np.testing.assert_allclose(lie.inverse(T_1) @ T_1, np.eye(4), atol=1e-14)
        np.testing.assert_allclose(T_1 @ lie.inverse(T_1), np.eye(4), atol=1e-14)
        np.testing.assert_allclose(
            lie.inverse(product), lie.inverse(T_2) @ lie.inverse(T_1), atol=1e-13
        )
        np.testing.assert_allclose(
            lie.adjoint(product), lie.adjoint(T_1) @ lie.adjoint(T_2), atol=1e-12
        )
        np.testing.assert_allclose(
            lie.adjoint(lie.inverse(T_1)), np.linalg.inv(lie.adjoint(T_1)), atol=1e-12
        )
        xi = rng.normal(size=6)
        np.testing.assert_allclose(lie.se3_exp(xi) @ lie.se3_exp(-xi), np.eye(4), atol=1e-13)
    np.testing.assert_array_equal(lie.se3_exp(np.zeros(6)), np.eye(4))
    np.testing.assert_array_equal(lie.se3_log(np.eye(4)), np.zeros(6))


def test_exp_is_the_flow_of_its_twist_by_finite_differences(rng):
    # d/dt exp(tξ) = exp(tξ) [ξ] (MR §3.3.3): the body twist of the flow is ξ at every t.
    h = 1e-6
    for _ in range(20):
        xi = rng.normal(size=6)
        t = rng.uniform(-1, 1)
        derivative = (lie.se3_exp((t + h) * xi) - lie.se3_exp((t - h) * xi)) / (2 * h)
        twist_matrix = lie.inverse(lie.se3_exp(t * xi)) @ derivative
        np.testing.assert_allclose(twist_matrix[:3, 3], xi[:3], atol=1e-8)
        np.testing.assert_allclose(twist_matrix[:3, :3], lie.skew(xi[3:]), atol=1e-8)


@pytest.mark.parametrize("angle", [1e-5, 0.3, 1.5, 3.0])
def test_left_jacobian_inverse_is_the_derivative_of_log_by_finite_differences(angle, rng):
    # log(exp(εδ) exp(ξ)) = ξ + ε J_l⁻¹(ξ) δ + O(ε²) (Barfoot §7.1.5), on SE(3) and SO(3).
    h = 1e-6
    xi = rng.normal(size=6)
    xi[3:] *= angle / np.linalg.norm(xi[3:])
    T = lie.se3_exp(xi)
    for delta in np.eye(6):
        plus, minus = (
            lie.se3_log(lie.se3_exp(h * delta) @ T),
            lie.se3_log(lie.se3_exp(-h * delta) @ T),
        )
        np.testing.assert_allclose(
            (plus - minus) / (2 * h), lie.se3_left_jacobian_inverse(xi) @ delta, atol=2e-7
        )
    R = T[:3, :3]
    for delta in np.eye(3):
        plus, minus = (
            lie.so3_log(lie.so3_exp(h * delta) @ R),
            lie.so3_log(lie.so3_exp(-h * delta) @ R),
        )
        np.testing.assert_allclose(
            (plus - minus) / (2 * h), lie.so3_left_jacobian_inverse(xi[3:]) @ delta, atol=2e-7
        )
