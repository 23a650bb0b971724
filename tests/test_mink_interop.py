"""mink interoperability: equal steps for equivalent stacks, tasks crossing both ways."""

from __future__ import annotations

import inspect

import mink
import numpy as np
import pytest

import redik
from redik.core.exceptions import InvalidInput
from redik.limits import ConfigurationLimit, MinkLimit
from redik.qp import Problem
from redik.qp.backends import QPSOLVERS_SETTINGS
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

DAMPING = 1e-6


def mink_step(robot, q, tasks, limits, solver="daqp"):
    configuration = mink.Configuration(robot.model, robot.full_qpos(q))
    # qpsolvers' ProxQP defaults stop at ~1e-5; ask for what redik asks of it.
    settings = QPSOLVERS_SETTINGS.get(solver, {})
    return mink.solve_ik(
        configuration, tasks, 1.0, solver, damping=DAMPING, limits=limits, **settings
    )


def targets(robot, rng, count):
    """Targets with rotation errors > 0.05 rad: mink's se3_jlog loses accuracy near 0."""
    out = []
    for _ in range(count):
        q = np.clip(robot.random_q(rng), robot.lower + 0.3, robot.upper - 0.3)
        out.append((q, robot.fk(np.clip(q + rng.uniform(-0.5, 0.5, robot.dof), robot.lower,
                                         robot.upper))))  # fmt: skip
    return out


@pytest.mark.parametrize("backend", ["daqp", "proxsuite", "quadprog"])
def test_weighted_stack_equals_mink_solve_ik(backend, rng):
    robot = redik.load("panda")
    solver = {"proxsuite": "proxqp"}.get(backend, backend)
    for q, T in targets(robot, rng, 5):
        q_nominal = robot.random_q(rng)
        redik_tasks = [
            FrameTask("ee", target=T, position_cost=[1, 2, 3], orientation_cost=0.5),
            PostureTask(q_nominal, cost=0.1, priority=0),
            JointLimitAvoidanceTask(cost=0.3, priority=0),
        ]
        problem = Problem(robot, redik_tasks, limits=[], backend=backend, damping=DAMPING)
        frame = mink.FrameTask("ee", "site", [1, 2, 3], 0.5)
        frame.set_target(mink.SE3.from_matrix(T))
        posture = mink.PostureTask(robot.model, cost=0.1)
        posture.set_target(robot.full_qpos(q_nominal))
        limit_avoidance = JointLimitAvoidanceTask(cost=0.3).bind(robot)  # a redik task in mink
        v = mink_step(robot, q, [frame, posture, limit_avoidance], limits=[], solver=solver)
        np.testing.assert_allclose(problem.step(q), v[robot.dof_indices], atol=1e-8)


def test_position_box_equals_minks_full_gain_configuration_limit(rng):
    robot = redik.load("panda")
    for q, T in targets(robot, rng, 5):
        problem = Problem(robot, [FrameTask("ee", target=T)], backend="daqp", damping=DAMPING)
        v = mink_step(robot, q, [_frame(T)], [mink.ConfigurationLimit(robot.model, gain=1.0)])
        # redik shrinks the box by daqp's 1e-9 tolerance; otherwise the QPs are the same.
        np.testing.assert_allclose(problem.step(q), v, atol=1e-8)


def _frame(T, name="ee", kind="site"):
    task = mink.FrameTask(name, kind, 1.0, 1.0)
    task.set_target(mink.SE3.from_matrix(T))
    return task


def test_mink_tasks_and_limits_inside_a_redik_problem_on_an_off_chain_model(arm, rng):
    # arm: nv = 14 with a free body and a gripper off the chain; mink tasks see all nv.
    for q, T in targets(arm, rng, 3):
        native = Problem(arm, [FrameTask("ee", target=T)], limits=[])
        with_mink = Problem(arm, [_frame(T)], limits=[])
        np.testing.assert_allclose(with_mink.step(q), native.step(q), atol=1e-10)
        mixed = Problem(arm, [_frame(T), PostureTask()], [ConfigurationLimit(),
                        MinkLimit(mink.ConfigurationLimit(arm.model))])  # fmt: skip
        assert mixed.step(q).shape == (arm.dof,)
    com = mink.ComTask(cost=1.0)
    com.set_target(np.array([0.3, -0.1, 0.4]))
    result = redik.solve_problem(
        Problem(arm, [com, PostureTask()]), arm.home, redik.SolveOptions(pos_tol=1e-3)
    )
    assert result.q.shape == (arm.dof,)


def test_redik_tasks_inside_mink_solve_ik_on_an_off_chain_model(arm, rng):
    q, T = targets(arm, rng, 1)[0]
    tasks = [FrameTask("ee", target=T).bind(arm), PositionTask("l5", target=T[:3, 3]).bind(arm)]
    v = mink_step(arm, q, tasks, limits=[])
    problem = Problem(arm, [FrameTask("ee", target=T), PositionTask("l5", target=T[:3, 3])],
                      limits=[], damping=DAMPING)  # fmt: skip
    np.testing.assert_allclose(v[arm.dof_indices], problem.step(q), atol=1e-8)
    off_chain = np.setdiff1d(np.arange(arm.model.nv), arm.dof_indices)
    np.testing.assert_allclose(v[off_chain], 0.0, atol=1e-12)


def test_an_unbound_redik_task_in_mink_says_what_to_do(arm):
    configuration = mink.Configuration(arm.model)
    with pytest.raises(InvalidInput, match=r"task.bind\(robot\)"):
        FrameTask("ee", target=np.eye(4)).compute_error(configuration)


def test_costs_are_set_with_minks_setters(rng):
    robot = redik.load("panda")
    T = robot.fk(robot.random_q(rng))
    pose = FrameTask("ee", target=T, position_cost=[1, 2, 3], orientation_cost=0.5)
    np.testing.assert_array_equal(pose.cost, [1, 2, 3, 0.5, 0.5, 0.5])
    pose.set_position_cost(4.0)
    pose.set_orientation_cost([1, 2, 3])
    np.testing.assert_array_equal(pose.cost, [4, 4, 4, 1, 2, 3])
    posture = PostureTask(robot.random_q(rng), cost=0.1).bind(robot)
    posture.set_cost(0.7)
    np.testing.assert_array_equal(posture.cost, np.full(7, 0.7))
    for task, cost in ((JointLimitAvoidanceTask(cost=0.3), 0.3), (DampingTask(cost=0.2), 0.2)):
        np.testing.assert_array_equal(task.bind(robot).cost, np.full(7, cost))
    manipulability = ManipulabilityTask(cost=0.4).bind(robot)
    np.testing.assert_array_equal(manipulability.cost, np.full(7, 0.4))


def test_mink_tasks_converge_on_their_cost_weighted_error():
    # A component of zero cost is no part of the target: the QP leaves it free, so the
    # unweighted error (the CoM height, the frame's rotation) never vanished and the solve
    # stalled instead of converging.
    robot = redik.load("panda")
    configuration = mink.Configuration(robot.model, robot.full_qpos(robot.home))
    com = mink.ComTask(cost=[1.0, 1.0, 0.0])
    target = configuration.data.subtree_com[1] + [0.03, -0.02, 0.3]  # 30 cm too high
    com.set_target(target)
    result = redik.solve_problem(Problem(robot, [com]), robot.home)
    assert result.status == "converged", result.message
    configuration.update(robot.full_qpos(result.q))
    reached = configuration.data.subtree_com[1]
    np.testing.assert_allclose(reached[:2], target[:2], atol=1e-6)
    assert abs(reached[2] - target[2]) > 0.1  # the height was not asked for
    frame = mink.FrameTask("ee", "site", position_cost=1.0, orientation_cost=0.0)
    T = robot.fk(robot.clip(robot.home + 0.2))
    frame.set_target(mink.SE3.from_matrix(T @ redik.lie.make_pose(redik.lie.so3_exp([0.3, 0, 0]),
                                                                  np.zeros(3))))  # fmt: skip
    result = redik.solve_problem(Problem(robot, [frame]), robot.home)
    assert result.status == "converged", result.message
    assert np.linalg.norm(robot.fk(result.q)[:3, 3] - T[:3, 3]) < 1e-6


def test_frame_task_takes_minks_parameters_in_minks_order():
    theirs = list(inspect.signature(mink.FrameTask).parameters)
    ours = list(inspect.signature(redik.FrameTask).parameters)
    assert ours[: len(theirs)] == theirs  # frame_name, frame_type, …, gain, lm_damping


def test_frame_task_is_minks_frame_task_built_with_minks_arguments(arm, rng):
    # The same arguments, positionally and by keyword, as mink.FrameTask takes.
    for q, T in targets(arm, rng, 3):
        ours = redik.FrameTask("ee", "site", [1.0, 2.0, 3.0], 0.5, gain=0.8)
        ours.set_target(mink.SE3.from_matrix(T))
        theirs = mink.FrameTask("ee", "site", [1.0, 2.0, 3.0], 0.5, gain=0.8)
        theirs.set_target(mink.SE3.from_matrix(T))
        configuration = mink.Configuration(arm.model, arm.full_qpos(q))
        ours.bind(arm)
        np.testing.assert_allclose(ours.compute_error(configuration),
                                   theirs.compute_error(configuration), atol=1e-12)  # fmt: skip
        np.testing.assert_allclose(ours.compute_jacobian(configuration),
                                   theirs.compute_jacobian(configuration), atol=1e-10)  # fmt: skip
        np.testing.assert_array_equal(ours.cost, theirs.cost)
        np.testing.assert_allclose(ours.transform_target_to_world.as_matrix(), T, atol=1e-15)
        # In a redik Problem it is a FrameTask.
        native_task = FrameTask("ee", position_cost=[1, 2, 3], orientation_cost=0.5, gain=0.8,
                                target=T)  # fmt: skip
        native = Problem(arm, [native_task], limits=[])
        mirrored = Problem(arm, [ours], limits=[])
        np.testing.assert_allclose(mirrored.step(q), native.step(q), atol=1e-12)


def test_frame_task_target_from_a_configuration_and_before_one_is_set(arm):
    configuration = mink.Configuration(arm.model, arm.full_qpos(arm.home))
    task = redik.FrameTask("l5", "body")
    assert task.transform_target_to_world is None
    with pytest.raises(redik.TargetNotSet, match=r"'l5' has no target: call set_target"):
        Problem(arm, [task]).step(arm.home)
    task.set_target_from_configuration(configuration)  # unbound: mink's lookup
    expected = configuration.get_transform_frame_to_world("l5", "body").as_matrix()
    np.testing.assert_allclose(task.target, expected, atol=1e-15)
    bound = redik.FrameTask("ee", "site").bind(arm)
    bound.set_target_from_configuration(configuration)  # bound: through the robot
    np.testing.assert_allclose(bound.target, arm.fk(arm.home, "ee"), atol=1e-15)
    with pytest.raises(InvalidInput, match="frame_type must be one of"):
        redik.FrameTask("ee", "joint")
    with pytest.raises(InvalidInput, match="lm_damping must be a finite number ≥ 0"):
        redik.FrameTask("ee", "site", lm_damping=-1.0)
    with pytest.raises(InvalidInput, match="frame_name must be the name of a site, body or geom"):
        redik.FrameTask(None, target=np.eye(4))  # type: ignore[arg-type]


def test_frame_task_defaults_look_the_frame_up_with_unit_costs(arm, rng):
    q, T = targets(arm, rng, 1)[0]
    short = redik.FrameTask("ee", target=T).bind(arm)
    full = redik.FrameTask("ee", "site", 1.0, 1.0, target=T).bind(arm)
    assert (short.frame.kind, short.frame.id) == (full.frame.kind, full.frame.id)
    assert short.frame_type is None
    np.testing.assert_array_equal(short.cost, np.ones(6))
    state = KinematicState.for_robot(arm)
    state.update(q)
    for ours, theirs in zip(short.error_and_jacobian(state), full.error_and_jacobian(state),
                            strict=True):  # fmt: skip
        np.testing.assert_array_equal(ours, theirs)


@pytest.mark.parametrize("make", [PositionTask, OrientationTask])
def test_position_and_orientation_tasks_take_the_frame_first_and_a_later_target(arm, make):
    task = make("l5", "body", 2.0)
    np.testing.assert_array_equal(task.cost, np.full(3, 2.0))
    with pytest.raises(redik.TargetNotSet, match=r"'l5' has no target: call set_target"):
        Problem(arm, [task]).step(arm.home)
    T = arm.fk(arm.home, "l5")
    task.set_target(T[:3, 3] if make is PositionTask else T[:3, :3])
    np.testing.assert_allclose(Problem(arm, [task], limits=[]).step(arm.home), 0.0, atol=1e-9)


@pytest.mark.parametrize("lm_damping", [0.0, 0.3])
def test_lm_damping_is_minks_in_mink_solve_ik_and_in_a_redik_problem(arm, rng, lm_damping):
    # mink adds μI to the Hessian, μ = λ‖α W e‖²: a damped step far from the target.
    for q, T in targets(arm, rng, 3):
        ours = redik.FrameTask("ee", "site", 1.0, 0.5, lm_damping=lm_damping, target=T)
        theirs = mink.FrameTask("ee", "site", 1.0, 0.5, lm_damping=lm_damping)
        theirs.set_target(mink.SE3.from_matrix(T))
        configuration = mink.Configuration(arm.model, arm.full_qpos(q))
        H, c = ours.bind(arm).compute_qp_objective(configuration)
        H_mink, c_mink = theirs.compute_qp_objective(configuration)
        np.testing.assert_allclose(H, H_mink, atol=1e-9)
        np.testing.assert_allclose(c, c_mink, atol=1e-9)
        v = mink_step(arm, q, [theirs], limits=[])
        problem = Problem(arm, [ours], limits=[], damping=DAMPING)
        np.testing.assert_allclose(problem.step(q), v[arm.dof_indices], atol=1e-8)
