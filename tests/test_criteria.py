"""Secondary criteria (redik.criteria): finite differences, batches, and the formulas they replaced.

The ``_reference_*`` functions are the implementations the tasks and the null-space tools
carried before :mod:`redik.criteria` became the one home of this math; they stay here as
independent oracles (the manipulability one differentiates the *space* Jacobian by the Lie
bracket of screws, a different derivation from Haviland & Corke's world-Jacobian formula).
"""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik import criteria
from redik.tasks import JointLimitAvoidanceTask, KinematicState, ManipulabilityTask


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
# The former implementations, as oracles


def _reference_task_potential(q, lower, upper):
    """JointLimitAvoidanceTask.value/gradient before redik.criteria (flat robot)."""
    limited = np.isfinite(lower) & np.isfinite(upper)
    span = np.where(limited, upper - lower, 1.0)
    scale = np.where(limited & (span > 0.0), 1.0 / span, 0.0)
    middle = 0.5 * (np.where(limited, lower, 0.0) + np.where(limited, upper, 0.0))
    return float(np.sum((scale * (q - middle)) ** 2)), 2.0 * scale**2 * (q - middle)


def _reference_joint_limit_distance(q, lower, upper):
    """redundancy.nullspace.joint_limit_distance(_gradient) before redik.criteria."""
    limited = np.isfinite(lower) & np.isfinite(upper)
    gradient = np.zeros_like(q)
    if not np.any(limited):
        return 0.0, gradient
    middle = 0.5 * (lower[limited] + upper[limited])
    width = upper[limited] - lower[limited]
    value = float(-0.5 * np.mean(((q[limited] - middle) / width) ** 2))
    gradient[limited] = -(q[limited] - middle) / (int(np.sum(limited)) * width**2)
    return value, gradient


def _reference_space_manipulability_gradient(J_world, p):
    """ManipulabilityTask.value_and_gradient before redik.criteria: ad_{S_k} S_i on the space
    Jacobian (Park & Kim 1998), ``p`` the frame's world position."""
    S = J_world.copy()
    S[:3] += np.cross(p, S[3:], axis=0)
    n = S.shape[1]
    JJt = S @ S.T
    w = float(np.sqrt(max(np.linalg.det(JJt), 0.0)))
    gradient = np.zeros(n)
    if w < 1e-12:
        return w, gradient
    M = np.linalg.solve(JJt, S).T
    for k in range(n - 1):
        omega, v = S[3:, k], S[:3, k]
        later = S[:, k + 1 :]
        d_v = np.cross(omega, later[:3], axis=0) - np.cross(later[3:], v, axis=0)
        d_omega = np.cross(omega, later[3:], axis=0)
        gradient[k] = np.sum(M[k + 1 :, :3] * d_v.T) + np.sum(M[k + 1 :, 3:] * d_omega.T)
    return w, w * gradient


def _reference_pinv_manipulability_gradient(J_world):
    """redundancy.nullspace.manipulability_gradient before redik.criteria (w · tr(J⁺ ∂J))."""
    w = float(np.sqrt(max(np.linalg.det(J_world @ J_world.T), 0.0)))
    if w == 0.0:
        return np.zeros(J_world.shape[1])
    return w * np.einsum(
        "ij,kji->k", np.linalg.pinv(J_world), criteria.jacobian_derivatives(J_world)
    )


# --------------------------------------------------------------------------------------
# Joint limits


def test_joint_limit_scaling_skips_unlimited_and_empty_ranges():
    lower = np.array([-1.0, -np.inf, 0.5, 0.0])
    upper = np.array([3.0, np.inf, 0.5, np.inf])
    scale, middle = criteria.joint_limit_scaling(lower, upper)
    np.testing.assert_allclose(scale, [0.25, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(middle, [1.0, 0.0, 0.5, 0.0])


def test_joint_limit_potential_matches_finite_differences_and_the_former_task(arm, rng):
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
        old_value, old_gradient = _reference_task_potential(q, arm.lower, arm.upper)
        assert value == pytest.approx(old_value, rel=1e-13)
        np.testing.assert_allclose(gradient, old_gradient, rtol=1e-13, atol=1e-15)
        task = JointLimitAvoidanceTask().bind(arm)
        assert task.value(q) == pytest.approx(old_value, rel=1e-13)
        np.testing.assert_allclose(task.gradient(q), old_gradient, rtol=1e-13, atol=1e-15)


def test_joint_limit_potential_is_batched(arm, rng):
    scale, middle = criteria.joint_limit_scaling(arm.lower, arm.upper)
    q = arm.random_q(rng, size=6) - middle
    batch = criteria.joint_limit_potential(q, scale)
    assert batch.shape == (6,)
    np.testing.assert_allclose(batch, [criteria.joint_limit_potential(x, scale) for x in q])


def test_joint_limit_distance_matches_finite_differences_and_the_former_one(panda, arm, rng):
    for robot in (panda, arm):
        q = robot.random_q(rng)
        value = criteria.joint_limit_distance(q, robot.lower, robot.upper)
        gradient = criteria.joint_limit_distance_gradient(q, robot.lower, robot.upper)
        numeric = central_difference(
            lambda x, r=robot: criteria.joint_limit_distance(x, r.lower, r.upper), q
        )
        np.testing.assert_allclose(gradient, numeric, atol=1e-8)
        old_value, old_gradient = _reference_joint_limit_distance(q, robot.lower, robot.upper)
        assert value == pytest.approx(old_value, rel=1e-13)
        np.testing.assert_allclose(gradient, old_gradient, rtol=1e-13, atol=1e-15)
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
def test_manipulability_gradient_matches_finite_differences_and_both_former_ones(name, rng):
    robot = redik.load(name)
    for _ in range(3):
        q = robot.random_q(rng)
        J = robot.jacobian(q, reference="world")
        gradient = criteria.manipulability_gradient(J)
        numeric = central_difference(
            lambda x: criteria.manipulability(robot.jacobian(x, reference="world")), q
        )
        np.testing.assert_allclose(gradient, numeric, atol=1e-7 * max(1.0, np.abs(numeric).max()))
        p = robot.fk(q)[:3, 3]
        old_w, old_space = _reference_space_manipulability_gradient(J, p)
        assert criteria.manipulability(J) == pytest.approx(old_w, rel=1e-10)
        np.testing.assert_allclose(gradient, old_space, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(
            gradient, _reference_pinv_manipulability_gradient(J), rtol=1e-9, atol=1e-12
        )


def test_manipulability_task_uses_the_shared_gradient(panda, rng):
    task = ManipulabilityTask().bind(panda)
    state = KinematicState.for_robot(panda)
    for _ in range(3):
        q = panda.random_q(rng)
        state.update(q)
        w, gradient = task.value_and_gradient(state)
        J = panda.jacobian(q, reference="world")
        assert w == pytest.approx(criteria.manipulability(J), rel=1e-12)
        np.testing.assert_allclose(gradient, criteria.manipulability_gradient(J), atol=1e-13)


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
