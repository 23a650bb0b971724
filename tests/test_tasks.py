"""Tasks: every Jacobian and gradient against finite differences, the Lie Jacobians, inputs."""

from __future__ import annotations

import math

import mink
import numpy as np
import pytest

import redik
from redik import lie
from redik.core.exceptions import InvalidInput, InvalidPose
from redik.tasks import (
    DampingTask,
    FrameTask,
    JointLimitAvoidanceTask,
    KinematicState,
    ManipulabilityTask,
    OrientationTask,
    PositionTask,
    PostureTask,
)

H = 1e-6  # central differences: truncation O(h²) ≈ 1e-12, rounding ≈ 1e-10


def state_at(robot: redik.Robot, q: np.ndarray) -> KinematicState:
    state = KinematicState.for_robot(robot)
    state.update(q)
    return state


def numeric_jacobian(task, robot: redik.Robot, q: np.ndarray) -> np.ndarray:
    columns = []
    for i in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[i] = H
        e_plus, _ = task.error_and_jacobian(state_at(robot, q + dq))
        e_minus, _ = task.error_and_jacobian(state_at(robot, q - dq))
        columns.append((e_plus - e_minus) / (2 * H))
    return np.array(columns).T


def frame_tasks(robot: redik.Robot, rng: np.random.Generator) -> list:
    T = robot.fk(robot.random_q(rng))
    return [
        FrameTask("ee", target=T),
        PositionTask("ee", target=T[:3, 3]),
        OrientationTask("ee", target=T[:3, :3]),
        FrameTask(robot.ee.name, target=T, position_cost=[1, 2, 3], orientation_cost=0.5),
    ]


@pytest.mark.parametrize("robot_name", ["arm", "panda"])
def test_every_residual_jacobian_matches_finite_differences(robot_name, arm, rng):
    robot = arm if robot_name == "arm" else redik.load("panda")
    tasks = [
        *frame_tasks(robot, rng),
        PostureTask(robot.random_q(rng), cost=0.3),
        JointLimitAvoidanceTask(cost=2.0),
    ]
    for task in tasks:
        task.bind(robot)
        for _ in range(3):
            q = robot.random_q(rng)
            _, J = task.error_and_jacobian(state_at(robot, q))
            np.testing.assert_allclose(J, numeric_jacobian(task, robot, q), atol=2e-8)


def test_pose_error_is_the_body_twist_of_the_conventions(rng):
    robot = redik.load("panda")
    T_d = robot.fk(robot.random_q(rng))
    task = FrameTask("ee", target=T_d).bind(robot)
    q = robot.random_q(rng)
    e, _ = task.error_and_jacobian(state_at(robot, q))
    np.testing.assert_allclose(e, lie.body_error_twist(robot.fk(q), T_d), atol=1e-12)
    p_err, r_err = task.pose_errors(state_at(robot, q))
    assert (p_err, r_err) == pytest.approx(lie.pose_errors(robot.fk(q), T_d), abs=1e-12)


def test_frame_task_matches_minks_frame_task(rng):
    robot = redik.load("panda")
    for _ in range(5):
        T = robot.fk(robot.random_q(rng))
        q = robot.random_q(rng)
        task = FrameTask("ee", target=T).bind(robot)
        e, J = task.error_and_jacobian(state_at(robot, q))
        configuration = mink.Configuration(robot.model, robot.full_qpos(q))
        frame = mink.FrameTask("ee", "site", 1.0, 1.0)
        frame.set_target(mink.SE3.from_matrix(T))
        np.testing.assert_allclose(e, frame.compute_error(configuration), atol=1e-12)
        J_mink = frame.compute_jacobian(configuration)[:, robot.dof_indices]
        np.testing.assert_allclose(J, J_mink, atol=1e-10)


def test_joint_limit_potential_gradient_and_hessian(arm, rng):
    task = JointLimitAvoidanceTask(cost=0.7, gain=0.5).bind(arm)
    q = arm.random_q(rng)
    gradient = np.array(
        [
            (task.value(q + H * np.eye(arm.dof)[i]) - task.value(q - H * np.eye(arm.dof)[i]))
            / (2 * H)
            for i in range(arm.dof)
        ]
    )
    np.testing.assert_allclose(task.gradient(q), gradient, atol=1e-8)
    hessian = np.array(
        [
            (task.gradient(q + H * np.eye(arm.dof)[i]) - task.gradient(q - H * np.eye(arm.dof)[i]))
            / (2 * H)
            for i in range(arm.dof)
        ]
    )
    np.testing.assert_allclose(task.hessian(), hessian, atol=1e-6)
    # The unlimited joint j4 carries no potential.
    assert task.gradient(q)[3] == 0.0 and task.hessian()[3, 3] == 0.0
    # In the QP: w² (½ Δqᵀ ∇²φ Δq + α ∇φᵀ Δq).
    Hq, c = np.zeros((arm.dof, arm.dof)), np.zeros(arm.dof)
    task.add_objective(state_at(arm, q), Hq, c)
    np.testing.assert_allclose(Hq, 0.49 * task.hessian(), atol=1e-14)
    np.testing.assert_allclose(c, 0.49 * 0.5 * task.gradient(q), atol=1e-14)


def manipulability(robot: redik.Robot, q: np.ndarray) -> float:
    J = robot.jacobian(q, reference="body")
    return math.sqrt(np.linalg.det(J @ J.T))


@pytest.mark.parametrize("robot_name", ["arm", "panda", "iiwa14"])
def test_manipulability_value_and_gradient(robot_name, arm, rng):
    robot = arm if robot_name == "arm" else redik.load(robot_name)
    task = ManipulabilityTask().bind(robot)
    for _ in range(3):
        q = robot.random_q(rng)
        w, gradient = task.value_and_gradient(state_at(robot, q))
        assert w == pytest.approx(manipulability(robot, q), rel=1e-10)
        numeric = np.array(
            [
                (
                    manipulability(robot, q + H * np.eye(robot.dof)[i])
                    - manipulability(robot, q - H * np.eye(robot.dof)[i])
                )
                / (2 * H)
                for i in range(robot.dof)
            ]
        )
        np.testing.assert_allclose(gradient, numeric, atol=1e-7 * max(1.0, np.abs(numeric).max()))


def test_manipulability_objective_is_a_gradient_step(rng):
    robot = redik.load("panda")
    task = ManipulabilityTask(cost=0.5, gain=0.2).bind(robot)
    q = robot.random_q(rng)
    state = state_at(robot, q)
    Hq, c = np.zeros((7, 7)), np.zeros(7)
    task.add_objective(state, Hq, c)
    _, gradient = task.value_and_gradient(state)
    # The minimiser of ½ w²‖Δq − α∇w‖² is α∇w.
    np.testing.assert_allclose(np.linalg.solve(Hq, -c), 0.2 * gradient, atol=1e-12)


def test_damping_task_objective(arm):
    task = DampingTask(cost=[1, 2, 3, 4, 5, 6, 7]).bind(arm)
    Hq, c = np.zeros((7, 7)), np.zeros(7)
    task.add_objective(state_at(arm, arm.home), Hq, c)
    np.testing.assert_allclose(Hq, np.diag(np.arange(1, 8) ** 2.0))
    np.testing.assert_array_equal(c, 0.0)


def test_posture_defaults_to_home_and_validates_length(arm):
    assert np.array_equal(PostureTask().bind(arm).q_nominal, arm.home)
    with pytest.raises(InvalidInput, match="q_nominal"):
        PostureTask(np.zeros(3)).bind(arm)


def test_bad_inputs_are_rejected_at_the_boundary(arm):
    T = arm.fk(arm.home)
    bad = T.copy()
    bad[:3, :3] *= 2.0
    with pytest.raises(InvalidPose):
        FrameTask("ee", target=bad)
    with pytest.raises(InvalidInput, match="position_cost"):
        FrameTask("ee", target=T, position_cost=-1.0)
    with pytest.raises(InvalidInput, match="orientation_cost"):
        FrameTask("ee", target=T, orientation_cost=[1.0, 2.0])
    with pytest.raises(InvalidInput, match="gain"):
        FrameTask("ee", target=T, gain=1.5)
    with pytest.raises(InvalidInput, match="priority"):
        FrameTask("ee", target=T, priority=-1)
    with pytest.raises(InvalidInput, match="target_position"):
        PositionTask("ee", target=[0.0, np.nan, 0.0])
    with pytest.raises(InvalidInput, match="JointLimitAvoidanceTask cost must be a scalar"):
        JointLimitAvoidanceTask(cost=np.ones(3)).bind(arm)
    with pytest.raises(redik.UnknownFrame):
        FrameTask("nowhere", target=T).bind(arm)
    with pytest.raises(InvalidInput, match="6 chain joints"):
        ManipulabilityTask().bind(redik.load("planar_3r"))


def test_targets_accept_mink_types_and_quaternions(arm):
    T = arm.fk(arm.home)
    assert np.allclose(FrameTask("ee", target=mink.SE3.from_matrix(T)).target, T)
    quat = lie.quat_from_matrix(T[:3, :3])
    assert np.allclose(OrientationTask("ee", target=quat).target, T[:3, :3])


def test_set_cost_is_seen_by_the_next_objective(rng):
    robot = redik.load("panda")
    task = FrameTask("ee", target=robot.fk(robot.random_q(rng))).bind(robot)
    state = state_at(robot, robot.home)
    A, b = np.empty((6, 7)), np.empty(6)
    task.weighted_residual_into(state, A, b)
    task.set_position_cost(2.0)
    task.set_orientation_cost(3.0)
    A2, b2 = np.empty((6, 7)), np.empty(6)
    task.weighted_residual_into(state, A2, b2)
    np.testing.assert_allclose(A2, A * np.array([2, 2, 2, 3, 3, 3])[:, None])
    np.testing.assert_allclose(b2, b * np.array([2, 2, 2, 3, 3, 3]))
