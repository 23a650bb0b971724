"""Headless closed-loop simulation: the QP drives MuJoCo's position servos along a path.

Stated bound (also in :mod:`redik.sim`): iiwa14 tracing a 10 cm circle in 4 s at 100 Hz
with the default ``command="integrate"`` stays within 3 mm and 0.01 rad of the reference
and ends within 0.05 mm.
"""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.limits import PositionLimit, VelocityLimit
from redik.problem import Problem
from redik.sim import actuator_indices, plot_tracking, servo_lead, simulate
from redik.tasks import PoseTask, PostureTask
from redik.trajectory import CircularPath

POSITION_BOUND, ROTATION_BOUND, FINAL_BOUND = 3e-3, 1e-2, 5e-5


def tracking_problem(robot):
    task = PoseTask(robot.fk(robot.home))
    posture = PostureTask(robot.home, weight=0.1, priority=1)
    limits = [PositionLimit(), VelocityLimit(2.0)]
    return Problem(robot, [task, posture], limits=limits), task


@pytest.fixture(scope="module")
def iiwa_circle():
    robot = redik.load("iiwa14")
    T0 = robot.fk(robot.home)
    path = CircularPath(
        T0, center=T0[:3, 3] + [0.0, 0.0, 0.1], normal=[1.0, 0.0, 0.0], duration=4.0
    )
    problem, task = tracking_problem(robot)
    return robot, path, simulate(robot, problem, task, path, control_rate=100.0)


def test_circle_path_keeps_radius_orientation_and_closes():
    robot = redik.load("iiwa14")
    T0 = robot.fk(robot.home)
    path = CircularPath(T0, T0[:3, 3] + [0.0, 0.0, 0.1], [1.0, 0.0, 0.0], duration=4.0)
    assert path.radius == pytest.approx(0.1)
    for t in np.linspace(0.0, 4.0, 17):
        T = path.pose(t)
        assert np.linalg.norm(T[:3, 3] - path.center) == pytest.approx(0.1)
        assert np.allclose(T[:3, :3], T0[:3, :3])
    assert np.allclose(path.pose(4.0), T0, atol=1e-12)


def test_tracking_error_stays_below_the_stated_bound(iiwa_circle):
    robot, path, result = iiwa_circle
    assert result.q.shape == (400, robot.dof)
    assert result.max_position_error < POSITION_BOUND, result.summary()
    assert result.max_rotation_error < ROTATION_BOUND, result.summary()
    assert result.final_position_error < FINAL_BOUND, result.summary()
    # the arm really moved around the circle (not a trivially small error on a still arm)
    reached = result.targets[:, :3, 3] - path.center
    assert np.ptp(reached[:, 1]) == pytest.approx(0.2, abs=1e-4)
    assert all(robot.within_limits(q) for q in result.q_command)


def test_recorded_state_reproduces_the_measured_pose(iiwa_circle):
    robot, _, result = iiwa_circle
    k = 200
    q = result.qpos[k, robot.qpos_indices]
    assert np.allclose(q, result.q[k])
    error = np.linalg.norm(robot.fk(q)[:3, 3] - result.targets[k, :3, 3])
    assert error == pytest.approx(result.position_error[k], abs=1e-12)


def test_feedforward_beats_plain_position_commands():
    robot = redik.load("iiwa14")
    T0 = robot.fk(robot.home)
    path = CircularPath(T0, T0[:3, 3] + [0.0, 0.0, 0.1], [1.0, 0.0, 0.0], duration=2.0)
    errors = {}
    for command in ("integrate", "position"):
        problem, task = tracking_problem(robot)
        result = simulate(robot, problem, task, path, control_rate=100.0, command=command)
        errors[command] = result.max_position_error
    assert errors["integrate"] < 0.5 * errors["position"], errors


def test_servo_lead_reads_kv_over_kp():
    robot = redik.load("panda")
    actuators = actuator_indices(robot)
    lead = servo_lead(robot.model, actuators)
    kp = robot.model.actuator_gainprm[actuators, 0]
    kv = -robot.model.actuator_biasprm[actuators, 2]
    assert np.allclose(lead, kv / kp) and np.all(lead > 0.0)


def test_tracking_plot_is_written(iiwa_circle, tmp_path):
    _, _, result = iiwa_circle
    path = plot_tracking(result, tmp_path / "tracking.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bad_arguments_are_rejected():
    robot = redik.load("planar_2r")
    problem, task = tracking_problem(robot)
    T = robot.fk(robot.home)
    with pytest.raises(redik.InvalidInput, match="command"):
        simulate(robot, problem, task, lambda t: T, 1.0, command="torque")
    with pytest.raises(redik.InvalidInput, match="duration"):
        simulate(robot, problem, task, lambda t: T)
    with pytest.raises(redik.InvalidInput, match="physics steps"):
        simulate(robot, problem, task, lambda t: T, 1.0, control_rate=300.0)


def test_a_joint_without_actuator_is_reported():
    xml = """<mujoco><worldbody><body><joint name="j" axis="0 0 1"/>
    <geom size="0.1"/><site name="ee" pos="0.2 0 0"/></body></worldbody></mujoco>"""
    robot = redik.Robot.from_xml_string(xml)
    with pytest.raises(redik.ModelError, match="no actuator"):
        actuator_indices(robot)
