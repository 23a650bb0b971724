"""Cartesian paths, and IK along them: continuous, warm-started, with events reported."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import redik
from redik.apps.trajectory import CartesianPath, follow_path, joint_steps, time_scaling
from redik.lie import make_pose, pose_errors, rotation_angle, so3_exp


def pose(rotation_vector, position) -> np.ndarray:
    return make_pose(so3_exp(np.asarray(rotation_vector, float)), np.asarray(position, float))


@pytest.mark.parametrize("kind", ["linear", "cubic", "quintic"])
def test_time_scalings_go_from_0_to_1_monotonically(kind):
    tau = np.linspace(0.0, 1.0, 101)
    s = np.array([time_scaling(t, kind) for t in tau])
    assert s[0] == 0.0 and s[-1] == pytest.approx(1.0)
    assert np.all(np.diff(s) >= 0.0)


@pytest.mark.parametrize("kind", ["cubic", "quintic"])
def test_smooth_scalings_start_and_end_at_rest(kind):
    h = 1e-6
    assert time_scaling(h, kind) / h < 1e-4
    assert (1.0 - time_scaling(1.0 - h, kind)) / h < 1e-4


def test_path_passes_through_its_waypoints_at_their_times():
    poses = [pose([0, 0, 0], [0.4, 0, 0.5]), pose([0.3, -0.2, 0.5], [0.5, 0.1, 0.4]),
             pose([0.1, 0.4, 1.0], [0.3, 0.2, 0.6])]  # fmt: skip
    path = CartesianPath(poses, [0.0, 0.7, 2.0], time_scaling="cubic")
    assert path.duration == pytest.approx(2.0)
    for t, T in zip(path.times, poses, strict=True):
        assert np.allclose(path.pose(t), T, atol=1e-12)
    assert np.allclose(path.pose(-1.0), poses[0]) and np.allclose(path.pose(5.0), poses[-1])


def test_linear_segment_has_constant_speed_and_a_single_rotation_axis():
    T_a, T_b = pose([0, 0, 0], [0.4, 0.0, 0.5]), pose([0.0, 0.6, 0.8], [0.6, 0.2, 0.3])
    path = CartesianPath([T_a, T_b], [0.0, 1.0], time_scaling="linear")
    times, samples = path.sample(rate=50.0)
    assert len(times) == 51 and times[-1] == pytest.approx(1.0)
    steps = np.array([pose_errors(a, b) for a, b in itertools.pairwise(samples)])
    total_p, total_r = pose_errors(T_a, T_b)
    assert np.allclose(steps[:, 0], total_p / 50, rtol=1e-9)
    assert np.allclose(steps[:, 1], total_r / 50, rtol=1e-6)
    # positions on the segment, orientations on the geodesic: angle(a, t) + angle(t, b) = total
    for T in samples:
        p = T[:3, 3]
        assert np.linalg.norm(np.cross(p - T_a[:3, 3], T_b[:3, 3] - T_a[:3, 3])) < 1e-12
        detour = rotation_angle(T_a[:3, :3], T[:3, :3]) + rotation_angle(T[:3, :3], T_b[:3, :3])
        assert detour == pytest.approx(total_r, abs=1e-9)


@pytest.mark.parametrize(
    ("poses", "times", "scaling", "match"),
    [
        ([np.eye(4)], None, "linear", "at least two"),
        ([np.eye(4), np.eye(4)], [0.0, 0.0], "linear", "increase"),
        ([np.eye(4), np.eye(4)], [0.0], "linear", "one per pose"),
        ([np.eye(4), np.eye(4)], None, "cubicle", "time_scaling"),
        ([np.eye(4), 2 * np.eye(4)], None, "linear", "poses\\[1\\]"),
    ],
)
def test_bad_paths_are_rejected(poses, times, scaling, match):
    with pytest.raises(redik.InvalidInput, match=match):
        CartesianPath(poses, times, scaling)


def test_joint_steps_is_the_largest_change_per_step():
    q = np.array([[0.0, 0.0], [0.1, -0.3], [0.1, -0.2]])
    assert np.allclose(joint_steps(q), [0.3, 0.1])


@pytest.mark.parametrize("scene", ["panda", "iiwa14", "ur5e"])
def test_smooth_path_gives_a_continuous_trajectory_in_few_iterations(scene):
    robot = redik.load(scene)
    T0 = robot.fk(robot.home)
    T1 = T0 @ pose([0.2, -0.3, 0.25], [0.08, -0.06, 0.05])
    T2 = T0 @ pose([-0.2, 0.1, -0.3], [-0.05, 0.08, 0.1])
    path = CartesianPath([T0, T1, T2], [0.0, 1.0, 2.0], time_scaling="quintic")
    trajectory = follow_path(robot, path, robot.home, rate=100.0)
    assert trajectory.q.shape == (201, robot.dof)
    assert trajectory.success.all()
    assert trajectory.position_error.max() <= 1e-6 and trajectory.rotation_error.max() <= 1e-5
    assert trajectory.continuous and trajectory.max_joint_step < 0.02
    assert trajectory.mean_iterations <= 2.0
    assert not trajectory.singular_crossings
    assert all(robot.within_limits(q) for q in trajectory.q)
    assert np.allclose(trajectory.velocities[0], 0.0, atol=0.05)  # quintic: starts at rest


def replaying(joint_path: np.ndarray):
    """A "solver" that replays a known joint path, to test the checks in isolation."""
    answers = iter(joint_path)

    def solver(T, q):
        return redik.core.result.IKResult(q=next(answers), success=True, status="converged",
                                     iterations=0, error=0.0)  # fmt: skip

    return solver


def test_a_qp_stack_can_follow_the_path_too():
    from redik.qp import Problem
    from redik.tasks import FrameTask, PostureTask

    robot = redik.load("panda")
    T0 = robot.fk(robot.home)
    path = CartesianPath.line(T0, T0 @ pose([0.0, 0.2, 0.0], [0.1, 0.0, -0.05]), 1.0)
    task = FrameTask("ee", target=T0)
    problem = Problem(robot, [task, PostureTask(robot.home, cost=1e-2, priority=1)])

    def qp(T, q):
        task.set_target(T)
        return redik.solve_problem(problem, q)

    trajectory = follow_path(robot, path, robot.home, qp, rate=50.0)
    assert trajectory.success.all() and trajectory.continuous
    assert trajectory.position_error.max() <= 1e-6
    assert trajectory.mean_iterations <= 3.0


def test_singular_crossing_and_limit_contact_are_reported():
    robot = redik.load("ur5e")
    # the wrist passes q5 = 0, where the axes of joints 4 and 6 align (UR wrist singularity)
    q_a = np.array([0.0, -1.2, 1.5, -1.9, 0.4, 0.0])
    q_b = q_a.copy()
    q_b[4] = -0.4
    qs = np.linspace(q_a, q_b, 81)
    path = CartesianPath([robot.fk(q_a), robot.fk(q_b)], [0.0, 0.8])
    trajectory = follow_path(robot, path, q_a, replaying(qs), rate=100.0, singular_tol=0.01)
    assert len(trajectory.singular_crossings) == 1
    crossing = trajectory.singular_crossings[0]
    assert crossing.start < 40 < crossing.end and crossing.value < 1e-9
    assert trajectory.sigma_min[0] > 0.05
    assert not trajectory.limit_contacts
    near_limit = q_a.copy()
    near_limit[2] = robot.upper[2] - 0.0005
    touching = follow_path(robot, path, near_limit, replaying([near_limit] * 81), rate=100.0)
    assert [event.label for event in touching.limit_contacts] == [f"{robot.joint_names[2]} upper"]
    assert touching.limit_contacts[0].value == pytest.approx(0.0005)
    assert (touching.limit_contacts[0].start, touching.limit_contacts[0].end) == (0, 80)


def test_branch_switch_is_flagged_as_discontinuous():
    robot = redik.load("planar_2r")
    elbow_up, elbow_down = np.array([0.3, 1.0]), np.array([1.3, -1.0])  # same point, two branches
    assert np.allclose(robot.fk(elbow_up)[:2, 3], robot.fk(elbow_down)[:2, 3])
    path = CartesianPath([robot.fk(elbow_up), robot.fk(elbow_up)], [0.0, 0.1])
    switching = replaying([elbow_up] * 5 + [elbow_down] * 6)
    trajectory = follow_path(robot, path, elbow_up, switching, rate=100.0)
    assert not trajectory.continuous
    assert trajectory.discontinuities.tolist() == [4]


def test_a_qp_stack_follows_the_path_alike_after_a_simulation():
    import warnings

    from redik.apps.sim import TrackingWarning, simulate
    from redik.limits import AccelerationLimit, ConfigurationLimit, VelocityLimit
    from redik.qp import Problem
    from redik.tasks import FrameTask, PostureTask

    # solve() looks for a static solution: an acceleration limit has no meaning between its
    # iterates, and the motion a simulation leaves in the problem must not leak into it.
    robot = redik.load("iiwa14")
    T0 = robot.fk(robot.home)
    path = CartesianPath.line(T0, T0 @ pose([0.0, 0.2, 0.0], [0.1, 0.0, -0.05]), 1.0)

    def stack(*extra):
        task = FrameTask("ee", target=T0)
        posture = PostureTask(robot.home, cost=1e-2, priority=1)
        limits = [ConfigurationLimit(), VelocityLimit(2.0), *extra]
        # The general path for all three (an acceleration limit takes it anyway), so that
        # the answers can be compared bit for bit.
        problem = Problem(robot, [task, posture], limits, compiled=False)
        return (
            problem,
            task,
            lambda T, q: (
                task.set_target(T),
                redik.solve_problem(problem, q, redik.SolveOptions(dt=0.01)),
            )[1],
        )

    problem, task, qp = stack(AccelerationLimit(20.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TrackingWarning)
        simulate(robot, problem, task, path, 0.5, control_rate=100.0)
    assert np.abs(problem.limits[-1].velocity).max() > 0.1  # the simulation left it moving
    after = follow_path(robot, path, robot.home, qp, rate=20.0)
    fresh = follow_path(robot, path, robot.home, stack(AccelerationLimit(20.0))[2], rate=20.0)
    unlimited = follow_path(robot, path, robot.home, stack()[2], rate=20.0)
    np.testing.assert_array_equal(after.q, fresh.q)
    np.testing.assert_array_equal(fresh.q, unlimited.q)
    assert fresh.success.all() and fresh.position_error.max() <= 1e-6
