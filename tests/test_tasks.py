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


# Two frames held together: RelativeFrameTask and EqualityConstraintTask

CLOSED_LOOPS = """
<mujoco model="two_arms">
  <compiler angle="radian"/>
  <worldbody>
    <body name="a1" pos="0 0 0.5">
      <joint name="a1" axis="0 0 1" range="-3 3"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.02"/>
      <body name="a2" pos="0.4 0 0">
        <joint name="a2" axis="0 1 0" range="-3 3"/>
        <joint name="a3" axis="1 0 0" range="-3 3"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.02"/>
        <site name="hand_a" pos="0.4 0 0" quat="0.9 0.1 0.2 0.3"/>
      </body>
    </body>
    <body name="b1" pos="1 0 0.5">
      <joint name="b1" axis="0 0 1" range="-3 3"/>
      <geom type="capsule" fromto="0 0 0 -0.4 0 0" size="0.02"/>
      <body name="b2" pos="-0.4 0 0">
        <joint name="b2" axis="1 0 0" range="-3 3"/>
        <joint name="b3" axis="0 1 0" range="-3 3"/>
        <geom type="capsule" fromto="0 0 0 -0.2 0 0" size="0.02"/>
        <site name="hand_b" pos="-0.2 0 0"/>
      </body>
    </body>
  </worldbody>
  <equality>
    <connect name="pin" body1="a2" body2="b2" anchor="0.4 0 0"/>
    <weld name="grip" body1="a2" body2="b2" relpose="0.1 0.2 0.3 0.8 0.2 0.1 0.3"
          anchor="0.05 0.02 0.01" torquescale="2"/>
    <connect name="sites" site1="hand_a" site2="hand_b"/>
    <weld name="site_grip" site1="hand_a" site2="hand_b"/>
    <weld name="to_world" body1="a2"/>
    <joint name="coupled" joint1="a1" joint2="b1"/>
  </equality>
</mujoco>
"""
HELD = ["pin", "grip", "sites", "site_grip", "to_world"]


@pytest.fixture(scope="module")
def loops() -> redik.Robot:
    import mujoco

    return redik.Robot(mujoco.MjModel.from_xml_string(CLOSED_LOOPS), joints="all")


def _finite_difference(task, robot, state, q, h=1e-6):
    J = np.empty((task.k, robot.dof))
    for k in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[k] = h
        state.update(robot.integrate(q, dq))
        plus = task.error_and_jacobian(state)[0]
        state.update(robot.integrate(q, -dq))
        J[:, k] = (plus - task.error_and_jacobian(state)[0]) / (2 * h)
    state.update(q)
    return J


def test_equality_constraint_task_is_mujocos_residual_and_its_jacobian(loops, rng):
    """The error is MuJoCo's own equality residual (efc_pos after mj_fwdPosition) and the
    Jacobian its efc_J, for body and site connects and welds and a weld to the world; the
    Jacobian is also the finite difference of the error."""
    import mujoco

    model = loops.model
    task = redik.EqualityConstraintTask(model, 1.0, HELD).bind(loops)
    assert task.k == 3 + 6 + 3 + 6 + 6
    state = KinematicState.for_robot(loops)
    data = mujoco.MjData(model)
    for _ in range(4):
        q = rng.uniform(-1.5, 1.5, loops.nq)
        state.update(q)
        e, J = task.error_and_jacobian(state)
        data.qpos[:] = loops.full_qpos(q)
        mujoco.mj_fwdPosition(model, data)
        rows = np.isin(data.efc_id, [0, 1, 2, 3, 4]) & (
            data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
        )
        np.testing.assert_allclose(e, data.efc_pos[rows], atol=1e-14)
        efc_J = data.efc_J.reshape(data.nefc, model.nv)[rows][:, loops.dof_indices]
        np.testing.assert_allclose(J, efc_J, atol=1e-13)
        np.testing.assert_allclose(J, _finite_difference(task, loops, state, q), atol=1e-8)


def test_equality_constraint_task_equals_minks_where_mink_works(loops, rng):
    """mink reads MuJoCo's constraint rows, which its Configuration builds on update."""
    model = loops.model
    theirs = mink.EqualityConstraintTask(model, cost=[1.0, 2.0], equalities=["grip", "pin"])
    ours = redik.EqualityConstraintTask(model, [1.0, 2.0], ["grip", "pin"]).bind(loops)
    np.testing.assert_array_equal(ours.cost, [2.0] * 3 + [1.0] * 6)  # rows in constraint order
    configuration = mink.Configuration(model)
    for _ in range(3):
        q = rng.uniform(-1.5, 1.5, loops.nq)
        configuration.update(loops.full_qpos(q))
        for method, atol in (("compute_error", 1e-14), ("compute_jacobian", 1e-13)):
            np.testing.assert_allclose(
                getattr(ours, method)(configuration), getattr(theirs, method)(configuration),
                atol=atol,
            )  # fmt: skip
        np.testing.assert_array_equal(ours.cost, theirs.cost)


def test_equality_constraint_task_refuses_what_it_cannot_hold(loops):
    model = loops.model
    with pytest.raises(InvalidInput, match="'coupled' is a mjEQ_JOINT"):
        redik.EqualityConstraintTask(model)  # every constraint, the joint coupling among them
    with pytest.raises(InvalidInput, match="no equality constraint named 'nope'"):
        redik.EqualityConstraintTask(model, 1.0, ["nope"])
    with pytest.raises(InvalidInput, match=r"must be in \[0, 6\), got 9"):
        redik.EqualityConstraintTask(model, 1.0, [9])
    with pytest.raises(InvalidInput, match="twice"):
        redik.EqualityConstraintTask(model, 1.0, ["pin", 0])
    with pytest.raises(InvalidInput, match="cost"):
        redik.EqualityConstraintTask(model, [1.0, 2.0, 3.0], ["pin", "grip"])
    with pytest.raises(InvalidInput, match="MjModel"):
        redik.EqualityConstraintTask(loops, 1.0, ["pin"])
    panda = redik.load("panda")
    with pytest.raises(InvalidInput, match="another model"):
        redik.EqualityConstraintTask(model, 1.0, ["pin"]).bind(panda)


def test_relative_frame_task_is_minks_and_its_jacobian_the_finite_difference(loops, rng):
    T = lie.make_pose(lie.so3_exp(np.array([0.3, -0.2, 0.5])), np.array([0.1, 0.2, -0.3]))
    ours = redik.RelativeFrameTask("hand_a", "site", "b2", "body", 2.0, 0.5, target=T)
    ours.bind(loops)
    theirs = mink.RelativeFrameTask("hand_a", "site", "b2", "body", 2.0, 0.5)
    theirs.set_target(mink.SE3.from_matrix(T))
    np.testing.assert_array_equal(ours.cost, theirs.cost)
    configuration = mink.Configuration(loops.model)
    state = KinematicState.for_robot(loops)
    for _ in range(3):
        q = rng.uniform(-1.5, 1.5, loops.nq)
        configuration.update(loops.full_qpos(q))
        for method, atol in (("compute_error", 1e-13), ("compute_jacobian", 1e-12)):
            np.testing.assert_allclose(
                getattr(ours, method)(configuration), getattr(theirs, method)(configuration),
                atol=atol,
            )  # fmt: skip
        state.update(q)
        np.testing.assert_allclose(
            ours.error_and_jacobian(state)[1], _finite_difference(ours, loops, state, q), atol=1e-7
        )
    # Its target from a configuration, mink's way and redik's.
    q = rng.uniform(-1.0, 1.0, loops.nq)
    configuration.update(loops.full_qpos(q))
    ours.set_target_from_configuration(configuration)
    theirs.set_target_from_configuration(configuration)
    np.testing.assert_allclose(ours.target, theirs.transform_target_to_root.as_matrix(), atol=1e-12)
    ours.set_target_from_q(q)
    state.update(q)
    assert np.abs(ours.error_and_jacobian(state)[0]).max() < 1e-12
    assert ours.pose_errors(state) == pytest.approx((0.0, 0.0), abs=1e-9)


def test_relative_frame_task_takes_minks_parameters_in_minks_order(loops):
    import inspect

    theirs = list(inspect.signature(mink.RelativeFrameTask).parameters)
    ours = list(inspect.signature(redik.RelativeFrameTask).parameters)
    assert ours[: len(theirs)] == theirs
    unset = redik.RelativeFrameTask("hand_a", None, "b2", None).bind(loops)
    with pytest.raises(redik.TargetNotSet, match="set_target"):
        unset.objective_value(KinematicState.for_robot(loops))
    with pytest.raises(InvalidInput, match="root_type"):
        redik.RelativeFrameTask("hand_a", "site", "b2", "joint")


def test_a_closed_loop_is_held_exactly_at_priority_0_while_a_lower_level_moves(loops, rng):
    """The pin (a connect) at priority 0, from a configuration that holds it; a hand moved
    at priority 1: the driver meets the pin to round-off and moves the hand within the loop."""
    import mujoco

    model = mujoco.MjModel.from_xml_string(CLOSED_LOOPS)
    robot = redik.Robot(model, joints="all")
    q_held = rng.uniform(-1.0, 1.0, robot.nq)
    # The pin's anchor on b2 set where a2's anchor is at q_held: the loop closes there.
    data = mujoco.MjData(model)
    data.qpos[:] = robot.full_qpos(q_held)
    mujoco.mj_kinematics(model, data)
    pin = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, "pin")
    a2, b2 = model.eq_obj1id[pin], model.eq_obj2id[pin]
    point = data.xpos[a2] + data.xmat[a2].reshape(3, 3) @ model.eq_data[pin, :3]
    model.eq_data[pin, 3:6] = data.xmat[b2].reshape(3, 3).T @ (point - data.xpos[b2])
    hold = redik.EqualityConstraintTask(model, 1.0, ["pin"])
    target = robot.fk(q_held, "hand_b")[:3, 3] + [0.0, 0.0, 0.02]
    move = redik.PositionTask("hand_b", target=target, priority=1)
    result = redik.solve_problem(redik.Problem(robot, [hold, move]), q_held)
    assert result.success and result.error < 1e-9, result.message
    state = KinematicState.for_robot(robot)
    state.update(result.q)
    assert np.abs(hold.error_and_jacobian(state)[0]).max() < 1e-9
    start = np.linalg.norm(robot.fk(q_held, "hand_b")[:3, 3] - target)
    assert np.linalg.norm(robot.fk(result.q, "hand_b")[:3, 3] - target) < 0.5 * start
