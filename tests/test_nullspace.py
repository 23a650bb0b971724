"""Null-space projection and secondary-criterion gradients (redik.solvers.redundancy.nullspace)."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.solvers.redundancy import (
    JointLimitMargin,
    Manipulability,
    PostureDistance,
    gradient_projection_ik,
    jacobian_derivatives,
    joint_limit_distance,
    joint_limit_distance_gradient,
    joint_limit_margin,
    joint_limit_margin_gradient,
    manipulability,
    manipulability_gradient,
    nullspace_basis,
    nullspace_projector,
    nullspace_velocity,
    posture_gradient,
    pseudo_inverse,
)


@pytest.fixture(scope="module")
def panda() -> redik.Robot:
    return redik.load("panda")


def world_jacobian(robot: redik.Robot, q: np.ndarray) -> np.ndarray:
    return robot.jacobian(q, reference="world")


def central_difference(f, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    columns = []
    for k in range(len(q)):
        dq = np.zeros_like(q)
        dq[k] = h
        columns.append((np.asarray(f(q + dq)) - np.asarray(f(q - dq))) / (2 * h))
    return np.stack(columns, axis=-1)


def test_projector_is_the_orthogonal_projector_onto_the_kernel(panda, rng):
    J = panda.jacobian(panda.random_q(rng), reference="body")
    P = nullspace_projector(J)
    assert np.allclose(J @ P, 0.0, atol=1e-12)
    assert np.allclose(P @ P, P, atol=1e-12)
    assert np.allclose(P, P.T, atol=1e-12)
    assert np.isclose(np.trace(P), 1.0)  # rank 6 of 7: a one-dimensional kernel


def test_nullspace_basis_is_orthonormal_and_spans_the_kernel(rng):
    dexter = redik.load("dexter8r")
    J = dexter.jacobian(dexter.random_q(rng), reference="body")
    N = nullspace_basis(J)
    assert N.shape == (8, 2)
    assert np.allclose(N.T @ N, np.eye(2), atol=1e-12)
    assert np.allclose(J @ N, 0.0, atol=1e-12)
    assert np.allclose(N @ N.T, nullspace_projector(J), atol=1e-10)


def test_nullspace_velocity_meets_the_task_and_projects_the_secondary_velocity(panda, rng):
    J = panda.jacobian(panda.random_q(rng), reference="body")
    twist = rng.normal(size=6)
    dq0 = rng.normal(size=7)
    dq = nullspace_velocity(J, twist, dq0)
    assert np.allclose(J @ dq, twist, atol=1e-10)
    # The secondary part is dq0 projected: the closest task-neutral velocity to dq0.
    secondary = dq - nullspace_velocity(J, twist)
    assert np.allclose(secondary, nullspace_projector(J) @ dq0, atol=1e-10)
    assert np.allclose(J @ secondary, 0.0, atol=1e-10)


def test_damped_pseudo_inverse_tends_to_the_exact_one(panda, rng):
    J = panda.jacobian(panda.random_q(rng), reference="body")
    assert np.allclose(pseudo_inverse(J, damping=1e-7), pseudo_inverse(J), atol=1e-8)
    # Damping bounds the response along a near-singular direction.
    assert np.linalg.norm(pseudo_inverse(J, damping=0.5)) < np.linalg.norm(pseudo_inverse(J))


def test_nullspace_velocity_rejects_mismatched_shapes(panda):
    J = np.zeros((6, 7))
    with pytest.raises(redik.InvalidInput, match=r"twist must have shape \(6,\)"):
        nullspace_velocity(J, np.zeros(3))
    with pytest.raises(redik.InvalidInput, match=r"dq0 must have shape \(7,\)"):
        nullspace_velocity(J, np.zeros(6), np.zeros(6))


@pytest.mark.parametrize("scene", ["panda", "dexter8r", "fixture_arm"])
def test_jacobian_derivatives_match_finite_differences(scene, arm, rng):
    robot = arm if scene == "fixture_arm" else redik.load(scene)  # the fixture has a slide joint
    q = robot.random_q(rng)
    expected = central_difference(lambda x: world_jacobian(robot, x), q)  # 6 × n × n
    H = jacobian_derivatives(world_jacobian(robot, q))  # n × 6 × n, H[k] = ∂J/∂q_k
    assert np.allclose(np.moveaxis(H, 0, -1), expected, atol=1e-7)


@pytest.mark.parametrize("scene", ["panda", "dexter8r"])
def test_manipulability_gradient_matches_finite_differences(scene, rng):
    robot = redik.load(scene)
    q = robot.random_q(rng)
    numeric = central_difference(lambda x: manipulability(world_jacobian(robot, x)), q)
    analytic = manipulability_gradient(world_jacobian(robot, q))
    assert np.allclose(analytic, numeric, atol=1e-7 * max(1.0, np.abs(numeric).max()))


def test_joint_limit_gradients_match_finite_differences(panda, rng):
    q = panda.random_q(rng)
    lower, upper = panda.lower, panda.upper
    numeric = central_difference(lambda x: joint_limit_distance(x, lower, upper), q)
    assert np.allclose(joint_limit_distance_gradient(q, lower, upper), numeric, atol=1e-8)
    tau = 0.05

    def soft_min(x):
        m = np.concatenate([x - lower, upper - x])
        return -tau * np.log(np.sum(np.exp(-m / tau)))

    numeric = central_difference(soft_min, q)
    assert np.allclose(joint_limit_margin_gradient(q, lower, upper, tau), numeric, atol=1e-6)


def test_joint_limit_margin_is_the_distance_to_the_nearest_limit(panda):
    q = panda.home.copy()
    q[3] = panda.upper[3] - 0.01
    assert np.isclose(joint_limit_margin(q, panda.lower, panda.upper), 0.01)
    step = 1e-3 * joint_limit_margin_gradient(q, panda.lower, panda.upper)
    assert joint_limit_margin(q + step, panda.lower, panda.upper) > 0.01


def test_posture_gradient_wraps_unlimited_hinges():
    q = np.array([3.1, 0.5])
    nominal = np.array([-3.1, 0.0])
    wrapped = posture_gradient(q, nominal, periodic=np.array([True, False]))
    assert np.allclose(wrapped, [2 * np.pi - 6.2, -0.5])  # 3.1 is 0.083 rad short of -3.1
    assert np.allclose(posture_gradient(q, nominal), [-6.2, -0.5])


@pytest.mark.parametrize(
    "criterion", [Manipulability(), JointLimitMargin(), "posture"], ids=["manip", "limits", "pose"]
)
def test_gradient_projection_keeps_the_pose_and_improves_the_criterion(panda, criterion, rng):
    if criterion == "posture":
        criterion = PostureDistance(panda.home)
    q_start = panda.random_q(rng)  # home is symmetric: a stationary point of manipulability
    T = panda.fk(q_start)
    result = gradient_projection_ik(panda, T, q_start, criterion, max_iterations=400)
    assert result.position_error <= 1e-9 and result.rotation_error <= 1e-8
    J0, J1 = world_jacobian(panda, q_start), world_jacobian(panda, result.q)
    before = criterion.value(panda, q_start, J0)
    after = criterion.value(panda, result.q, J1)
    improved = after > before if criterion.maximize else after < before
    assert improved, (before, after)
    assert panda.within_limits(result.q)


def test_qp_priority_level_equals_the_nullspace_formula(panda, rng):
    """Unconstrained, a FrameTask at priority 0 and a PostureTask at priority 1 give the
    textbook step ``Δq = J⁺ẋ + (I − J⁺J) q̇₀`` with ``ẋ = −e``, ``q̇₀ = −e_posture``."""
    from redik.qp import Problem
    from redik.tasks import FrameTask
    from redik.tasks.kinematics import KinematicState
    from redik.tasks.posture_task import PostureTask

    q = panda.home + rng.normal(scale=0.05, size=7)
    target = panda.fk(panda.home)
    pose = FrameTask("ee", target=target, priority=0)
    posture = PostureTask(panda.home + rng.normal(scale=0.3, size=7), priority=1)
    problem = Problem(panda, [pose, posture], limits=[], damping=0.0)
    dq_qp = problem.step(q)

    state = KinematicState.for_robot(panda)
    state.update(q)
    e, J = pose.error_and_jacobian(state)
    e_posture, J_posture = posture.error_and_jacobian(state)
    assert np.allclose(J_posture, np.eye(7))
    dq_formula = nullspace_velocity(J, -pose.gain * e, -posture.gain * e_posture)
    # Equal up to the QP back-end's tolerance (~1e-6 here).
    assert np.allclose(dq_qp, dq_formula, atol=2e-5 * max(1.0, np.linalg.norm(dq_formula)))


def test_nullspace_basis_of_a_stack_is_each_basis(rng):
    J = rng.standard_normal((5, 6, 8))
    bases = nullspace_basis(J, 2)
    assert bases.shape == (5, 8, 2)
    for Ji, Ni in zip(J, bases, strict=True):
        np.testing.assert_allclose(np.abs(Ni), np.abs(nullspace_basis(Ji, 2)), atol=1e-12)
        np.testing.assert_allclose(Ji @ Ni, 0.0, atol=1e-12)


def test_damped_pseudo_inverse_is_the_damped_least_squares_step(panda, rng):
    # One formula, Jᵀ(JJᵀ + λ²I)⁻¹: as a matrix here, as a step in kinematics.dls.
    from redik.kinematics.dls import damped_step

    J = panda.jacobian(panda.random_q(rng))
    e = rng.standard_normal(6)
    for damping in (1e-3, 0.1, 1.0):
        step = damped_step(J[:, :, None], e[:, None], np.array([damping**2]))[:, 0]
        np.testing.assert_allclose(pseudo_inverse(J, damping) @ e, step, rtol=1e-10, atol=1e-12)
