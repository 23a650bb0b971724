"""solve_problem: the one driver of every task stack — reach, polish, optimise, restarts."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import redik
from redik import SolveOptions, lie, solve_problem
from redik.apps.bench import _whole_body as whole_body
from redik.core.exceptions import InvalidInput
from redik.qp import Problem
from redik.solvers.pose.qp import solve_pose_qp
from redik.tasks import FrameTask, JointLimitAvoidanceTask, PositionTask, PostureTask


@pytest.fixture(scope="module")
def panda() -> redik.Robot:
    return redik.load("panda")


def on_pose(robot, q, T) -> bool:
    """``q`` puts the end-effector on ``T`` within 1e-6 m and 1e-5 rad, inside the limits."""
    p_err, r_err = lie.pose_errors(robot.fk(q), T)
    return p_err <= 1e-6 and r_err <= 1e-5 and robot.within_limits(q)


# From a start already on the pose (issue 20, item 1)


@pytest.mark.parametrize("name", ["dexter8r", "iiwa14"])
def test_the_lower_level_is_optimised_from_a_start_exactly_on_the_pose(name):
    """q0 on the pose: level 0 holds from the start, yet the joint-limit potential below it
    falls until stationary (a driver that accepts a step only when level 0 *stays* met
    rejects every tangent step — it leaves the curved pose set at second order)."""
    robot = redik.load(name)
    rng = np.random.default_rng(1)
    for _ in range(5):
        q_on = robot.clip(robot.random_q(rng))
        T = robot.fk(q_on)
        potential = JointLimitAvoidanceTask(priority=1)
        problem = Problem(robot, [FrameTask("ee", target=T), potential])
        result = solve_problem(problem, q_on, SolveOptions(restarts=0))
        assert result.status == "converged" and result.stationary, result.message
        assert on_pose(robot, result.q, T)
        assert max(result.stationarity) <= 1e-8
        assert potential.value(result.q) < potential.value(q_on) - 1e-6


def test_the_issue_case_lowers_the_potential_from_its_exact_start():
    robot = redik.load("dexter8r")
    q_on = robot.clip(robot.home + 0.05)
    potential = JointLimitAvoidanceTask(priority=1)
    problem = Problem(robot, [FrameTask("ee", target=robot.fk(q_on)), potential])
    result = solve_problem(problem, q_on)
    # φ(q_on) = 0.14934; the constrained optimum from home + noise is 0.14659.
    assert potential.value(q_on) == pytest.approx(0.14934, abs=1e-5)
    assert potential.value(result.q) == pytest.approx(0.14659, abs=1e-5)
    assert result.status == "converged" and on_pose(robot, result.q, robot.fk(q_on))


# The lower levels' optimum


def test_the_lower_level_ends_at_the_constrained_optimum(panda, rng):
    """Pose at priority 0, posture at priority 1: the result minimises the posture cost
    subject to the pose (an independent SLSQP solve agrees); stopping once the pose is met
    leaves the posture cost higher and its projected gradient away from zero."""
    from scipy.optimize import minimize

    for _ in range(3):
        q0 = np.clip(panda.random_q(rng), panda.lower + 0.3, panda.upper - 0.3)
        T = panda.fk(np.clip(q0 + rng.uniform(-0.3, 0.3, 7), panda.lower, panda.upper))
        q_nominal = np.clip(q0 + rng.uniform(-0.5, 0.5, 7), panda.lower, panda.upper)
        problem = Problem(
            panda, [FrameTask("ee", target=T), PostureTask(q_nominal, gain=0.2, priority=1)]
        )
        result = solve_problem(problem, q0)
        early = solve_problem(problem, q0, SolveOptions(stationarity_tol=None))
        assert result.status == "converged" and result.stationary
        np.testing.assert_array_equal(result.history[-1], result.q)  # the path ends at q
        assert result.error_history.shape == (result.history.shape[0],)
        assert early.success and not early.stationary and early.stationarity == []
        assert problem.stationarity(early.q)[0] > 1e-6

        def cost(q, q_nominal=q_nominal):
            return 0.5 * float(np.sum((q - q_nominal) ** 2))

        def pose_residual(q, T=T):
            F = panda.fk(q)
            return np.concatenate([F[:3, 3] - T[:3, 3], lie.so3_log(F[:3, :3].T @ T[:3, :3])])

        reference = minimize(
            cost,
            early.q,
            method="SLSQP",
            constraints=[{"type": "eq", "fun": pose_residual}],
            bounds=list(zip(panda.lower, panda.upper, strict=True)),
            options={"ftol": 1e-14, "maxiter": 500},
        )
        assert reference.success and np.max(np.abs(pose_residual(reference.x))) < 1e-10
        assert cost(result.q) < cost(early.q) - 1e-5
        np.testing.assert_allclose(result.q, reference.x, atol=1e-6)


def test_the_lower_level_converges_fast_once_level_0_holds(panda):
    """Joint-limit avoidance below the pose: with the curvature of the pose set in level 1's
    model (SQP), each of panda_reach's first 20 targets ends stationary in a few iterations."""
    T_home = panda.fk(panda.home)
    rng = np.random.default_rng(0)
    iterations = []
    for _ in range(20):
        T = lie.make_pose(
            T_home[:3, :3] @ lie.so3_exp(rng.uniform(-0.5, 0.5, 3)),
            T_home[:3, 3] + rng.uniform(-0.2, 0.2, 3),
        )
        problem = Problem(panda, [FrameTask("ee", target=T), JointLimitAvoidanceTask(priority=1)])
        result = solve_problem(problem, panda.home)
        assert result.status == "converged" and result.stationary, result.message
        iterations.append(result.iterations)
    assert max(iterations) <= 30 and np.mean(iterations) < 10


def test_suboptimal_when_the_budget_ends_before_the_lower_level_is_stationary(panda, rng):
    q0 = np.clip(panda.random_q(rng), panda.lower + 0.3, panda.upper - 0.3)
    T = panda.fk(np.clip(q0 + rng.uniform(-0.1, 0.1, 7), panda.lower, panda.upper))
    problem = Problem(
        panda, [FrameTask("ee", target=T), PostureTask(panda.home, gain=0.05, priority=1)]
    )
    result = solve_problem(problem, q0, SolveOptions(max_iterations=8))
    assert result.success and result.status == "suboptimal" and not result.stationary
    assert result.stationarity[0] > 1e-8 and on_pose(panda, result.q, T)
    assert "not stationary within 1e-08" in result.message
    single = solve_problem(Problem(panda, [FrameTask("ee", target=T)]), q0)
    assert single.status == "converged" and single.stationary and single.stationarity == []


def test_a_level_0_without_targets_is_optimised_as_a_level(panda):
    problem = Problem(panda, [PostureTask(panda.home, priority=0)])
    start = np.clip(panda.home + 0.3, panda.lower, panda.upper)
    result = solve_problem(problem, start)
    assert result.status == "converged" and len(result.stationarity) == 1
    np.testing.assert_allclose(result.q, panda.home, atol=1e-6)


def test_a_mink_task_at_level_0_is_restored_and_the_level_below_finished(panda, rng):
    import mink

    T = panda.fk(panda.random_q(rng))
    frame = mink.FrameTask("ee", "site", position_cost=1.0, orientation_cost=1.0)
    frame.set_target(mink.SE3.from_matrix(T))
    result = solve_problem(Problem(panda, [frame, PostureTask(priority=1)]), panda.home)
    assert result.status == "converged" and result.stationary, result.message
    assert on_pose(panda, result.q, T)


def test_velocity_limits_take_the_options_dt(panda, rng):
    T = panda.fk(np.clip(panda.home + 0.2, panda.lower, panda.upper))
    problem = Problem(
        panda, [FrameTask("ee", target=T), PostureTask(priority=1)],
        [redik.ConfigurationLimit(), redik.VelocityLimit(1.0)],
    )  # fmt: skip
    result = solve_problem(problem, panda.home, SolveOptions(dt=0.05))
    assert result.status == "converged" and on_pose(panda, result.q, T)
    assert np.abs(np.diff(result.history, axis=0)).max() <= 0.05 + 1e-9
    with pytest.raises(InvalidInput, match="VelocityLimit needs the step duration"):
        solve_problem(problem, panda.home)


# One status for one situation (issue 20, item 3)


@pytest.mark.parametrize("name", ["iiwa14", "panda"])
def test_a_target_out_of_reach_is_unreachable_with_and_without_limits(name):
    robot = redik.load(name)
    far = np.eye(4)
    far[:3, 3] = (3.0, 0.0, 0.5)
    statuses = set()
    for limits in (None, []):
        result = solve_problem(Problem(robot, [FrameTask("ee", target=far)], limits), robot.home)
        assert result.status == "unreachable" and not result.success
        assert "beyond the reach of its chain" in result.message
        assert "limit" not in result.message
        statuses.add(result.status)
    assert statuses == {redik.solve_pose(robot, far, seed=0).status}
    assert redik.solve_pose(robot, far, method="qp", seed=0).status in statuses


def test_messages_name_joints_at_limits_only_when_the_problem_holds_them():
    spec_robot = redik.load("planar_2r")
    import mujoco

    spec = mujoco.MjSpec.from_file(str(redik.models.scene_path("planar_2r")))
    for joint in spec.joints:
        joint.range = [-1.0, 1.0]
        joint.limited = mujoco.mjtLimited.mjLIMITED_TRUE
    narrow = redik.Robot(spec.compile(), name="narrow")
    target = narrow.fk(np.array([0.3, 2.9]))[:3, 3]  # needs the elbow at 2.9 rad
    blocked = solve_problem(Problem(narrow, [PositionTask("ee", target=target)]), narrow.home)
    assert not blocked.success and "at their limits" in blocked.message
    free = solve_problem(Problem(narrow, [PositionTask("ee", target=target)], []), narrow.home)
    assert free.status == "converged"
    assert spec_robot.dof == narrow.dof


# Restarts, warm start, reproducibility (issue 20, item 2)


def test_restarts_are_seeded_and_reproducible(panda):
    rng = np.random.default_rng(3)
    T = panda.fk(panda.random_q(rng))
    problem = Problem(panda, [FrameTask("ee", target=T), PostureTask(priority=1)])
    starts = {}
    for seed in (0, 0, 1):
        result = solve_problem(problem, panda.lower + 0.01, SolveOptions(seed=seed))
        assert result.success and on_pose(panda, result.q, T)
        starts.setdefault(seed, []).append(result.q)
    np.testing.assert_array_equal(starts[0][0], starts[0][1])


def test_baxter_arm_position_targets_from_home_are_all_reached():
    """Baxter's right arm, position only, from home (a straight elbow): a monotone descent
    walks into the basin where the elbow and a wrist joint sit on their limits."""
    baxter = _third_party("baxter", False, ["right_[sew][0-9]"], None)
    chain = redik.Robot(baxter.model, "right_gripper")
    rng = np.random.default_rng(0)
    for _ in range(6):
        p = chain.fk(chain.random_q(rng))[:3, 3]
        problem = Problem(chain, [PositionTask("right_gripper", target=p)])
        result = solve_problem(problem, chain.home)
        assert result.success, result.message
        assert np.linalg.norm(chain.fk(result.q)[:3, 3] - p) <= 1e-6
        assert chain.within_limits(result.q)


def test_options_are_checked():
    for arguments, match in (
        ({"pos_tol": -1.0}, "pos_tol"),
        ({"rot_tol": float("nan")}, "rot_tol"),
        ({"max_iterations": 2.5}, "max_iterations"),
        ({"restarts": -1}, "restarts"),
        ({"seed": -3}, "seed"),
        ({"stationarity_tol": 0.0}, "stationarity_tol"),
        ({"lm_damping": "0.1"}, "lm_damping"),
        ({"max_step": 0.0}, "max_step"),
        ({"dt": -0.01}, "dt"),
        ({"warm_start": 1}, "warm_start"),
    ):
        with pytest.raises(InvalidInput, match=match):
            SolveOptions(**arguments)
    with pytest.raises(InvalidInput, match=r"redik\.Problem"):
        solve_problem("problem", np.zeros(7))  # type: ignore[arg-type]


def test_the_driver_is_exported_and_documented():
    for name in ("solve_problem", "SolveOptions", "QPResult"):
        assert name in redik.__all__
    assert redik.QPResult.__mro__[1] is redik.IKResult
    assert redik.Status.SUBOPTIMAL == "suboptimal" and "solve_problem" in redik.Status.__doc__


# Multi-frame targets on whole-body models (issue 20, item 2)


def _third_party(name, floating, joints, fixed) -> redik.Robot:
    pytest.importorskip("cmeel")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # meshes dropped with a warning
        path = redik.models.example_robot_data(name)
        model = redik.models.loading.load_model(path, meshes=False, floating_base=floating)
    return redik.Robot(model, joints=joints, fixed=fixed)


def _success_rate(key: str, count: int, seed: int) -> float:
    """Strict success (1e-6 m, 1e-5 rad, inside the limits) from home on ``count`` targets:
    every frame's pose at a configuration drawn inside the limits."""
    pytest.importorskip("cmeel")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # meshes dropped with a warning
        robot, frames = whole_body.whole_body(key)
    rng = np.random.default_rng(seed)
    reached = 0
    for _ in range(count):
        goal = whole_body.goal(robot, frames, rng)
        result = solve_problem(whole_body.stack(robot, goal), robot.home)
        strict = whole_body.reaches(robot, result.q, goal, 1e-6, 1e-5)
        reached += strict
        assert strict == result.success, result.message  # the status tells the truth
    return reached / count


@pytest.mark.parametrize("key", list(whole_body.WHOLE_BODIES))
def test_multi_frame_targets_from_home_are_reached(key):
    assert _success_rate(key, count=4, seed=2) == 1.0


@pytest.mark.slow
@pytest.mark.parametrize("key", list(whole_body.WHOLE_BODIES))
def test_multi_frame_success_rate_is_at_least_95_percent(key):
    assert _success_rate(key, count=100, seed=3) >= 0.95


# solve_pose(method="qp") runs the same driver


def test_solve_pose_qp_is_the_solve_pose_entry_point(panda, rng):
    q0 = np.clip(panda.random_q(rng), panda.lower + 0.2, panda.upper - 0.2)
    T = panda.fk(np.clip(q0 + rng.uniform(-0.4, 0.4, 7), panda.lower, panda.upper))
    options = {"pos_tol": 1e-7, "rot_tol": 1e-7, "max_iterations": 50, "respect_limits": True}
    result = solve_pose_qp(panda, T, q0, frame=None, backend=["daqp", "proxsuite"], **options)
    assert result.success and result.position_error <= 1e-7
    assert isinstance(result, redik.QPResult) and result.method == "qp"
    extra = [PostureTask(priority=1)]
    result = redik.solve_pose(panda, T, q0, method="qp", tasks=extra, respect_limits=False)
    assert result.success and result.stationary
    with pytest.raises(InvalidInput, match="unknown options"):
        solve_pose_qp(panda, T, q0, step_size=0.1)


def test_solve_pose_qp_turns_full_turn_joints_instead_of_stopping_at_their_bounds():
    # UR5e joints span ±2π. From the shoulder near its lower bound, the short way to a target
    # at q₀ = −0.3 (≡ −2π − 0.3) runs into that bound. Periodic, the joint passes it and is
    # turned back into range in one attempt.
    ur5e = redik.load("ur5e")
    q_star = np.array([-0.3, -1.2, 1.4, -1.8, -1.5, 0.4])
    start = q_star.copy()
    start[0] = ur5e.lower[0] + 0.05
    result = solve_pose_qp(ur5e, ur5e.fk(q_star), start, restarts=1, seed=3)
    assert result.success and result.restarts == 0 and ur5e.within_limits(result.q)
    assert np.all(result.history >= ur5e.lower) and np.all(result.history <= ur5e.upper)
    np.testing.assert_allclose(result.q, q_star, atol=1e-5)


def test_solve_pose_qp_reuses_its_problem_and_stays_reproducible(rng):
    from redik.solvers.pose.cache import PoseCache

    robot = redik.load("panda")  # a fresh robot: an empty solver cache
    targets = [robot.fk(q) for q in robot.random_q(rng, size=6)]
    starts = robot.random_q(rng, size=6)
    first = [solve_pose_qp(robot, T, q0, restarts=5, seed=i) for i, (T, q0) in
             enumerate(zip(targets, starts, strict=True))]  # fmt: skip
    assert len(PoseCache.of(robot).qp_problems) == 1
    # In reverse order: each call sets its own target and owes nothing to the calls before.
    for i in reversed(range(6)):
        again = solve_pose_qp(robot, targets[i], starts[i], restarts=5, seed=i)
        assert again.success == first[i].success and again.iterations == first[i].iterations
        np.testing.assert_array_equal(again.q, first[i].q)
    solve_pose_qp(robot, targets[0], starts[0], backend="proxsuite")
    solve_pose_qp(robot, targets[0], starts[0], tasks=[PostureTask(priority=1)])
    assert len(PoseCache.of(robot).qp_problems) == 1


def test_solve_pose_qp_refuses_tasks_that_are_not_a_list(panda):
    T = panda.fk(panda.home)
    for tasks in (3, None, "posture"):
        with pytest.raises(InvalidInput, match="tasks must be a list"):
            solve_pose_qp(panda, T, panda.home, tasks=tasks)
    one = solve_pose_qp(panda, T, panda.home, tasks=PostureTask(priority=1))
    listed = solve_pose_qp(panda, T, panda.home, tasks=[PostureTask(priority=1)])
    assert one.success and np.array_equal(one.q, listed.q)


def test_solve_pose_qp_keeps_a_bounded_number_of_problems(rng):
    from redik.solvers.pose.cache import PoseCache
    from redik.solvers.pose.qp import PROBLEMS_KEPT

    robot = redik.load("panda")
    T = robot.fk(robot.random_q(rng))
    for gain in np.linspace(0.5, 1.0, 3 * PROBLEMS_KEPT):
        solve_pose_qp(robot, T, robot.home, gain=float(gain), max_iterations=2)
    assert 1 <= len(PoseCache.of(robot).qp_problems) <= PROBLEMS_KEPT
