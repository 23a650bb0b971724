"""Limits: the boxes, mink limits on a model with off-chain joints, limits never left."""

from __future__ import annotations

import mink
import numpy as np
import pytest

import redik
from redik.core.exceptions import InfeasibleProblem, InvalidInput
from redik.limits import ConfigurationLimit, InequalityLimit, MinkLimit, VelocityLimit
from redik.qp import Problem, available_backends
from redik.tasks import FrameTask, PositionTask, PostureTask


def test_position_box_is_shrunk_by_margin_and_tolerance_and_pulls_back_inside(arm):
    limit = ConfigurationLimit(margin=0.01).bind(arm, tolerance=1e-6)
    lower, upper = np.empty(7), np.empty(7)
    q = arm.home.copy()
    limit.set_bounds(q, None, lower, upper)
    limited = np.isfinite(arm.lower)
    np.testing.assert_allclose((q + lower)[limited], arm.lower[limited] + 0.010001)
    np.testing.assert_allclose((q + upper)[limited], arm.upper[limited] - 0.010001)
    assert lower[3] == -np.inf and upper[3] == np.inf  # j4 has no range
    q[0] = arm.upper[0] + 0.5  # outside: the box forces the step back in
    limit.set_bounds(q, None, lower, upper)
    assert upper[0] < -0.5 and lower[0] < upper[0]


def test_position_box_never_shrinks_past_a_quarter_range(arm):
    limit = ConfigurationLimit(margin=10.0).bind(arm)
    lower, upper = np.empty(7), np.empty(7)
    limit.set_bounds(arm.home, None, lower, upper)
    assert np.all(lower <= upper)


def test_a_periodic_configuration_limit_leaves_full_turn_joints_unboxed_and_wraps_them(rng):
    ur5e = redik.load("ur5e")  # ±2π everywhere, the elbow ±π (a full turn too)
    panda = redik.load("panda")
    assert not ConfigurationLimit(periodic=True).bind(panda).turning.any()  # ranges below a turn
    limit = ConfigurationLimit(periodic=True).bind(ur5e, tolerance=1e-9)
    assert limit.turning.all()
    lower, upper = np.empty(6), np.empty(6)
    limit.set_bounds(ur5e.home, None, lower, upper)
    assert np.all(lower == -np.inf) and np.all(upper == np.inf)
    q = ur5e.random_q(rng) + 2 * np.pi * np.array([2, -1, 1, 0, -3, 0])
    wrapped = limit.wrap(q)
    assert ur5e.within_limits(wrapped)
    np.testing.assert_allclose(ur5e.fk(wrapped), ur5e.fk(q), atol=1e-9)
    inside = ur5e.random_q(rng)
    assert limit.wrap(inside) is inside  # nothing outside: untouched, bit for bit
    assert not ConfigurationLimit().bind(ur5e).turning.any()
    with pytest.raises(InvalidInput, match="periodic"):
        ConfigurationLimit(periodic="yes")
    # The driver turns every iterate back into range (one attempt each, no restart).
    T = ur5e.fk(np.array([-0.3, -1.2, 1.4, -1.8, -1.5, 0.4]))
    start = np.array([ur5e.lower[0] + 0.05, -1.2, 1.4, -1.8, -1.5, 0.4])
    once = redik.SolveOptions(restarts=0)
    boxed = redik.solve_problem(Problem(ur5e, [FrameTask("ee", target=T)]), start, once)
    periodic = redik.solve_problem(
        Problem(ur5e, [FrameTask("ee", target=T)], [ConfigurationLimit(periodic=True)]),
        start,
        once,
    )
    assert not boxed.success  # stuck against the shoulder's lower bound
    assert periodic.success and periodic.iterations < 10
    assert all(ur5e.within_limits(q) for q in periodic.history)


def test_velocity_limit_forms_and_errors(arm):
    lower, upper = np.full(7, -np.inf), np.full(7, np.inf)
    VelocityLimit(2.0).bind(arm).bounds_into(arm.home, 0.1, lower, upper)
    np.testing.assert_allclose(upper, 0.2)
    lower, upper = np.full(7, -np.inf), np.full(7, np.inf)
    VelocityLimit({"j2": 1.0}).bind(arm).bounds_into(arm.home, 0.5, lower, upper)
    assert upper[1] == 0.5 and np.isinf(upper[[0, 2, 3, 4, 5, 6]]).all()
    with pytest.raises(InvalidInput, match="grip"):
        VelocityLimit({"grip": 1.0}).bind(arm)  # off the chain
    with pytest.raises(InvalidInput, match="> 0"):
        VelocityLimit(-1.0).bind(arm)
    with pytest.raises(InvalidInput, match="shape"):
        VelocityLimit([1.0, 2.0]).bind(arm)
    with pytest.raises(InvalidInput, match="dt"):
        VelocityLimit(1.0).bind(arm).bounds_into(arm.home, None, lower, upper)


def test_mink_limit_keeps_the_chain_columns_of_an_off_chain_model(arm):
    # The arm has a gripper slide and a free body off the chain (nv = 14, dof = 7).
    assert arm.model.nv > arm.dof
    configuration = mink.Configuration(arm.model, arm.full_qpos(arm.home))
    limit = MinkLimit(mink.ConfigurationLimit(arm.model)).bind(arm)
    G, h = limit.inequalities(configuration, None)
    assert G.shape[1] == arm.dof and h.shape == (G.shape[0],)
    # Six limited chain joints, two rows each; the gripper's rows vanish and are dropped.
    assert G.shape[0] == 12 and np.all(np.any(G != 0.0, axis=1))


@pytest.mark.parametrize("backend", ["daqp", "proxsuite", "osqp", "clarabel"])
def test_returned_q_never_leaves_the_limits(backend, rng):
    robot = redik.load("panda")
    lower, upper = np.array(robot.lower), np.array(robot.upper)
    # Targets far out of reach drive joints into their limits. A weak posture term at the
    # same level keeps the QP well-posed: a position task alone leaves four Hessian
    # eigenvalues at the 1e-6 damping, a minimiser that first-order back-ends (osqp) cannot
    # resolve to their tolerance — they then raise BackendError, which is not this test.
    posture = PostureTask(robot.home, cost=1e-2, priority=0)
    problem = Problem(robot, [PositionTask("ee", target=[2.0, 0.0, 0.5]), posture], backend=backend)
    for _ in range(2):
        problem.tasks[0].set_target(rng.normal(size=3) * 2.0)
        result = redik.solve_problem(
            problem, robot.random_q(rng), redik.SolveOptions(max_iterations=15)
        )
        assert np.all(result.history >= lower) and np.all(result.history <= upper)
        q = robot.random_q(rng)
        for _ in range(5):
            q = q + problem.step(q)
            assert np.all(q >= lower) and np.all(q <= upper)


def test_a_joint_too_far_outside_for_its_velocity_limit_is_infeasible():
    robot = redik.load("panda")
    problem = Problem(
        robot,
        [FrameTask("ee", target=robot.fk(robot.home))],
        [ConfigurationLimit(), VelocityLimit(1.0)],
    )
    q = robot.home.copy()
    q[1] = robot.upper[1] + 0.5  # needs 0.5 rad back, 0.1 rad allowed in dt = 0.1
    with pytest.raises(InfeasibleProblem, match=r"joints \['joint2'\]"):
        problem.step(q, dt=0.1)
    assert np.isfinite(problem.step(q, dt=1.0)).all()  # 1 rad allowed: feasible


class EmptySet(InequalityLimit):
    """x₀ ≤ −1 and −x₀ ≤ −1: contradictory rows."""

    def inequalities(self, state, dt):
        G = np.zeros((2, self.robot.dof))
        G[0, 0], G[1, 0] = 1.0, -1.0
        return G, np.array([-1.0, -1.0])


@pytest.mark.parametrize("backend", ["daqp", ["daqp", "cvxpy"]])
def test_contradictory_rows_are_reported_infeasible(backend):
    robot = redik.load("panda")
    problem = Problem(
        robot, [FrameTask("ee", target=robot.fk(robot.home))], [EmptySet()], backend=backend
    )
    with pytest.raises(InfeasibleProblem, match="infeasible"):
        problem.step(robot.home)


@pytest.mark.parametrize("backend", available_backends())
def test_no_iterate_leaves_the_limits_on_any_backend(backend):
    """Targets just inside the limits pull iterates against them; whatever the back-end's
    accuracy (its declared tolerance shrinks the box), every iterate stays within."""
    robot = redik.load("panda")
    rng = np.random.default_rng(11)
    problem = Problem(robot, [FrameTask("ee", target=np.eye(4))], backend=backend)
    for _ in range(3):
        q_target = robot.random_q(rng)
        joints = rng.choice(robot.dof, size=2, replace=False)  # two joints at a limit
        q_target[joints] = np.where(rng.random(2) < 0.5, robot.lower[joints], robot.upper[joints])
        problem.tasks[0].set_target(robot.fk(q_target))
        options = redik.SolveOptions(max_iterations=30, restarts=0)
        result = redik.solve_problem(problem, robot.random_q(rng), options)
        assert np.all(result.history >= robot.lower) and np.all(result.history <= robot.upper)


class ZeroRow(InequalityLimit):
    """0 · Δq ≤ −1: a row no step satisfies, which DAQP refuses at its set-up."""

    def inequalities(self, state, dt):
        return np.zeros((1, self.robot.dof)), np.array([-1.0])


def test_a_row_refused_at_the_backend_set_up_is_infeasible_not_a_raw_error():
    robot = redik.load("panda")
    target = robot.fk(robot.clip(robot.home + 0.1))
    problem = Problem(robot, [FrameTask("ee", target=target)], [ConfigurationLimit(), ZeroRow()])
    for _ in range(2):
        with pytest.raises(InfeasibleProblem, match=r"'daqp'.*infeasible"):
            problem.step(robot.home)
    with pytest.raises(InfeasibleProblem, match=r"'daqp'.*infeasible"):
        redik.solve_problem(problem, robot.home)


# Limits at a priority (issue: a collision limit that the hand may override)

_PLANAR_OBSTACLES = """
<mujoco model="planar_3r_obstacles">
  <compiler angle="radian"/>
  <worldbody>
    <geom name="bin" type="sphere" pos="1.6 1.2 0" size="0.2"/>
    <geom name="post" type="sphere" pos="1.38 -0.04 0" size="0.1"/>
    <body name="link1">
      <joint name="joint1" axis="0 0 1" range="-3 3"/>
      <geom name="link1" type="capsule" fromto="0.1 0 0 0.9 0 0" size="0.05"/>
      <body name="link2" pos="1 0 0">
        <joint name="joint2" axis="0 0 1" range="-2.8 2.8"/>
        <geom name="link2" type="capsule" fromto="0.1 0 0 0.9 0 0" size="0.05"/>
        <body name="link3" pos="1 0 0">
          <joint name="joint3" axis="0 0 1" range="-2.8 2.8"/>
          <geom name="link3" type="capsule" fromto="0.1 0 0 0.9 0 0" size="0.05"/>
          <site name="tip" pos="1 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
  <keyframe><key name="home" qpos="0.3 0.6 0.6"/></keyframe>
</mujoco>
"""


@pytest.fixture(scope="module")
def planar_obstacles() -> redik.Robot:
    import mujoco

    return redik.Robot(mujoco.MjModel.from_xml_string(_PLANAR_OBSTACLES), ee="tip")


def _solve_with_collision_priority(robot, priority):
    """The tip asked to the centre of the bin (only reachable through it), a posture below;
    the collision limit ("none": absent) at ``priority``."""
    from redik.limits import CollisionAvoidanceLimit

    limits = [ConfigurationLimit()]
    if priority != "none":
        limits.append(
            CollisionAvoidanceLimit(
                [(["link1", "link2", "link3"], ["bin", "post"])],
                minimum_distance=0.01,
                detection_distance=0.1,
                priority=priority,
            )
        )
    tasks = [PositionTask("tip", target=[1.6, 1.2, 0.0]), PostureTask(priority=1)]
    return redik.solve_problem(Problem(robot, tasks, limits), robot.home)


def test_a_collision_limit_at_a_priority_yields_to_the_levels_above_only(planar_obstacles):
    from redik.limits import CollisionAvoidanceLimit

    robot = planar_obstacles
    arm = CollisionAvoidanceLimit([(["link1", "link2"], ["bin", "post"])]).bind(robot)
    hand = CollisionAvoidanceLimit([(["link3"], ["bin"])]).bind(robot)
    free = _solve_with_collision_priority(robot, "none")
    assert free.success and arm.minimum_distance_at(free.q)[0] < -0.1  # link2 in the post
    # Default: hard at every level, the tip stops outside the bin.
    hard = _solve_with_collision_priority(robot, None)
    assert not hard.success and hard.position_error > 0.15
    assert arm.minimum_distance_at(hard.q)[0] >= 0.01 - 1e-3
    assert hand.minimum_distance_at(hard.q)[0] >= 0.01 - 1e-3
    # priority=0 ranks it above every task: hard again.
    top = _solve_with_collision_priority(robot, 0)
    assert not top.success and hand.minimum_distance_at(top.q)[0] >= 0.01 - 1e-3
    # priority=1, below the tip and above the posture: the tip reaches into the bin (the
    # forearm with it, unavoidably) and the rest of the arm keeps clear of the post.
    ranked = _solve_with_collision_priority(robot, 1)
    assert ranked.success and ranked.position_error < 1e-6
    assert ranked.stationary  # the posture is optimal subject to the ranked rows it meets
    assert hand.minimum_distance_at(ranked.q)[0] < -0.1
    assert arm.minimum_distance_at(ranked.q)[0] >= 0.01 - 1e-3
    # priority=2, below the posture that takes the last freedom: the unconstrained answer.
    below = _solve_with_collision_priority(robot, 2)
    assert below.success
    np.testing.assert_allclose(below.q, free.q, atol=1e-6)


def test_a_ranked_limit_in_online_steps_and_its_bad_input(planar_obstacles):
    robot = planar_obstacles
    # A ranked velocity box: the posture at level 0 breaks it, the one at level 1 may not.
    far = robot.home + 1.0
    tasks = [PostureTask(far, gain=1.0, priority=0), PostureTask(priority=1)]
    dq = Problem(robot, tasks, [VelocityLimit(0.1, priority=1)]).step(robot.home, dt=1.0)
    np.testing.assert_allclose(dq, 1.0, atol=1e-6)
    dq = Problem(robot, tasks, [VelocityLimit(0.1)]).step(robot.home, dt=1.0)
    np.testing.assert_allclose(dq, 0.1, atol=1e-6)
    # Only the first task at level 0 and the limit between the levels: level 1 (a posture
    # to home, which wants dq = 0 where level 0 leaves freedom) is boxed.
    tasks = [PositionTask("tip", target=robot.fk(far)[:3, 3]), PostureTask(far, priority=1)]
    dq = Problem(robot, tasks, [VelocityLimit(0.1, priority=1)]).step(robot.home, dt=1.0)
    assert np.abs(dq).max() > 0.1 + 1e-3  # level 0 needs more than the box
    # A link deep in the bin: the hard damper asks more than the velocity box allows in one
    # tick (InfeasibleProblem); ranked at 0, the step is the least violation: out, at full speed.
    from redik.limits import CollisionAvoidanceLimit

    inside = np.array([0.03, 0.214, 1.706])
    bin_ = CollisionAvoidanceLimit([(["link3"], ["bin"])]).bind(robot)
    for priority in (None, 0):
        collisions = CollisionAvoidanceLimit(
            [(["link3"], ["bin"])], detection_distance=0.1, priority=priority
        )
        problem = Problem(robot, tasks, [VelocityLimit(2.0), collisions])
        if priority is None:
            with pytest.raises(InfeasibleProblem):
                problem.step(inside, dt=0.01)
            continue
        dq = problem.step(inside, dt=0.01)
        assert np.abs(dq).max() == pytest.approx(0.02, abs=1e-9)
        depth = bin_.minimum_distance_at(inside)[0]
        assert bin_.minimum_distance_at(inside + dq)[0] > depth + 1e-3
    for bad in (-1, 1.5, "1", True):
        with pytest.raises(InvalidInput, match="priority"):
            VelocityLimit(1.0, priority=bad)
    with pytest.raises(InvalidInput, match="Backend instance"):
        backend = redik.qp.make_backend("daqp")
        Problem(robot, tasks[:1], [ConfigurationLimit(priority=0)], backend=backend)


def test_acceleration_limit_bounds_the_velocity_change_and_brakes_before_the_limits():
    from redik.limits import AccelerationLimit

    robot = redik.load("panda")
    a, v_max, dt = 5.0, 2.0, 0.01
    acceleration = AccelerationLimit(a)
    # Every joint driven at its range's far end beyond it: it must speed up at a, cruise
    # and brake in time; the posture asks for the impossible at each tick.
    beyond = robot.upper + 1.0
    problem = Problem(
        robot,
        [PostureTask(beyond, gain=1.0, priority=0)],
        [ConfigurationLimit(), VelocityLimit(v_max), acceleration],
    )
    q, v = robot.home.copy(), np.zeros(robot.dof)
    for _ in range(300):
        dq = problem.step(q, dt)
        assert np.abs(dq / dt - v).max() <= a * dt + 1e-9
        v = dq / dt
        q = q + dq
        assert robot.within_limits(q)
    assert np.abs(v).max() < a * dt + 1e-9  # stopped at the limits, not slammed into them
    assert np.abs(q - robot.upper).max() < 0.05  # …and close to them
    np.testing.assert_allclose(acceleration.velocity, v)
    acceleration.reset()
    assert not acceleration.velocity.any()
    with pytest.raises(InvalidInput, match="shape"):
        acceleration.reset(np.zeros(3))
    with pytest.raises(InvalidInput, match="step duration"):
        problem.step(q)
    with pytest.raises(InvalidInput, match="> 0"):
        AccelerationLimit(0.0).bind(robot)
    with pytest.raises(InvalidInput, match="does not move"):
        AccelerationLimit({"elbow": 1.0}).bind(robot)
    with pytest.raises(InvalidInput, match="not bound"):
        AccelerationLimit(1.0).reset()
    # A joint not in the mapping is not bounded.
    loose = AccelerationLimit({"joint1": 1.0}).bind(robot)
    lower, upper = np.full(robot.dof, -np.inf), np.full(robot.dof, np.inf)
    loose.bounds_into(robot.scalar_values(robot.home), dt, lower, upper)
    assert upper[0] == pytest.approx(0.01 * dt) and np.isinf(upper[1:]).all()


def test_configuration_limit_refuses_a_margin_that_is_not_a_number():
    """``ConfigurationLimit("x")`` or ``ConfigurationLimit(None)`` raised a raw ValueError/TypeError
    from ``float()``; ``BallJointLimit`` already named the fault."""
    for margin in ("x", None, [0.1], np.array([0.1, 0.2])):
        with pytest.raises(InvalidInput, match="margin must be a number"):
            ConfigurationLimit(margin)
    for margin in (np.nan, -0.1, np.inf):
        with pytest.raises(InvalidInput, match="margin must be finite"):
            ConfigurationLimit(margin)


def test_mink_limit_refuses_a_dt_that_is_not_a_positive_number(arm):
    """``MinkLimit(limit, dt="x")`` raised a raw ValueError; NaN, 0 and negative steps were
    kept and handed to mink (which divides by dt)."""
    for dt in ("x", None, np.nan, 0.0, -1.0, np.inf):
        with pytest.raises(InvalidInput, match="dt must be a finite positive number"):
            MinkLimit(mink.ConfigurationLimit(arm.model), dt=dt)
    assert MinkLimit(mink.ConfigurationLimit(arm.model), dt=0.01).dt == 0.01
