"""solve_pose and solve_all: FK∘IK on every scene, each method, limits, failures, misuse."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import redik
from redik import lie
from redik.core.exceptions import (
    InvalidConfiguration,
    InvalidInput,
    InvalidPose,
    NearRotationWarning,
    RedikError,
)
from redik.core.result import IKResult
from redik.kinematics.dls import BatchOptions
from redik.solvers.cache import solver_cache
from redik.solvers.pose import solve_all, solve_pose
from redik.solvers.pose.attempt import PoseProblem
from redik.solvers.pose.result import body_twist_norm

SCENES = redik.list_scenes()


def check_solution(robot, result, T_target, pos_tol=1e-6, rot_tol=1e-5, limits=True):
    """Success checked independently: FK of the returned q, not the solver's flag."""
    assert np.all(np.isfinite(result.q))
    position_error, rotation_error = lie.pose_errors(robot.fk(result.q), T_target)
    assert position_error <= pos_tol and rotation_error <= rot_tol, result.summary()
    assert result.position_error == pytest.approx(position_error, abs=1e-12)
    assert result.rotation_error == pytest.approx(rotation_error, abs=1e-12)
    if limits:
        assert robot.within_limits(result.q)


def test_the_scenes_are_there():
    assert {"panda", "iiwa14", "ur5e"} <= set(SCENES)


@pytest.mark.parametrize("name", SCENES)
def test_fk_of_ik_is_the_identity_on_random_poses_of_every_scene(name):
    """Targets are FK of random q inside the limits, so they are reachable even for planar
    arms and 3-joint legs, whose 6-D pose target is then consistent (rank-deficient J)."""
    robot = redik.load(name)
    rng = np.random.default_rng(7)
    for index in range(8):
        T_target = robot.fk(robot.random_q(rng))
        result = solve_pose(robot, T_target, robot.random_q(rng), seed=index)
        assert result.success and result.status == "converged", (name, result.message)
        check_solution(robot, result, T_target)


@pytest.mark.parametrize("method", ["newton", "hybrid", "transpose", "dls"])
def test_every_method_solves_panda_near_a_solution(method):
    robot = redik.load("panda")
    rng = np.random.default_rng(3)
    q_goal = robot.clip(robot.home + rng.uniform(-0.3, 0.3, robot.dof))
    T_target = robot.fk(q_goal)
    q0 = robot.clip(q_goal + rng.uniform(-0.1, 0.1, robot.dof))
    result = solve_pose(robot, T_target, q0, method=method, seed=0)
    assert result.success, result.message
    assert result.method == method
    check_solution(robot, result, T_target)
    # History: q0 (projected into the limits) first, one row per iteration of the attempt.
    assert result.history.shape[1] == robot.dof
    assert result.error_history.shape == (result.history.shape[0],)
    if result.restarts == 0:
        np.testing.assert_allclose(result.history[0], q0)
        assert result.history.shape[0] == result.iterations + 1


def test_newton_body_and_space_forms_converge_quadratically():
    robot = redik.load("ur5e")  # square J: both forms take the same step
    q_goal = robot.home + 0.2
    T_target = robot.fk(q_goal)
    q0 = q_goal + 0.05
    body = solve_pose(robot, T_target, q0, method="newton", restarts=0, pos_tol=1e-12,
                      rot_tol=1e-12)  # fmt: skip
    space = solve_pose(robot, T_target, q0, method="newton", restarts=0, form="space",
                       pos_tol=1e-12, rot_tol=1e-12)  # fmt: skip
    assert body.success and space.success
    np.testing.assert_allclose(body.history, space.history, atol=1e-9)
    e = body.error_history
    for a, b in itertools.pairwise(e):
        if 1e-8 < a < 1e-2:
            assert b <= 10.0 * a**2


def test_transpose_with_armijo_decreases_monotonically():
    robot = redik.load("planar_3r")
    T_target = robot.fk(np.array([0.3, 0.5, -0.4]))
    result = solve_pose(robot, T_target, np.array([0.1, 0.2, 0.1]), method="transpose",
                        restarts=0, max_iterations=3000)  # fmt: skip
    assert np.all(np.diff(result.error_history) <= 0.0)
    assert result.success, result.message


def test_dls_error_never_increases_within_an_attempt():
    robot = redik.load("iiwa14")
    rng = np.random.default_rng(11)
    T_target = robot.fk(robot.random_q(rng))
    result = solve_pose(robot, T_target, robot.random_q(rng), restarts=0)
    assert np.all(np.diff(result.error_history) <= 0.0)


def test_singular_start_is_handled():
    """Start exactly at a singular posture (wrist axes aligned): no NaN, still converges."""
    robot = redik.load("puma560")
    q0 = np.zeros(robot.dof)  # θ5 = 0 aligns joints 4 and 6
    assert np.linalg.matrix_rank(robot.jacobian(q0), tol=1e-9) < 6
    T_target = robot.fk(robot.home)
    for method in ("dls", "newton"):
        result = solve_pose(robot, T_target, q0, method=method, seed=1)
        assert np.all(np.isfinite(result.q)) and np.all(np.isfinite(result.history))
        assert result.success, (method, result.message)


def test_respect_limits_keeps_every_iterate_inside(arm, rng):
    T_target = arm.fk(arm.random_q(rng))
    result = solve_pose(arm, T_target, arm.random_q(rng), seed=2)
    assert result.success
    lower, upper = arm.lower - 1e-12, arm.upper + 1e-12
    assert np.all((result.history >= lower) & (result.history <= upper))
    check_solution(arm, result, T_target)


def test_without_limits_success_ignores_them():
    robot = redik.load("panda")
    q_outside = robot.home.copy()
    q_outside[3] = 0.5  # joint 4 of the panda only bends one way: [-3.07, -0.07]
    T_target = robot.fk(q_outside)
    result = solve_pose(robot, T_target, q_outside + 0.02, respect_limits=False, restarts=0)
    assert result.success and result.status == "converged"
    check_solution(robot, result, T_target, limits=False)
    assert not robot.within_limits(result.q) and "outside" in result.message


def test_reproducible_with_a_seed():
    robot = redik.load("panda")
    T_target = robot.fk(robot.random_q(np.random.default_rng(5)))
    q0 = robot.lower + 0.01  # a poor start, so restarts are likely used
    first = solve_pose(robot, T_target, q0, seed=42, max_iterations=5)
    second = solve_pose(robot, T_target, q0, seed=42, max_iterations=5)
    np.testing.assert_array_equal(first.q, second.q)
    assert first.restarts == second.restarts and first.restarts > 0


def test_target_outside_the_workspace_is_unreachable_and_finite():
    robot = redik.load("ur5e")
    T_target = lie.make_pose(np.eye(3), np.array([3.0, 0.0, 0.5]))
    for method in ("dls", "newton", "hybrid"):
        result = solve_pose(robot, T_target, method=method, seed=0, max_iterations=50)
        assert not result.success
        assert result.status in ("unreachable", "max_iterations")
        assert result.status == "unreachable"  # 3 m is beyond the ~1 m arm: we can tell
        assert np.all(np.isfinite(result.q)) and np.isfinite(result.error)
        assert "closest" in result.message
        reached = robot.fk(result.q)[:3, 3]
        assert np.linalg.norm(reached - T_target[:3, 3]) == pytest.approx(result.position_error)
        if method != "newton":  # undamped Newton is not a minimiser far from a root
            # The closest q found stretches the arm towards the target (~1 m reach, 3 m away).
            assert result.position_error < 2.2


NARROW_2R = """
<mujoco model="narrow_2r">
  <compiler angle="radian"/>
  <worldbody>
    <body name="l1">
      <joint name="shoulder" type="hinge" axis="0 0 1" range="-1 1"/>
      <geom type="capsule" fromto="0 0 0 1 0 0" size="0.03"/>
      <body name="l2" pos="1 0 0">
        <joint name="elbow" type="hinge" axis="0 0 1" range="-1 1"/>
        <geom type="capsule" fromto="0 0 0 1 0 0" size="0.03"/>
        <site name="ee" pos="1 0 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("method", ["dls", "newton", "hybrid", "transpose", "qp"])
def test_a_pose_reached_only_outside_the_limits_is_limits(method):
    """A 2R arm reaches a pose with one q up to the elbow's sign: θ2 = ±2.9 rad, both
    beyond the elbow's ±1 rad. Without the diagnosis the failure was "max_iterations" or
    "unreachable", which says nothing of the limits."""
    robot = redik.Robot.from_xml_string(NARROW_2R)
    T_target = robot.fk(np.array([0.3, 2.9]))
    result = solve_pose(robot, T_target, seed=0, method=method)
    assert not result.success and result.status == "limits", (result.status, result.message)
    assert robot.within_limits(result.q) and np.all(np.isfinite(result.q))
    assert "elbow = 2.9 outside [-1, 1]" in result.message  # in (−π, π], whatever it found
    assert "elbow at its upper limit" in result.message and "closest pose" in result.message
    unchecked = solve_pose(robot, T_target, seed=0, method=method, diagnose_limits=False)
    assert unchecked.status in ("max_iterations", "stalled", "unreachable")
    np.testing.assert_array_equal(unchecked.q, result.q)


def test_the_limits_diagnosis_runs_on_failures_within_reach_only(monkeypatch):
    from redik.solvers.pose import solve as module

    robot = redik.Robot.from_xml_string(NARROW_2R)
    calls = []
    original = module.solve_pose

    def counting(*args, **kwargs):  # solve_all's calls respect the limits
        if kwargs.get("respect_limits") is False:
            calls.append(args[1])
        return original(*args, **kwargs)

    monkeypatch.setattr(module, "solve_pose", counting)  # what the diagnosis calls
    reachable = robot.fk(np.array([0.3, 0.9]))
    for _ in range(3):  # the first call validates, the others take the compiled fast path
        assert solve_pose(robot, reachable, seed=0).status == "converged"
    assert solve_all(robot, robot.fk(np.array([0.3, 2.9])), n_starts=3, seed=0) == []
    beyond = lie.make_pose(np.eye(3), np.array([3.0, 0.0, 0.0]))
    assert solve_pose(robot, beyond, seed=0).status == "unreachable"
    outside = robot.fk(np.array([0.3, 2.9]))
    assert not solve_pose(robot, outside, seed=0, max_iterations=1, respect_limits=False).success
    assert calls == []
    for _ in range(2):
        assert solve_pose(robot, outside, seed=0).status == "limits"
    assert len(calls) == 2  # one unconstrained solve per failure, of its target
    assert all(np.array_equal(target, outside) for target in calls)


def test_orientation_out_of_reach_of_a_planar_arm_is_a_failure_without_nan():
    """Inside the planar arm's reach but tilted out of its plane: no q matches it."""
    robot = redik.load("planar_2r")
    T_target = robot.fk(np.array([0.3, 0.6]))
    T_target[:3, :3] = T_target[:3, :3] @ lie.so3_exp([0.5, 0.0, 0.0])
    result = solve_pose(robot, T_target, seed=0, restarts=3)
    assert not result.success
    assert result.status in ("unreachable", "max_iterations")
    assert np.all(np.isfinite(result.q))
    assert result.rotation_error == pytest.approx(0.5, abs=1e-6)
    assert result.position_error < 1e-6


@pytest.mark.parametrize(
    "T_target",
    [
        np.full((4, 4), np.nan),
        np.eye(3),
        np.diag([2.0, 1.0, 1.0, 1.0]),  # not a rotation
        np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]], dtype=float),
    ],
    ids=["nan", "shape", "not-rigid", "last-row"],
)
def test_bad_targets_raise(arm, T_target):
    with pytest.raises(RedikError):
        solve_pose(arm, T_target)
    with pytest.raises(InvalidPose):
        solve_all(arm, T_target, n_starts=1)


@pytest.mark.parametrize(
    "T_target",
    ["abc", None, [[1.0, 0.0], "x"], {"p": 1.0}, np.eye(4, dtype=complex), object()],
    ids=["string", "none", "ragged", "dict", "complex", "object"],
)
def test_targets_that_are_not_numeric_matrices_name_the_value(arm, T_target):
    """Issue 11: ``solve_pose(robot, "abc")`` raised numpy's raw ValueError."""
    for method in ("dls", "newton"):
        with pytest.raises(InvalidPose, match="T_target") as raised:
            solve_pose(arm, T_target, method=method)
        assert "real numbers" in str(raised.value)
    with pytest.raises(InvalidPose, match="abc"):
        solve_pose(arm, "abc")


@pytest.mark.parametrize("method", ["dls", "newton", "hybrid", "transpose"])
def test_a_frame_no_joint_moves_is_refused(method):
    """Issue 11: ``frame="world"`` ran 1608 iterations instead of saying it cannot move."""
    robot = redik.load("panda")
    with pytest.raises(InvalidInput, match="world") as raised:
        solve_pose(robot, np.eye(4), frame="world", method=method)
    assert "no joint" in str(raised.value)
    with pytest.raises(InvalidInput, match="world"):
        solve_all(robot, np.eye(4), frame="world", n_starts=1)


def test_a_frame_some_joints_move_is_solved_with_those_joints():
    robot = redik.load("panda")
    q_goal = robot.random_q(np.random.default_rng(2))
    T_target = robot.fk(q_goal, "link3")
    result = solve_pose(robot, T_target, frame="link3", seed=0)
    assert result.success, result.message
    assert np.allclose(robot.fk(result.q, "link3"), T_target, atol=1e-5)
    assert np.array_equal(result.q[3:], robot.home[3:])  # joints 4-7 do not move link3


@pytest.mark.parametrize(
    "kwargs",
    [
        {"method": "secant"},
        {"pos_tol": 0.0},
        {"rot_tol": -1.0},
        {"max_iterations": 0},
        {"restarts": -1},
        {"q0": np.zeros(3)},
        {"q0": np.full(7, np.nan)},
        {"frame": "no_such_frame"},
        {"bogus_option": 1.0},
        {"method": "newton", "form": "diagonal"},
        {"method": "dls", "damping": -1.0},
        {"diagnose_limits": 1},
    ],
)
def test_bad_arguments_raise(arm, kwargs):
    with pytest.raises(RedikError):
        solve_pose(arm, arm.fk(arm.home), **kwargs)


def test_qp_is_dispatched_to_the_qp_core():
    robot = redik.load("iiwa14")
    T_target = robot.fk(robot.clip(robot.home + 0.2))
    result = solve_pose(robot, T_target, method="qp")
    assert isinstance(result, IKResult) and result.method == "qp"
    assert result.success, result.message
    check_solution(robot, result, T_target)


def test_body_twist_norm_from_the_world_error(rng):
    robot = redik.load("panda")
    for _ in range(10):
        T, T_d = robot.fk(robot.random_q(rng)), robot.fk(robot.random_q(rng))
        e = np.empty(6)
        PoseProblem(robot, robot.ee, T_d, 1e-6, 1e-5, True).world_error(T, e)
        expected = np.linalg.norm(lie.se3_log(lie.inverse(T) @ T_d))
        assert body_twist_norm(e) == pytest.approx(expected, rel=1e-12)


def test_solve_all_finds_the_elbow_up_and_down_solutions_of_a_planar_3r_arm():
    """Position and heading (x, y, φ) of a planar 3R arm: exactly two solutions."""
    robot = redik.load("planar_3r")
    q_goal = np.array([0.4, 1.2, -0.5])
    T_target = robot.fk(q_goal)
    solutions = solve_all(robot, T_target, n_starts=40, seed=0)
    assert len(solutions) == 2
    for solution in solutions:
        check_solution(robot, solution, T_target)
    elbows = sorted(s.q[1] for s in solutions)
    assert elbows[0] == pytest.approx(-1.2, abs=1e-5) and elbows[1] == pytest.approx(1.2, abs=1e-5)


def test_solve_all_compares_unlimited_angles_modulo_two_pi():
    robot = redik.load("ur5e")  # ranges of ±2π: q and q ± 2π are the same solution
    T_target = robot.fk(robot.home)
    solutions = solve_all(robot, T_target, n_starts=30, seed=3)
    assert 1 <= len(solutions) <= 8  # a 6R arm with an offset wrist has at most 8
    for a in solutions:
        check_solution(robot, a, T_target)
    for i, a in enumerate(solutions):
        for b in solutions[i + 1 :]:
            assert np.max(np.abs(lie.wrap_angle(a.q - b.q))) > 1e-3


def test_solve_all_rejects_bad_counts(arm):
    with pytest.raises(InvalidInput):
        solve_all(arm, arm.fk(arm.home), n_starts=0)


def test_dls_results_own_their_arrays_though_the_solver_state_is_reused(rng):
    """The compiled chain and buffers live on the robot; no result aliases them."""
    robot = redik.load("panda")
    first_target, second_target = (robot.fk(robot.random_q(rng)) for _ in range(2))
    first = solve_pose(robot, first_target, seed=0)
    q, history, errors = first.q.copy(), first.history.copy(), first.error_history.copy()
    assert len(solver_cache(robot)) == 1
    second = solve_pose(robot, second_target, robot.random_q(rng), seed=1)
    assert first.success and second.success
    np.testing.assert_array_equal(first.q, q)
    np.testing.assert_array_equal(first.history, history)
    np.testing.assert_array_equal(first.error_history, errors)
    assert len(solver_cache(robot)) == 1  # the same frame reuses its solver
    assert not solver_cache(redik.load("panda"))  # another robot owns its own


def test_scalar_options_take_numpy_numbers_and_refuse_bools_nan_and_inf():
    robot = redik.load("panda")
    T = robot.fk(robot.clip(robot.home + 0.1))
    for method, options in (("newton", {"step": np.float64(1.0)}),
                            ("transpose", {"step": np.float32(0.5)}),
                            ("hybrid", {"switch_error": np.float64(0.1)})):  # fmt: skip
        result = solve_pose(robot, T, method=method, pos_tol=np.float64(1e-6), seed=0, **options)
        assert result.success, (method, result.message)
    assert solve_all(robot, T, n_starts=20, seed=0, cluster_tol=np.float64(1e-3))
    for bad in (True, float("nan"), float("inf"), "1", -1.0):
        with pytest.raises(InvalidInput, match="step must be a finite positive number"):
            solve_pose(robot, T, method="newton", step=bad)
        with pytest.raises(InvalidInput, match="pos_tol must be a finite positive number"):
            solve_pose(robot, T, pos_tol=bad)
        with pytest.raises(InvalidInput, match="cluster_tol must be a finite positive number"):
            solve_all(robot, T, n_starts=1, cluster_tol=bad)


def test_a_repeated_dls_call_still_refuses_what_the_first_call_would(rng):
    """After a first solve, "dls" arguments seen before are checked in the compiled call;
    everything it does not accept as it is must still get the full validation's answer."""
    robot = redik.load("panda")
    T = robot.fk(robot.random_q(rng))
    q0 = robot.random_q(rng)
    reference = solve_pose(robot, T, q0, seed=0)
    assert reference.success
    # The same values in other layouts and types give the same answer.
    for T_like, q_like in (
        (np.asfortranarray(T), q0),
        (T.tolist(), q0.tolist()),
        (T, np.repeat(q0, 2)[::2]),
        (T.astype(np.float32).astype(float), q0.astype(np.float64)),
    ):
        again = solve_pose(robot, T_like, q_like, seed=0)
        np.testing.assert_allclose(again.q, reference.q, atol=1e-5)
    read_only = T.copy()
    read_only.setflags(write=False)
    np.testing.assert_array_equal(solve_pose(robot, read_only, q0, seed=0).q, reference.q)
    bad = T.copy()
    bad[0, 0] = np.nan
    with pytest.raises(InvalidPose, match="finite"):
        solve_pose(robot, bad, q0, seed=0)
    near = T.copy()
    near[:3, :3] *= 1.0 + 1e-4  # a near-rotation: projected with a warning, or refused
    with pytest.warns(NearRotationWarning):
        assert solve_pose(robot, near, q0, seed=0).success
    with pytest.raises(InvalidPose):
        solve_pose(robot, near, q0, seed=0, strict=True)
    for q_bad in (np.full(robot.dof, np.nan), np.full(robot.dof, 1e11), q0[:-1]):
        with pytest.raises(InvalidConfiguration):
            solve_pose(robot, T, q_bad, seed=0)
    # Arguments equal to accepted ones but of a refused type are still refused.
    solve_pose(robot, T, q0, seed=0, pos_tol=1, restarts=3)
    for bad_arguments in ({"pos_tol": True, "restarts": 3}, {"restarts": 3.0}, {"seed": -1}):
        with pytest.raises(InvalidInput):
            solve_pose(robot, T, q0, **{"seed": 0, **bad_arguments})
    with pytest.raises(InvalidInput, match="respect_limits"):
        solve_pose(robot, T, q0, seed=0, respect_limits=1)


def test_progress_is_a_fraction_for_dls():
    """``progress`` is a fraction in (0, 1): "dls" clamped 1.5 to 1 (an attempt stalls unless
    ‖e‖² reaches 0); "qp" (the task-stack driver) takes no such option."""
    robot = redik.load("panda")
    T = robot.fk(robot.clip(robot.home + 0.1))
    assert solve_pose(robot, T, method="dls", seed=0, progress=np.float64(0.25)).success
    for bad in (0.0, 1.0, 1.5, -0.5, float("nan"), True, "0.5"):
        with pytest.raises(InvalidInput, match=r"progress must be a number in \(0, 1\)"):
            solve_pose(robot, T, method="dls", seed=0, progress=bad)
    with pytest.raises(InvalidInput, match=r"unknown options \['progress'\] for method='qp'"):
        solve_pose(robot, T, method="qp", seed=0, progress=0.25)
    with pytest.raises(InvalidInput, match=r"progress must be a number in \(0, 1\)"):
        BatchOptions(progress=1.0)  # the compiled kernel's options, as "dls" passes them


def test_a_dls_option_of_a_refused_type_is_refused_after_an_equal_accepted_one():
    """``damping=1`` accepted, then ``damping=True`` (equal, same hash) found the kept
    settings and passed; on a fresh robot it is refused: the answer depended on history."""
    robot = redik.load("panda")
    T = robot.fk(robot.home)
    for accepted, refused in (
        ({"damping": 1}, {"damping": True}),
        ({"patience": 5}, {"patience": 5.0}),
        ({"patience": 1}, {"patience": True}),
    ):
        assert solve_pose(robot, T, seed=0, **accepted).success
        with pytest.raises(InvalidInput, match=next(iter(refused))):
            solve_pose(robot, T, seed=0, **refused)


def test_each_frame_argument_finds_its_own_dls_solver(rng):
    """A solve of another frame (with or without options) must not answer for the
    end-effector's later ones: each frame argument is remembered with its own solver."""
    robot = redik.load("panda")
    T_link = robot.fk(robot.random_q(rng), frame="link5")
    assert solve_pose(robot, T_link, frame="link5", seed=0, damping=0.2).success
    assert solve_pose(robot, T_link, frame="link5", seed=0).success
    T_ee = robot.fk(robot.random_q(rng))
    for _ in range(2):  # the first call resolves the frame, the second looks it up
        result = solve_pose(robot, T_ee, seed=0)
        check_solution(robot, result, T_ee)


@pytest.mark.parametrize("method", ["dls", "newton", "qp"])
def test_the_solvers_see_a_model_edited_after_the_first_solve(method, rng):
    """A tool change (the end-effector site moved) or a link moved between solves: MuJoCo's
    FK sees it at once, so must every method; ``"dls"`` kept its compiled chain and
    reported success on the old geometry (0.1 m off by MuJoCo's FK)."""
    robot = redik.load("panda")
    q_goal = robot.random_q(rng)
    for _ in range(2):  # the second call is the look-up path
        check_solution(robot, solve_pose(robot, robot.fk(q_goal), method=method, seed=0),
                       robot.fk(q_goal))  # fmt: skip
    for array, row in ((robot.model.site_pos, robot.ee.id), (robot.model.body_pos, 5)):
        array[row] += [0.0, 0.05, 0.1]
        T_target = robot.fk(q_goal)
        for _ in range(2):
            check_solution(robot, solve_pose(robot, T_target, method=method, seed=0), T_target)


@pytest.mark.parametrize("method", ["dls", "newton", "qp"])
def test_a_hinge_held_on_the_chain_keeps_its_held_value(method, rng):
    """``fixed=["joint4"]`` holds panda's elbow at its home value (−2.36 rad, not qpos0):
    the compiled chain of ``"dls"`` froze it at qpos0 and reported a wrong error; a new held
    value written into ``robot.state.data.qpos`` must be seen too."""
    robot = redik.Robot(redik.load("panda").model, fixed=["joint4"])
    assert "joint4" not in robot.joint_names
    for held in (None, -1.2):
        if held is not None:
            robot.state.data.qpos[3] = held
        q_goal = robot.random_q(rng)
        T_target = robot.fk(q_goal)
        q0 = robot.clip(q_goal + rng.uniform(-0.2, 0.2, robot.dof))
        for _ in range(2):
            result = solve_pose(robot, T_target, q0, method=method, seed=0)
            check_solution(robot, result, T_target)


@pytest.mark.parametrize("method", ["dls", "newton", "qp"])
def test_a_geom_frame_is_solved(method, rng):
    """``frame="geom:…"`` is a frame like a site or body (:meth:`Robot.frame`); it raised a
    raw IndexError (its id read as a body id), and the compiled chain ignored its offset."""
    robot = redik.load("panda")
    frame = "geom:link5"
    assert np.any(robot.model.geom_pos[robot.frame(frame).id] != 0)
    T_target = robot.fk(robot.random_q(rng), frame=frame)
    for _ in range(2):
        result = solve_pose(robot, T_target, method=method, seed=0, frame=frame)
        assert result.success, result.message
        errors = lie.pose_errors(robot.fk(result.q, frame=frame), T_target)
        assert errors[0] <= 1e-6 and errors[1] <= 1e-5


def test_dls_settings_evicted_by_another_thread_between_prepare_and_solve(monkeypatch):
    """Threads share a robot's dls solver; past 64 argument combinations one thread's
    ``prepare`` clears the kept settings, and another that had just prepared its own found
    none: a raw RuntimeError (4 threads × 3000 solves, 200 tolerances, switch interval
    1 µs). Here the eviction is placed in that window deterministically."""
    from redik.solvers.pose.dls import DLSSolver

    prepare = DLSSolver.prepare

    def prepare_then_evicted(self, *args, **kwargs):
        settings = prepare(self, *args, **kwargs)
        self.settings.clear()  # what another thread's prepare does when the table is full
        return settings

    monkeypatch.setattr(DLSSolver, "prepare", prepare_then_evicted)
    robot = redik.load("panda")
    T_target = robot.fk(robot.random_q(np.random.default_rng(4)))
    for pos_tol in (1e-6, 2e-6):
        result = solve_pose(robot, T_target, seed=0, pos_tol=pos_tol)
        check_solution(robot, result, T_target, pos_tol=pos_tol)


def test_a_read_only_or_strided_q0_and_target_take_the_fast_dls_path(monkeypatch):
    """``solve_pose(robot, T, robot.home)``: ``robot.home`` is read-only, and such a ``q0``
    (or a Fortran-ordered target) went through the full validation on every call, 2.4×
    slower; it is copied for the kernel instead, with the same answer."""
    from redik.solvers.pose import solve as solve_module

    robot = redik.load("panda")
    T_target = robot.fk(robot.random_q(np.random.default_rng(6)))
    reference = solve_pose(robot, T_target, robot.home.copy(), seed=0)  # prepares the settings
    validations = []
    as_pose = solve_module.as_pose
    monkeypatch.setattr(
        solve_module, "as_pose", lambda *a, **k: validations.append(1) or as_pose(*a, **k)
    )
    for q0, T in ((robot.home, T_target), (robot.home.copy(), np.asfortranarray(T_target))):
        result = solve_pose(robot, T, q0, seed=0)
        np.testing.assert_array_equal(result.q, reference.q)
    assert not validations
    assert not robot.home.flags.writeable
