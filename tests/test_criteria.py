"""Secondary criteria (redik.criteria): values at reference points, gradients against finite
differences, and batches."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik import criteria


def central_difference(f, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    columns = []
    for k in range(len(q)):
        dq = np.zeros_like(q)
        dq[k] = h
        columns.append((np.asarray(f(q + dq)) - np.asarray(f(q - dq))) / (2 * h))
    return np.stack(columns, axis=-1)


@pytest.fixture(scope="module")
def panda() -> redik.Robot:
    return redik.load("panda")


# --------------------------------------------------------------------------------------
# Joint limits


def test_joint_limit_scaling_skips_unlimited_and_empty_ranges():
    lower = np.array([-1.0, -np.inf, 0.5, 0.0])
    upper = np.array([3.0, np.inf, 0.5, np.inf])
    scale, middle = criteria.joint_limit_scaling(lower, upper)
    np.testing.assert_allclose(scale, [0.25, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(middle, [1.0, 0.0, 0.5, 0.0])


def test_joint_limit_potential_at_the_middle_and_the_limits():
    """φ = Σ((q − q̄)/(u − l))²: 0 in the middle of the ranges, ¼ per joint at a limit."""
    lower, upper = np.array([-1.0, 0.0, -2.0]), np.array([3.0, 1.0, 2.0])
    scale, middle = criteria.joint_limit_scaling(lower, upper)
    assert criteria.joint_limit_potential(np.zeros(3), scale) == 0.0
    assert criteria.joint_limit_potential(upper - middle, scale) == pytest.approx(0.75)
    assert criteria.joint_limit_potential(np.array([lower[0], 0.5, 0.0]) - middle, scale) == (
        pytest.approx(0.25)
    )
    np.testing.assert_allclose(
        criteria.joint_limit_potential_gradient(upper - middle, scale), 2.0 * scale * 0.5
    )


def test_joint_limit_potential_matches_finite_differences(arm, rng):
    scale, middle = criteria.joint_limit_scaling(arm.lower, arm.upper)
    for _ in range(5):
        q = arm.random_q(rng)
        value = criteria.joint_limit_potential(q - middle, scale)
        gradient = criteria.joint_limit_potential_gradient(q - middle, scale)
        numeric = central_difference(lambda x: criteria.joint_limit_potential(x - middle, scale), q)
        np.testing.assert_allclose(gradient, numeric, atol=1e-8)
        hessian = central_difference(
            lambda x: criteria.joint_limit_potential_gradient(x - middle, scale), q
        )
        np.testing.assert_allclose(
            criteria.joint_limit_potential_hessian(scale), hessian, atol=1e-6
        )
        assert value >= 0.0


def test_joint_limit_potential_is_batched(arm, rng):
    scale, middle = criteria.joint_limit_scaling(arm.lower, arm.upper)
    q = arm.random_q(rng, size=6) - middle
    batch = criteria.joint_limit_potential(q, scale)
    assert batch.shape == (6,)
    np.testing.assert_allclose(batch, [criteria.joint_limit_potential(x, scale) for x in q])


def test_joint_limit_distance_matches_finite_differences_and_eq_3_58(panda, arm, rng):
    """Siciliano et al. eq. 3.58: w = −(1/2n) Σ((q − q̄)/(u − l))², −1/8 with every joint of
    the n at a limit."""
    for robot in (panda, arm):
        q = robot.random_q(rng)
        gradient = criteria.joint_limit_distance_gradient(q, robot.lower, robot.upper)
        numeric = central_difference(
            lambda x, r=robot: criteria.joint_limit_distance(x, r.lower, r.upper), q
        )
        np.testing.assert_allclose(gradient, numeric, atol=1e-8)
    assert criteria.joint_limit_distance(panda.upper, panda.lower, panda.upper) == (
        pytest.approx(-0.125)
    )
    free = np.full(3, np.inf)
    assert criteria.joint_limit_distance(np.ones(3), -free, free) == 0.0
    np.testing.assert_array_equal(
        criteria.joint_limit_distance_gradient(np.ones(3), -free, free), 0
    )


def test_joint_limit_margin_is_batched_and_its_soft_gradient_ascends(panda, rng):
    q = panda.random_q(rng, size=5)
    margins = criteria.joint_limit_margin(q, panda.lower, panda.upper)
    assert margins.shape == (5,)
    for x, margin in zip(q, margins, strict=True):
        assert criteria.joint_limit_margin(x, panda.lower, panda.upper) == margin
        step = 1e-4 * criteria.joint_limit_margin_gradient(x, panda.lower, panda.upper)
        assert criteria.joint_limit_margin(x + step, panda.lower, panda.upper) > margin
    assert criteria.joint_limit_margin(np.zeros(2), np.full(2, -np.inf), np.full(2, np.inf)) == (
        np.inf
    )


# --------------------------------------------------------------------------------------
# Manipulability


@pytest.mark.parametrize("name", ["panda", "iiwa14", "dexter8r"])
def test_manipulability_gradient_matches_finite_differences(name, rng):
    robot = redik.load(name)
    for _ in range(3):
        q = robot.random_q(rng)
        J = robot.jacobian(q, reference="world")
        gradient = criteria.manipulability_gradient(J)
        numeric = central_difference(
            lambda x: criteria.manipulability(robot.jacobian(x, reference="world")), q
        )
        np.testing.assert_allclose(gradient, numeric, atol=1e-7 * max(1.0, np.abs(numeric).max()))


def test_manipulability_and_its_gradient_are_batched(panda, rng):
    q = panda.random_q(rng, size=4)
    J = np.array([panda.jacobian(x, reference="world") for x in q])
    J[2, :, 1:] = 0.0  # rank 1: singular, zero gradient
    values = criteria.manipulability(J)
    gradients = criteria.manipulability_gradient(J)
    assert values.shape == (4,) and gradients.shape == (4, 7)
    for k in range(4):
        assert values[k] == pytest.approx(criteria.manipulability(J[k]), abs=1e-15)
        np.testing.assert_allclose(gradients[k], criteria.manipulability_gradient(J[k]), atol=1e-14)
    np.testing.assert_array_equal(gradients[2], 0.0)
    derivatives = criteria.jacobian_derivatives(J)
    assert derivatives.shape == (4, 7, 6, 7)
    np.testing.assert_allclose(derivatives[1], criteria.jacobian_derivatives(J[1]), atol=0)


# --------------------------------------------------------------------------------------
# Posture


def test_posture_distance_and_gradient(rng):
    nominal = rng.uniform(-1, 1, size=4)
    periodic = np.array([True, False, True, False])
    q = rng.uniform(-4, 4, size=(3, 4))
    distances = criteria.posture_distance(q, nominal, periodic)
    assert distances.shape == (3,)
    for x, distance in zip(q, distances, strict=True):
        assert distance == pytest.approx(criteria.posture_distance(x, nominal, periodic))
        # Away from the wrap, −½‖δ‖² has the gradient −δ.
        numeric = central_difference(
            lambda y: -0.5 * criteria.posture_distance(y, nominal, periodic) ** 2, x
        )
        np.testing.assert_allclose(
            criteria.posture_gradient(x, nominal, periodic), numeric, atol=1e-7
        )
    wrapped = criteria.posture_difference(
        np.array([3.1, 0.5]), np.array([-3.1, 0.0]), [True, False]
    )
    np.testing.assert_allclose(wrapped, [6.2 - 2 * np.pi, 0.5])
