"""Headless closed-loop simulation: the QP drives MuJoCo's servos and motors along a path.

Stated bound (also in ``specs/iiwa14_tracking.py``): iiwa14 tracing a 10 cm circle in 4 s at
100 Hz with the default ``command="integrate"`` stays within 3 mm and 0.01 rad of the
reference and ends within 0.05 mm. A run MuJoCo finds unstable stops with its status; a
floating base is refused unsupported and held on request; contacts are reported.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import mujoco
import numpy as np
import pytest

import redik
from redik.apps.sim import (
    InstabilityWarning,
    SimulationStatus,
    TrackingWarning,
    actuator_indices,
    joint_drives,
    plot_tracking,
    simulate,
)
from redik.apps.trajectory import CartesianPath, CircularPath
from redik.limits import ConfigurationLimit, VelocityLimit
from redik.qp import Problem
from redik.tasks import FrameTask, PostureTask

POSITION_BOUND, ROTATION_BOUND, FINAL_BOUND = 3e-3, 1e-2, 5e-5


def tracking_problem(robot, q0=None):
    q0 = robot.home if q0 is None else q0
    task = FrameTask(robot.ee.name, target=robot.fk(q0))
    posture = PostureTask(q0, cost=0.1, priority=1)
    limits = [ConfigurationLimit(), VelocityLimit(2.0)]
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
        result = simulate(
            robot, problem, task, path, control_rate=100.0, command=command, error_bound=None
        )
        errors[command] = result.max_position_error
    assert errors["integrate"] < 0.5 * errors["position"], errors


def test_servo_lead_reads_kv_over_kp():
    robot = redik.load("panda")
    drives = joint_drives(robot)
    kp = robot.model.actuator_gainprm[drives.actuators, 0]
    kv = -robot.model.actuator_biasprm[drives.actuators, 2]
    assert np.allclose(drives.lead, kv / kp) and np.all(drives.lead > 0.0)
    assert np.all(joint_drives(torque_iiwa14()).lead == 0.0)  # a motor has no lag to lead


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
    with pytest.raises(redik.InvalidInput, match="shorter than one control tick"):
        simulate(robot, problem, task, lambda t: T, 0.001)
    with pytest.raises(redik.InvalidInput, match="physics steps"):
        simulate(robot, problem, task, lambda t: T, 1.0, control_rate=300.0)
    with pytest.raises(redik.InvalidInput, match="error_bound"):
        simulate(robot, problem, task, lambda t: T, 1.0, error_bound=(0.0, 1.0))
    with pytest.raises(redik.InvalidInput, match="motor_bandwidth"):
        simulate(robot, problem, task, lambda t: T, 1.0, motor_bandwidth=-1.0)
    # Wrong types are refused by name, never a raw TypeError (nor a truthy string obeyed).
    for options, match in [
        ({"motor_bandwidth": "fast"}, "motor_bandwidth"),
        ({"control_rate": "100"}, "control_rate"),
        ({"error_bound": 5e-3}, "error_bound"),
        ({"error_bound": ("1 mm", 0.05)}, r"error_bound\[0\]"),
        ({"feedforward": "no"}, "feedforward"),
        ({"on_tick": 5}, "on_tick"),
    ]:
        with pytest.raises(redik.InvalidInput, match=match):
            simulate(robot, problem, task, lambda t: T, 1.0, **options)
    with pytest.raises(redik.InvalidInput, match="duration"):
        simulate(robot, problem, task, lambda t: T, "1 s")


def test_a_joint_without_actuator_is_reported():
    xml = """<mujoco><worldbody><body><joint name="j" axis="0 0 1"/>
    <geom size="0.1"/><site name="ee" pos="0.2 0 0"/></body></worldbody></mujoco>"""
    robot = redik.Robot.from_xml_string(xml)
    with pytest.raises(redik.ModelError, match="no actuator"):
        actuator_indices(robot)


# --------------------------------------------------------------------------------------
# Third-party actuation: servos without gravcomp, torque motors, actuators refused


def iiwa14_spec() -> mujoco.MjSpec:
    return mujoco.MjSpec.from_file(str(redik.models.scene_path("iiwa14")))


def menagerie_like_iiwa14(forcerange: float | None = None) -> redik.Robot:
    """The bundled iiwa14 with MuJoCo Menagerie's actuation: no gravcomp, every joint a
    ``general`` servo with kp = 2000, kv = 200 (Menagerie's iiwa14), gravity on."""
    spec = iiwa14_spec()
    for body in spec.bodies:
        body.gravcomp = 0.0
    for actuator in spec.actuators:
        actuator.gainprm[0] = 2000.0
        actuator.biasprm[:3] = [0.0, -2000.0, -200.0]
        if forcerange is not None:
            actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            actuator.forcerange = [-forcerange, forcerange]
    return redik.Robot(spec.compile(), name="iiwa14_menagerie_servos")


def circle(robot, q0, duration=4.0, radius=0.1):
    T0 = robot.fk(q0)
    return CircularPath(
        T0, center=T0[:3, 3] + [0.0, 0.0, radius], normal=[1.0, 0.0, 0.0], duration=duration
    )


def test_servos_without_gravcomp_track_within_the_bound():
    # Without the inverse-dynamics feed-forward the servos sag under gravity by g(q) / kp.
    robot = menagerie_like_iiwa14()
    problem, task = tracking_problem(robot)
    result = simulate(robot, problem, task, circle(robot, robot.home), control_rate=100.0)
    assert result.drives == ("position",) * 7
    assert result.max_position_error < POSITION_BOUND, result.summary()
    assert result.max_rotation_error < ROTATION_BOUND, result.summary()
    assert result.final_position_error < FINAL_BOUND, result.summary()
    assert result.reference_position_error.max() < 1e-4  # the IK followed the circle
    assert not result.saturated.any() and result.within_bound


def test_exceeding_the_bound_warns_and_says_why():
    robot = menagerie_like_iiwa14()
    problem, task = tracking_problem(robot)
    with pytest.warns(TrackingWarning, match="exceeds the bound 3 mm") as caught:
        result = simulate(
            robot, problem, task, circle(robot, robot.home), feedforward=False,
            error_bound=(3e-3, 0.05),
        )  # fmt: skip
    assert "IK reference alone" in str(caught[0].message)
    # One root for redik's warnings, attributed to the caller's line (exceptions.warn).
    assert issubclass(caught[0].category, redik.RedikWarning)
    assert caught[0].filename == __file__
    assert not result.within_bound and result.max_position_error > 3e-3
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        problem, task = tracking_problem(robot)
        simulate(robot, problem, task, circle(robot, robot.home), feedforward=False,
                 error_bound=None)  # fmt: skip


def test_a_reference_the_ik_cannot_follow_is_blamed_on_the_ik():
    robot = menagerie_like_iiwa14()
    task = FrameTask(robot.ee.name, target=robot.fk(robot.home))
    slow = Problem(robot, [task], limits=[ConfigurationLimit(), VelocityLimit(0.05)])
    with pytest.warns(TrackingWarning, match="The IK reference itself leaves the path"):
        result = simulate(robot, slow, task, circle(robot, robot.home, duration=1.0))
    assert result.reference_position_error.max() > 0.5 * result.max_position_error


def test_force_limited_servos_report_saturation():
    robot = menagerie_like_iiwa14(forcerange=5.0)  # far below the gravity torque of joint 2
    problem, task = tracking_problem(robot)
    with pytest.warns(TrackingWarning, match="saturated"):
        result = simulate(robot, problem, task, circle(robot, robot.home, duration=1.0))
    assert result.saturation_fraction > 0.5


def test_inertial_feedforward_is_cut_to_what_the_actuator_can_give():
    # A chattering reference (near a singularity) asks for accelerations no servo can give;
    # sent whole, the feed-forward saturated the servo and lost the gravity and PD terms.
    from redik.apps.sim import Controller

    robot = menagerie_like_iiwa14(forcerange=60.0)
    drives = joint_drives(robot)
    controller = Controller(robot, drives, feedforward=True, motor_bandwidth=30.0)
    data = mujoco.MjData(robot.model)
    data.qpos[:] = robot.full_qpos(robot.home)
    mujoco.mj_forward(robot.model, data)
    still = np.zeros(robot.dof)
    for sign in (1.0, -1.0):
        ctrl, _ = controller.controls(data, robot.home, still, sign * np.full(robot.dof, 1e3))
        force = drives.gain * (ctrl - robot.home)  # at rest: kp (u − q)
        assert np.all(np.abs(force) <= 60.0 + 1e-9), force
        assert np.any(np.abs(force) > 59.0)  # cut to the range, not dropped
    gravity_only, _ = controller.controls(data, robot.home, still, still)
    assert np.allclose(drives.gain * (gravity_only - robot.home), data.qfrc_bias[:7], atol=1e-9)


def torque_iiwa14() -> redik.Robot:
    """The bundled iiwa14 driven by torque motors (gear 1, ±320 N·m), gravity on."""
    spec = iiwa14_spec()
    for body in spec.bodies:
        body.gravcomp = 0.0
    for actuator in spec.actuators:
        actuator.set_to_motor()
        actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
        actuator.ctrlrange = [-320.0, 320.0]
    return redik.Robot(spec.compile(), name="iiwa14_motors")


def test_torque_motors_are_driven_by_computed_torque():
    # A joint angle sent to a motor as a torque lets the arm fall: computed torque is needed.
    robot = torque_iiwa14()
    assert joint_drives(robot).kinds == ("motor",) * 7
    problem, task = tracking_problem(robot)
    result = simulate(robot, problem, task, circle(robot, robot.home), control_rate=100.0)
    assert result.status == "completed" and len(result.times) == 400
    assert result.max_position_error < POSITION_BOUND, result.summary()
    assert result.final_position_error < FINAL_BOUND, result.summary()
    assert np.ptp(result.q[:, 1]) > 0.05  # the arm moved


def gymnasium_pusher() -> redik.Robot:
    gymnasium = pytest.importorskip("gymnasium")
    xml = Path(gymnasium.__file__).parent / "envs/mujoco/assets/pusher_v5.xml"
    return redik.load(xml, ee="tips_arm")


def test_gymnasium_pusher_motors_track_a_circle():
    # A third-party 7-joint arm with <motor> actuators (±2 N·m), physics at 100 Hz.
    robot = gymnasium_pusher()
    assert joint_drives(robot).kinds == ("motor",) * 7
    q0 = np.array([0.2, 0.3, 0.0, -1.0, 0.0, -0.5, 0.0])
    problem, task = tracking_problem(robot, q0)
    result = simulate(robot, problem, task, circle(robot, q0, radius=0.05), q0=q0)
    assert result.max_position_error < POSITION_BOUND, result.summary()
    assert result.final_position_error < FINAL_BOUND, result.summary()


def test_actuators_simulate_cannot_drive_are_refused_by_name():
    spec = iiwa14_spec()
    spec.actuators[2].set_to_velocity(kv=30.0)
    with pytest.raises(redik.ModelError, match="'actuator3' is a velocity servo"):
        joint_drives(redik.Robot(spec.compile()))

    spec = iiwa14_spec()
    spec.actuators[0].set_to_position(kp=100.0, timeconst=0.05)
    with pytest.raises(redik.ModelError, match="'actuator1' has activation dynamics"):
        joint_drives(redik.Robot(spec.compile()))

    spec = iiwa14_spec()
    spec.actuators[1].gear[0] = 0.0  # its controls would be divided by 0
    with pytest.raises(redik.ModelError, match="'actuator2' has gear 0"):
        joint_drives(redik.Robot(spec.compile()))

    spec = iiwa14_spec()
    extra = spec.add_actuator(name="joint4_damper", target="joint4")
    extra.trntype = mujoco.mjtTrn.mjTRN_JOINT
    extra.set_to_velocity(kv=5.0)
    with pytest.raises(redik.ModelError, match=r"driven by 2 actuators.*'joint4_damper'"):
        joint_drives(redik.Robot(spec.compile()))

    spec = iiwa14_spec()
    spec.delete(spec.actuator("actuator7"))
    tendon = spec.add_tendon(name="wrist")
    tendon.wrap_joint("joint7", 1.0)
    motor = spec.add_actuator(name="wrist_motor", target="wrist")
    motor.trntype = mujoco.mjtTrn.mjTRN_TENDON
    motor.set_to_motor()
    with pytest.raises(redik.ModelError, match=r"'joint7'.*no actuator.*'wrist_motor' \(tendon\)"):
        joint_drives(redik.Robot(spec.compile()))


def test_the_same_problem_simulated_twice_runs_the_same_both_times():
    from redik.limits import AccelerationLimit

    # Stopped mid-circle, the first run leaves the arm at speed. Unless simulate starts a
    # new motion, the acceleration limit brakes the second run's first ticks against that
    # velocity.
    robot = redik.load("iiwa14")
    path = circle(robot, robot.home, duration=2.0)
    task = FrameTask("ee", target=path.pose(0.0))
    acceleration = AccelerationLimit(20.0)
    posture = PostureTask(robot.home, cost=0.1, priority=1)
    limits = [ConfigurationLimit(), VelocityLimit(2.0), acceleration]
    problem = Problem(robot, [task, posture], limits)
    first = simulate(robot, problem, task, path, 1.0, control_rate=100.0)
    assert np.abs(acceleration.velocity).max() > 0.1  # still moving when the run ends
    second = simulate(robot, problem, task, path, 1.0, control_rate=100.0)
    np.testing.assert_array_equal(second.q_command, first.q_command)
    np.testing.assert_array_equal(second.q, first.q)
    assert first.max_position_error < POSITION_BOUND


# --------------------------------------------------------------------------------------
# Runs MuJoCo finds unstable stop there, with a status


def test_a_completed_run_says_so(iiwa_circle):
    _, _, result = iiwa_circle
    assert result.status == SimulationStatus.COMPLETED and result.message == ""
    assert result.success and result.contacts == ()  # the bundled arm's geoms never collide
    assert not result.summary().startswith("unstable")


def test_an_unstable_run_stops_at_the_tick_mujoco_reset_and_never_reads_healthy():
    # Computed torque at a bandwidth far above the control rate (ω·dt = 5) diverges; MuJoCo
    # flags the huge acceleration and resets the state, which a run carried on past would
    # record as motion.
    robot = torque_iiwa14()
    problem, task = tracking_problem(robot)
    path = circle(robot, robot.home)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = simulate(robot, problem, task, path, motor_bandwidth=500.0)
    assert result.status == SimulationStatus.UNSTABLE and not result.success
    assert [w.category for w in caught] == [InstabilityWarning]  # no tracking verdict
    assert "mjWARN_BAD" in result.message and "reset the state" in result.message
    assert str(caught[0].message).startswith(f"{robot.name}: unstable: MuJoCo found")
    assert result.summary().startswith("unstable: MuJoCo found")
    ticks = len(result.times)
    assert 0 < ticks < 400  # stopped early, the ticks before kept
    assert f"t = {path.start_time + (ticks + 1) / 100.0:.3f} s" in result.message
    for field in (result.q, result.q_command, result.qpos, result.targets, result.saturated):
        assert len(field) == ticks
    assert np.isfinite(result.qpos).all()
    np.testing.assert_allclose(result.times, path.start_time + np.arange(1, ticks + 1) / 100.0)


# --------------------------------------------------------------------------------------
# A floating base: refused when nothing holds it up, held on request


def g1_with_servos(floating_base: bool, weld: bool = False) -> redik.Robot:
    """example-robot-data's G1 with a position servo on every joint (gravity compensated by
    ``gravcomp``), moving its left arm; ``floating_base`` adds the free root joint."""
    pytest.importorskip("cmeel")
    spec = redik.models.loading.load_spec(
        redik.models.example_robot_data("g1"), meshes=False, floating_base=floating_base
    )
    for body in spec.bodies:
        body.gravcomp = 1.0
    names = [j.name for j in spec.joints if j.type != mujoco.mjtJoint.mjJNT_FREE]
    for name in names:
        servo = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        servo.set_to_position(kp=100.0, kv=10.0)
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    if weld:
        spec.add_equality(
            type=mujoco.mjtEq.mjEQ_WELD, name1="pelvis", objtype=mujoco.mjtObj.mjOBJ_BODY
        )
    parts = ("shoulder", "elbow", "wrist")
    arm = [n for n in names if n.startswith("left_") and any(p in n for p in parts)]
    return redik.Robot(spec.compile(), ee="left_rubber_hand", joints=arm)


def g1_run(robot: redik.Robot, **options):
    problem, task = tracking_problem(robot)
    T0 = robot.fk(robot.home)
    path = CircularPath(T0, T0[:3, 3] + [0.0, 0.05, 0.0], normal=[1.0, 0.0, 0.0], duration=2.0)
    return simulate(robot, problem, task, path, **options)


def test_a_floating_base_nothing_supports_is_refused_by_name():
    robot = g1_with_servos(floating_base=True)
    refused = r"floating base \(free joint 'floating_base'\).*hold_base=True"
    with pytest.raises(redik.ModelError, match=refused):
        g1_run(robot)


def test_a_held_base_runs_as_the_same_robot_bolted_down():
    held = g1_run(g1_with_servos(floating_base=True), hold_base=True)
    fixed = g1_run(g1_with_servos(floating_base=False))
    assert held.status == "completed" and held.held_base == "floating_base"
    assert fixed.held_base == ""
    assert np.all(held.qpos[:, :7] == held.qpos[0, :7])  # the base never moved
    np.testing.assert_allclose(held.q, fixed.q, atol=1e-9)
    np.testing.assert_allclose(held.qpos[:, 7:], fixed.qpos, atol=1e-9)
    assert held.within_bound and np.ptp(held.q[:, 0]) > 0.01  # the arm moved and tracked


def test_a_welded_or_weightless_floating_base_is_simulated_free():
    welded = g1_run(g1_with_servos(floating_base=True, weld=True))
    assert welded.status == "completed" and welded.held_base == ""
    assert np.ptp(welded.qpos[:, 2]) > 0.0  # free: the soft weld gives a little
    robot = g1_with_servos(floating_base=True)
    robot.model.opt.gravity[:] = 0.0  # a free-flying manipulator: the base may move
    weightless = g1_run(robot, error_bound=None)
    assert weightless.status == "completed" and np.ptp(weightless.qpos[:, 0]) > 0.0


def test_a_robot_moving_its_own_free_joint_is_refused():
    base = g1_with_servos(floating_base=True)
    joints = ["floating_base", *base.joint_names]
    whole = redik.Robot(base.model, ee="left_rubber_hand", joints=joints)
    with pytest.raises(redik.ModelError, match=r"moves its free joint 'floating_base'.*fixed="):
        g1_run(whole, hold_base=True)


def test_bad_hold_base_is_refused():
    robot = redik.load("planar_2r")
    problem, task = tracking_problem(robot)
    T = robot.fk(robot.home)
    with pytest.raises(redik.InvalidInput, match="hold_base"):
        simulate(robot, problem, task, lambda t: T, 1.0, hold_base="yes")


# --------------------------------------------------------------------------------------
# Contacts: within the robot and with the world, in the result and in the warning

ARM_BY_A_WALL = """
<mujoco model="arm_by_a_wall">
  <compiler angle="radian"/>
  <option timestep="0.002" integrator="implicitfast"/>
  <worldbody>
    <geom name="wall" type="box" size="0.05 0.3 0.3" pos="0.65 0 0.1"/>
    <body name="base">
      <geom type="box" size="0.08 0.08 0.05"/>
      <body name="link1" pos="0 0 0.1">
        <joint name="j1" axis="0 1 0" range="-3 3"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.02" mass="1"/>
        <body name="link2" pos="0.4 0 0">
          <joint name="j2" axis="0 1 0" range="-3 3"/>
          <geom type="capsule" fromto="0 0 0 0.35 0 0" size="0.02" mass="0.5"/>
          <site name="ee" pos="0.35 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position joint="j1" kp="300" kv="30"/>
    <position joint="j2" kp="300" kv="30"/>
  </actuator>
</mujoco>
"""


def run_into(goal: list[float]):
    """A planar arm's tip moved in 2 s to ``goal``; the IK knows nothing of the obstacles."""
    robot = redik.Robot.from_xml_string(ARM_BY_A_WALL, ee="ee")
    q0 = np.array([-0.9, 1.8])  # the tip at (0.47, 0, 0.14), clear of the wall and the base
    T0, T1 = robot.fk(q0), robot.fk(q0)
    T1[:3, 3] = goal
    path = CartesianPath([T0, T1], times=[0.0, 2.0], time_scaling="quintic")
    task = FrameTask("ee", orientation_cost=0.0, target=T0)  # a planar arm: position only
    problem = Problem(robot, [task], [ConfigurationLimit(), VelocityLimit(3.0)])
    with pytest.warns(TrackingWarning) as caught:
        result = simulate(robot, problem, task, path, q0=q0, error_bound=(5e-3, np.inf))
    return result, str(caught[0].message)


def test_a_contact_with_the_world_is_reported_with_its_time_and_depth(tmp_path):
    result, warning = run_into([0.68, 0.0, 0.3])  # into the wall (0.6 ≤ x ≤ 0.7)
    (contact,) = result.contacts
    assert (contact.body1, contact.body2, contact.kind) == ("link2", "world", "world")
    assert 0.0 < contact.first < contact.last <= 2.0 and len(contact.times) > 10
    assert contact.max_depth > 1e-3 and np.all(contact.depth >= 0.0)
    assert contact.first > result.times[0]  # the tip starts clear of the wall
    for text in (result.summary(), warning):
        assert "contacts: world link2–world" in text and "deepest" in text
    assert "Bodies touched" in warning
    png = plot_tracking(result, tmp_path / "contact.png")  # the contact span shaded
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_contact_within_the_robot_is_reported_as_self():
    result, warning = run_into([0.05, 0.0, 0.0])  # the tip down into the robot's own base
    (contact,) = result.contacts
    assert (contact.body1, contact.body2, contact.kind) == ("base", "link2", "self")
    assert contact.first > 0.5 and contact.max_depth > 1e-3
    assert "contacts: self base–link2" in warning
