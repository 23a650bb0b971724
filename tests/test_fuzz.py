"""Property-based fuzzing of every public entry point with malformed and extreme input.

The contract (issue 11): a call either raises a :class:`redik.RedikError` (possibly after a
documented :class:`redik.RedikWarning`) or returns a result whose status says what happened —
never a raw exception, never a stray numpy/Python warning, never a NaN in a returned ``q`` or
error, never a returned ``q`` outside the joint limits. Inputs: NaN/inf, huge (1e300) and tiny
values, wrong shapes and dtypes, non-rotations, near-rotations, unreachable targets, ``q``
outside the limits, empty arrays.

Runs are reproducible (``derandomize=True``) and small (a few dozen examples per entry point)
so that the file stays well under a minute; every failure these found has a plain regression
test beside the code it fixed (listed at the end of this file).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import redik
from redik import lie
from redik.core.result import Status
from redik.core.rotation_policy import (
    as_pose,
    as_quaternion,
    as_rotation,
    check_rotations,
    closest_rotation,
    rotation_defect,
)
from redik.core.validate import as_vector
from redik.solvers.analytic import BatchSolutions, IKSolutions

FUZZ = settings(
    max_examples=250,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
SLOW = settings(FUZZ, max_examples=80)

EXTREMES = [math.nan, math.inf, -math.inf, 1e300, -1e300, 1e-300, -1e-300, 0.0, -0.0, 1e-12]


@pytest.fixture(scope="module")
def panda() -> redik.Robot:
    return redik.load("panda")


@pytest.fixture(scope="module")
def ur5e() -> redik.Robot:
    return redik.load("ur5e")


# --------------------------------------------------------------------------------------
# The contract


def _finite(array: object, what: str) -> None:
    values = np.asarray(array, dtype=float)
    assert np.all(np.isfinite(values)), f"{what} holds NaN or inf: {values}"


def _inside(robot: redik.Robot, q: np.ndarray, what: str) -> None:
    q = np.asarray(q)
    assert np.all(q >= robot.lower) and np.all(q <= robot.upper), (
        f"{what} outside the limits: {q} not in [{robot.lower}, {robot.upper}]"
    )


def check_result(out: object, robot: redik.Robot | None = None, limited: bool = True) -> None:
    """Assert the output half of the contract for every result type redik returns."""
    if isinstance(out, redik.IKResult):
        assert isinstance(out.status, Status)
        _finite(out.q, "IKResult.q")
        _finite(out.error, "IKResult.error")
        for value in (out.position_error, out.rotation_error):
            if value is not None:
                _finite(value, "IKResult pose error")
        if robot is not None and limited:
            _inside(robot, out.q, "IKResult.q")
    elif isinstance(out, list):
        for item in out:
            check_result(item, robot, limited)
    elif isinstance(out, IKSolutions):
        for solution in out:
            _finite(solution, f"solution {solution.label}")
        assert len(out) > 0 or out.reason or out.reachable
        assert isinstance(out.status, Status) and out.success == (len(out) > 0)
    elif isinstance(out, BatchSolutions):
        _finite(out.q[out.valid], "BatchSolutions.q (valid slots)")
    elif isinstance(out, redik.BatchResult):
        _finite(out.q, "BatchResult.q")
        if robot is not None:
            for q in out.q:
                _inside(robot, q, "BatchResult.q")
        # An invalid target's errors are NaN, documented; every other error is a number.
        assert all(isinstance(status, Status) for status in out.statuses)
        invalid = out.status_names == "invalid"
        assert np.array_equal(np.isnan(out.position_error), invalid)
        assert np.array_equal(np.isnan(out.rotation_error), invalid)
    elif isinstance(out, redik.SelfMotion):
        _finite(out.samples, "SelfMotion.samples")
        if robot is not None:
            for q in out.samples:
                _inside(robot, q, "SelfMotion sample")
        _finite(out.position_error, "SelfMotion.position_error")
        assert isinstance(out.status, Status)
    elif isinstance(out, redik.JointTrajectory):
        _finite(out.q, "JointTrajectory.q")
        _finite(out.position_error, "JointTrajectory.position_error")
        if robot is not None:
            for q in out.q:
                _inside(robot, q, "JointTrajectory.q")
    elif isinstance(out, np.ndarray):
        _finite(out, "returned array")


def holds(
    call: Callable[[], object],
    robot: redik.Robot | None = None,
    limited: bool = True,
    elementwise: bool = False,
):
    """Run ``call`` under the contract; the result, or None when it raised a RedikError.

    ``elementwise`` marks a numeric function (``wrap_angle``, ``rotation_defect``) that maps
    NaN to NaN by design: its output is then not checked for finiteness."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a stray RuntimeWarning/ComplexWarning is a failure
        warnings.simplefilter("ignore", redik.RedikWarning)  # documented repairs
        try:
            out = call()
        except redik.RedikError as error:
            event(f"refused: {type(error).__name__}")
            return None
    event(f"returned {type(out).__name__}")
    if not elementwise:
        check_result(out, robot, limited)
    return out


# --------------------------------------------------------------------------------------
# Strategies

extreme = st.sampled_from(EXTREMES)
number = st.one_of(extreme, st.floats(-10, 10), st.floats(allow_nan=True, allow_infinity=True))


def junk() -> st.SearchStrategy:
    """Anything that is not a well-formed numeric array."""
    dtypes = st.sampled_from(["complex128", "U3", "object", "bool", "int64", "float32"])
    return st.one_of(
        st.none(),
        st.text(max_size=4),
        st.booleans(),
        number,
        st.lists(st.one_of(number, st.none(), st.text(max_size=2)), max_size=5),
        st.lists(st.lists(number, max_size=3), max_size=3),  # ragged
        hnp.arrays(np.float64, hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=5)),
        dtypes.flatmap(
            lambda dtype: (
                hnp.arrays(
                    dtype, hnp.array_shapes(min_dims=1, max_dims=2, max_side=7), elements=None
                )
                if dtype != "object"
                else st.just(np.array([None, 1.0, "x"], dtype=object))
            )
        ),
    )


@st.composite
def rotations(draw: st.DrawFn) -> np.ndarray:
    """Exact, near (typed from a book), bad, reflected or non-finite 3 × 3 matrices."""
    omega = np.array(draw(st.lists(st.floats(-4, 4), min_size=3, max_size=3)))
    R = lie.so3_exp(omega)
    kind = draw(st.sampled_from(["exact", "3 decimals", "noise", "reflection", "extreme"]))
    if kind == "3 decimals":
        R = np.round(R, 3)
    elif kind == "noise":
        scale = draw(st.sampled_from([1e-7, 1e-5, 1e-3, 2.5e-3, 1e-2, 1.0]))
        noise = np.array(draw(st.lists(st.floats(-1, 1), min_size=9, max_size=9)))
        R = R + scale * noise.reshape(3, 3)
    elif kind == "reflection":
        R = R @ np.diag([1.0, 1.0, -1.0])
    elif kind == "extreme":
        R = R.copy()
        R[draw(st.integers(0, 2)), draw(st.integers(0, 2))] = draw(extreme)
    return R


@st.composite
def poses(draw: st.DrawFn) -> np.ndarray:
    """4 × 4 matrices around the rigid transforms: bad rotation blocks, far, huge or
    non-finite translations, a wrong bottom row."""
    T = np.eye(4)
    T[:3, :3] = draw(rotations())
    reach = draw(st.sampled_from([0.5, 3.0, 1e3, 1e300]))
    T[:3, 3] = np.array(draw(st.lists(st.floats(-1, 1), min_size=3, max_size=3))) * reach
    if draw(st.integers(0, 9)) == 0:
        T[draw(st.integers(0, 2)), 3] = draw(extreme)
    if draw(st.integers(0, 9)) == 0:
        T[3, draw(st.integers(0, 3))] += draw(st.sampled_from([1e-9, 1e-3, 1.0, math.nan]))
    return T


def mostly(good: st.SearchStrategy, *bad: st.SearchStrategy) -> st.SearchStrategy:
    """``good`` two times in three, else one of ``bad``: malformed input is cheap to refuse,
    so most examples should get far enough to exercise the solver."""
    return st.integers(0, 2).flatmap(lambda pick: good if pick else st.one_of(*bad))


def pose_or_junk() -> st.SearchStrategy:
    return st.one_of(poses(), poses(), junk())


@st.composite
def reachable(draw: st.DrawFn, robot: redik.Robot) -> np.ndarray:
    """A pose the robot reaches (``fk`` inside the limits), as computed, typed with three
    decimals, or moved out of reach."""
    u = np.array(draw(st.lists(st.floats(0, 1), min_size=robot.dof, max_size=robot.dof)))
    T = robot.fk(robot.sampling_lower + u * (robot.sampling_upper - robot.sampling_lower))
    kind = draw(st.sampled_from(["exact", "3 decimals", "far"]))
    if kind == "3 decimals":
        T = np.round(T, 3)
    elif kind == "far":
        T[:3, 3] *= draw(st.sampled_from([2.0, 10.0, 1e9]))
    return T


def targets(robot: redik.Robot) -> st.SearchStrategy:
    """Mostly poses a solver gets to work on, some malformed ones, some junk."""
    return st.integers(0, 9).flatmap(
        lambda pick: reachable(robot) if pick < 6 else poses() if pick < 8 else junk()
    )


@st.composite
def configurations(draw: st.DrawFn, robot: redik.Robot) -> object:
    """Joint vectors: inside the limits, outside them, extreme entries, or junk."""
    kind = draw(st.sampled_from(["inside", "outside", "extreme", "junk"]))
    if kind == "junk":
        return draw(junk())
    u = np.array(draw(st.lists(st.floats(0, 1), min_size=robot.dof, max_size=robot.dof)))
    q = robot.sampling_lower + u * (robot.sampling_upper - robot.sampling_lower)
    if kind == "outside":
        q = q * draw(st.sampled_from([3.0, 100.0, 1e6]))
    elif kind == "extreme":
        q[draw(st.integers(0, robot.dof - 1))] = draw(extreme)
    return q


# --------------------------------------------------------------------------------------
# Models and group math


@FUZZ
@given(name=st.one_of(junk(), st.text(max_size=300), st.sampled_from(["panda", "ur5e", ""])))
def test_load(name):
    holds(lambda: redik.load(name))


@FUZZ
@given(data=st.data())
def test_fk_and_jacobian(panda, data):
    q = data.draw(configurations(panda))
    frame = data.draw(st.one_of(st.none(), st.sampled_from(["ee", "nowhere", "link3"]), junk()))
    reference = data.draw(st.sampled_from(["space", "body", "world", "hybrid", None]))
    holds(lambda: panda.fk(q, frame))
    holds(lambda: panda.jacobian(q, frame, reference))


@FUZZ
@given(R=st.one_of(rotations(), junk()), T=pose_or_junk(), strict=st.booleans())
def test_lie_validators(R, T, strict):
    holds(lambda: as_rotation(R, strict=strict))
    holds(lambda: as_pose(T, strict=strict))
    holds(lambda: as_vector(R, 3, "x"))
    holds(lambda: as_quaternion(R))
    holds(lambda: closest_rotation(R))
    holds(lambda: rotation_defect(T), elementwise=True)
    holds(lambda: check_rotations(np.asarray(R)[None] if isinstance(R, np.ndarray) else R))
    holds(lambda: lie.wrap_angle(R), elementwise=True)


@FUZZ
@given(R=rotations(), T=poses(), omega=st.lists(number, min_size=3, max_size=3))
def test_lie_maps_on_validated_input(R, T, omega):
    """The group maps take validated input (the hot path does not check): once a matrix is
    accepted by the validators, every map gives a finite, consistent answer."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", redik.RedikWarning)
            R = as_rotation(R)
            T = as_pose(T)
    except redik.RedikError:
        return
    if not np.all(np.abs(T[:3, 3]) < 1e150):  # squared in the log map's translation
        return
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for value in (
            lie.so3_log(R),
            lie.se3_log(T),
            lie.quat_from_matrix(R),
            lie.euler_angles(R, "zyz"),
            lie.adjoint(T),
            lie.inverse(T),
            lie.interpolate_pose(np.eye(4), T, 0.5),
        ):
            _finite(value, "lie map")
        omega = np.asarray(omega, dtype=float)
        if np.all(np.isfinite(omega)) and np.all(np.abs(omega) < 1e6):
            _finite(lie.so3_exp(omega), "so3_exp")
            _finite(lie.wrap_angle(omega), "wrap_angle")


# --------------------------------------------------------------------------------------
# Pose IK


def options() -> st.SearchStrategy:
    """Tolerances, budgets, seeds and frames: mostly sane, sometimes junk."""
    return st.fixed_dictionaries(
        {},
        optional={
            "pos_tol": st.one_of(st.just(1e-4), number, junk()),
            "rot_tol": st.one_of(st.just(1e-3), number, junk()),
            "seed": st.one_of(st.integers(-5, 2**70), junk()),
            "frame": st.one_of(st.sampled_from(["ee", "link7", "nowhere"]), junk()),
            "respect_limits": st.one_of(st.booleans(), junk()),
        },
    )


@SLOW
@given(data=st.data())
@pytest.mark.parametrize("method", redik.solvers.pose.METHODS)
def test_solve_pose(panda, method, data):
    T = data.draw(targets(panda))
    q0 = data.draw(st.one_of(st.none(), configurations(panda)))
    strict = data.draw(st.booleans())
    kwargs = data.draw(mostly(st.just({}), options()))
    kwargs["max_iterations"] = data.draw(mostly(st.just(15), st.integers(-1, 3), number, junk()))
    kwargs["restarts"] = data.draw(mostly(st.just(1), st.integers(-1, 2), number, junk()))
    limited = kwargs.get("respect_limits", True) is not False
    holds(
        lambda: redik.solve_pose(panda, T, q0, method=method, strict=strict, **kwargs),
        panda,
        limited,
    )


@SLOW
@given(data=st.data(), n_starts=st.one_of(st.integers(-1, 3), junk()))
def test_solve_all(panda, data, n_starts):
    T = data.draw(targets(panda))
    cluster_tol = data.draw(mostly(st.just(1e-3), number, junk()))
    holds(
        lambda: redik.solve_all(
            panda, T, n_starts=n_starts, seed=0, max_iterations=10, cluster_tol=cluster_tol
        ),
        panda,
    )


@FUZZ
@given(
    x_d=mostly(st.lists(st.floats(-3, 3), min_size=2, max_size=2), st.lists(number), junk()),
    q0=mostly(st.lists(st.floats(-1e3, 1e3), min_size=2, max_size=2), st.lists(number), junk()),
    step=mostly(st.sampled_from([0.5, "armijo"]), st.sampled_from([0.0, -1.0, "x"]), number),
    tol=mostly(st.just(1e-6), number),
)
def test_newton_and_gradient(x_d, q0, step, tol):
    def f(q):  # defined for any length of q, so that every failure is redik's
        return np.array([np.cos(q).sum(), np.sin(q).sum() + np.tanh(q).sum()])

    holds(
        lambda: redik.solve_equations(f, x_d, q0, step=step if step != "armijo" else 1.0, tol=tol)
    )
    holds(
        lambda: redik.solve_equations(f, x_d, q0, "gradient", step=step, tol=tol, max_iterations=20)
    )


# --------------------------------------------------------------------------------------
# Task stacks


@SLOW
@given(data=st.data())
def test_problem_and_task_targets(panda, data):
    task = redik.FrameTask("ee", target=panda.fk(panda.home))
    orientation = redik.OrientationTask("ee", target=np.eye(3), priority=1)
    problem = redik.Problem(panda, [task, orientation, redik.PostureTask(panda.home, priority=1)])
    holds(lambda: task.set_target(data.draw(targets(panda)), strict=data.draw(st.booleans())))
    holds(lambda: orientation.set_target(data.draw(st.one_of(rotations(), junk()))))
    holds(lambda: redik.PositionTask("ee", target=data.draw(st.one_of(junk(), poses()))))
    q = data.draw(configurations(panda))
    holds(lambda: redik.solve_problem(problem, q, redik.SolveOptions(max_iterations=5)), panda)
    holds(lambda: problem.step(q))
    cost = data.draw(mostly(st.just(1.0), number, junk()))
    gain = data.draw(mostly(st.just(0.5), number, junk()))
    priority = data.draw(mostly(st.just(1), st.integers(-2, 2), number, junk()))
    holds(lambda: redik.PostureTask(data.draw(configurations(panda)), cost=cost))
    holds(lambda: redik.JointLimitAvoidanceTask(cost, gain, priority))
    holds(
        lambda: redik.FrameTask(
            "ee",
            target=panda.fk(panda.home),
            position_cost=cost,
            orientation_cost=cost,
            gain=gain,
            priority=priority,
        )
    )
    holds(lambda: redik.DampingTask(cost, priority))
    holds(lambda: redik.ManipulabilityTask(None, cost, gain, priority))
    holds(
        lambda: redik.solve_problem(
            redik.Problem(
                panda,
                data.draw(mostly(st.just([task]), st.just([]), junk())),
                data.draw(mostly(st.none(), st.just([]), junk())),
                data.draw(mostly(st.sampled_from(["daqp", "quadprog"]), junk())),
                damping=data.draw(mostly(st.just(1e-6), number, junk())),
            ),
            panda.home,
            redik.SolveOptions(
                max_iterations=data.draw(mostly(st.just(3), st.integers(-1, 2), junk())),
                restarts=0,
            ),
        ),
        panda,
    )


@SLOW
@given(data=st.data(), strict=st.booleans())
def test_solve_batch(panda, data, strict):
    stack = st.lists(st.one_of(reachable(panda), poses()), min_size=0, max_size=4)
    T = data.draw(st.one_of(stack.map(lambda ts: np.array(ts).reshape(-1, 4, 4)), junk()))
    q0 = data.draw(st.one_of(st.none(), configurations(panda), junk()))
    restarts = data.draw(mostly(st.just(1), st.integers(-1, 2), number, junk()))
    tol = data.draw(mostly(st.just(1e-6), number, junk()))
    chunk = data.draw(mostly(st.none(), st.integers(-1, 3), number, junk()))
    engine = data.draw(mostly(st.just("local"), st.text(max_size=5), junk()))
    holds(
        lambda: redik.solve_batch(
            panda, T, q0, pos_tol=tol, restarts=restarts, max_iterations=10, strict=strict,
            chunk_size=chunk, engine=engine,
        ),
        panda,
    )  # fmt: skip


# --------------------------------------------------------------------------------------
# Closed form


@FUZZ
@given(data=st.data(), strict=st.booleans(), limits=st.sampled_from([None, "robot", "junk"]))
def test_analytic_solvers(ur5e, data, strict, limits):
    T = data.draw(targets(ur5e))
    solver = redik.solvers.analytic.solver_for(ur5e)
    chosen = {"junk": (np.zeros(6), np.full(5, np.nan)), "robot": "robot", None: None}[limits]
    holds(lambda: solver(T, limits=chosen, strict=strict))
    holds(lambda: solver.raw(T, limits=chosen, strict=strict))
    holds(lambda: solver.batch([T], limits=chosen, strict=strict))
    holds(lambda: solver.batch(T, limits=chosen, strict=strict))


@FUZZ
@given(
    R=st.one_of(rotations(), junk()),
    p=st.one_of(st.lists(number, min_size=3, max_size=3), junk()),
    length=st.one_of(st.just(0.3), number, junk()),
)
def test_analytic_small_solvers(R, p, length):
    holds(lambda: redik.solvers.analytic.spherical_wrist(R, "ZYX"))
    holds(
        lambda: redik.solvers.analytic.planar_2r(
            p[0] if isinstance(p, list) and p else p, 0.2, length, 0.3
        )
    )
    holds(lambda: redik.solvers.analytic.planar_3r(0.3, 0.1, p, 0.3, 0.3, length))
    holds(lambda: redik.solvers.analytic.rrp_polar(p, length))
    holds(lambda: redik.solvers.analytic.hexapod_leg(p, 0.05, length, 0.1))
    holds(lambda: redik.solvers.analytic.planar_2r_batch(p, 0.3, length))
    holds(
        lambda: redik.solvers.analytic.planar_2r_batch(
            [p[:2]] if isinstance(p, list) else p, 0.3, 0.3
        )
    )


@FUZZ
@given(method=st.one_of(st.text(max_size=8), junk(), st.sampled_from(["closed_form", "ur"])))
def test_solver_for(ur5e, method):
    holds(lambda: redik.solvers.analytic.solver_for(ur5e, method))


# --------------------------------------------------------------------------------------
# Redundancy and trajectories


@FUZZ
@given(data=st.data(), damping=mostly(st.sampled_from([0.0, 0.1]), number, junk()))
def test_nullspace_velocity(data, damping):
    m, n = data.draw(st.integers(0, 6)), data.draw(st.integers(0, 7))

    def vectors(*shape: int) -> st.SearchStrategy:
        plain = hnp.arrays(np.float64, shape, elements=st.floats(-2, 2))
        return mostly(plain, hnp.arrays(np.float64, shape, elements=extreme), junk())

    J, twist = data.draw(vectors(m, n)), data.draw(vectors(m))
    dq0 = data.draw(st.one_of(st.none(), vectors(n)))
    holds(lambda: redik.nullspace_velocity(J, twist, dq0, damping))


@SLOW
@given(data=st.data(), spacing=mostly(st.none(), number), initial=mostly(st.none(), junk()))
def test_explore_self_motion(panda, data, spacing, initial):
    T = data.draw(targets(panda))
    n_starts = data.draw(mostly(st.just(2), st.integers(-1, 1), junk()))
    max_samples = data.draw(mostly(st.just(40), st.integers(-1, 2), junk()))
    nominal = data.draw(mostly(st.none(), configurations(panda)))
    holds(
        lambda: redik.explore_self_motion(
            panda, T, spacing=spacing, n_starts=n_starts, max_samples=max_samples, seed=0,
            initial=initial, nominal=nominal,
        ),
        panda,
    )  # fmt: skip


@SLOW
@given(
    data=st.data(),
    times=mostly(st.none(), st.lists(number, min_size=0, max_size=3), junk()),
    rate=mostly(st.just(20.0), number),
)
def test_cartesian_path_and_follow_path(panda, data, times, rate):
    waypoints = data.draw(
        mostly(st.lists(targets(panda), min_size=2, max_size=3), st.lists(targets(panda)), junk())
    )
    center = data.draw(mostly(st.just([0.3, 0.0, 0.5]), st.lists(number, max_size=4), junk()))
    normal = data.draw(mostly(st.just([0.0, 0.0, 1.0]), st.lists(number, max_size=4), junk()))
    duration = data.draw(mostly(st.just(1.0), number, junk()))
    start = waypoints[0] if isinstance(waypoints, list) and waypoints else waypoints
    circle = holds(lambda: redik.apps.trajectory.CircularPath(start, center, normal, duration))
    if circle is not None:
        holds(lambda: circle.sample(rate), elementwise=not math.isfinite(rate))
    path = holds(lambda: redik.CartesianPath(waypoints, times))
    if path is None:
        return
    holds(lambda: path.sample(rate))
    if path.duration * rate <= 40:  # keep the solves few; the rest checks the rate
        q0 = data.draw(configurations(panda))
        jump_tol = data.draw(mostly(st.just(0.1), number, junk()))
        holds(lambda: redik.follow_path(panda, path, q0, rate=rate, jump_tol=jump_tol), panda)


# --------------------------------------------------------------------------------------
# Plain regression tests: one per failure the fuzzing found (each failed before its fix)


def test_pose_translation_beyond_mjmaxval_is_refused_everywhere(panda, ur5e):
    # Found by test_problem_and_task_targets: a FrameTask 1e143 m away overflowed the QP and
    # daqp raised a raw RuntimeError ("Model has not been set up").
    T = np.eye(4)
    T[2, 3] = 1e143
    with pytest.raises(redik.InvalidPose, match="beyond ±1e\\+10 m"):
        redik.FrameTask("ee", target=T)
    with pytest.raises(redik.InvalidPose, match="beyond"):
        redik.solvers.analytic.solver_for(ur5e)(T)
    with pytest.raises(redik.InvalidPose, match="beyond"):
        redik.solvers.analytic.solver_for(ur5e).batch(T[None])
    result = redik.solve_batch(panda, T[None], restarts=0, max_iterations=1)
    assert result.status_names.tolist() == ["invalid"]
    T[2, 3] = 1e9  # far, but a number MuJoCo and the QP handle: an explicit status
    task = redik.FrameTask("ee", target=T)
    problem = redik.Problem(panda, [task])
    result = redik.solve_problem(problem, panda.home, redik.SolveOptions(max_iterations=3))
    assert result.status == "unreachable" and "beyond the reach" in result.message


@pytest.mark.parametrize("q", [np.zeros(7) + 1j, np.array([""] * 7), np.full(7, 1e11)])
def test_problem_step_refuses_non_real_or_huge_q(panda, q):
    # Found by test_problem_and_task_targets: step() cast complex q (ComplexWarning) and
    # failed on strings with a raw ValueError.
    problem = redik.Problem(panda, [redik.FrameTask("ee", target=panda.fk(panda.home))])
    with pytest.raises(redik.InvalidConfiguration):
        problem.step(q)


def test_newton_and_gradient_refuse_junk_and_overflowing_input():
    # Found by test_newton_and_gradient: x_d="" raised a raw ValueError; x_d = 1e300 overflowed
    # ‖e‖ (RuntimeWarning) and could overflow Armijo's ½‖e‖² (OverflowError).
    def f(q):
        return np.array([np.cos(q).sum(), np.sin(q).sum()])

    for method in ("newton", "gradient"):
        with pytest.raises(redik.InvalidInput, match="x_d must hold real numbers"):
            redik.solve_equations(f, "", [0.0, 0.0], method)
        with pytest.raises(redik.InvalidInput, match="x_d must be within"):
            redik.solve_equations(f, [1e300, 0.0], [0.0, 0.0], method)
        with pytest.raises(redik.InvalidInput, match=r"f\(q0\) must hold real numbers"):
            redik.solve_equations(lambda q: np.array(["a", "b"]), [0.0, 0.0], [0.0, 0.0], method)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = redik.solve_equations(
            lambda q: 1e140 * q**3, [0.0], [1.0], "gradient", step="armijo", max_iterations=5
        )
    assert np.isfinite(result.q).all() and np.isfinite(result.error)


def test_solver_for_and_analytic_targets_refuse_junk(ur5e):
    # Found by test_solver_for / test_analytic_solvers: a list as family name raised
    # "unhashable type"; a string target a raw ValueError.
    with pytest.raises(redik.InvalidInput, match="method must be"):
        redik.solvers.analytic.solver_for(ur5e, [])  # type: ignore[arg-type]
    with pytest.raises(redik.InvalidInput, match="target must hold real numbers"):
        redik.solvers.analytic.solver_for(ur5e)("")


@pytest.mark.parametrize(
    "value", [[1.0, [2.0]], "1.5", 10**400, 1e300, np.array(2.0 + 1j)]
)  # fmt: skip
def test_analytic_scalars_refuse_ragged_strings_and_huge_values(value):
    # Found by test_analytic_small_solvers: a ragged list raised a raw ValueError in np.ndim,
    # "1.5" was parsed as a number, 10**400 overflowed float(), 1e300 overflowed the kernel.
    with pytest.raises(redik.InvalidInput, match="x must be"):
        redik.solvers.analytic.planar_2r(value, 0.2, 0.3, 0.3)


def test_analytic_batch_refuses_huge_coordinates():
    with pytest.raises(redik.InvalidInput, match="within ±1e\\+10"):
        redik.solvers.analytic.planar_2r_batch([[1e300, 1e300]], 0.3, 0.3)


def test_nullspace_velocity_refuses_junk_and_overflowing_input():
    # Found by test_nullspace_velocity: junk arrays raised raw ValueErrors, damping=None a
    # TypeError, damping=1e300 an OverflowError from λ².
    J, twist = np.ones((2, 3)), np.ones(2)
    for bad in ("", None, np.zeros(0), 1e300, math.nan, -1.0):
        with pytest.raises(redik.InvalidInput, match="damping"):
            redik.nullspace_velocity(J, twist, damping=bad)  # type: ignore[arg-type]
    with pytest.raises(redik.InvalidInput, match="J must"):
        redik.nullspace_velocity("", twist)
    with pytest.raises(redik.InvalidInput, match="twist must"):
        redik.nullspace_velocity(J, [1.0, [2.0]])
    with pytest.raises(redik.InvalidInput, match="within"):
        redik.nullspace_velocity(J * 1e200, twist)


def test_frame_of_an_unhashable_name_is_an_unknown_frame(panda):
    # Found by test_fk_and_jacobian: a list as frame name raised "unhashable type".
    with pytest.raises(redik.UnknownFrame, match="named by a string"):
        panda.fk(panda.home, [])  # type: ignore[arg-type]


@pytest.mark.parametrize("poses", [None, 3.0, np.array(1.0), "ab"])
def test_cartesian_path_refuses_what_is_not_a_pose_sequence(poses):
    # Found by test_cartesian_path_and_follow_path: len() of None / a 0-d array raised
    # TypeError.
    with pytest.raises(redik.InvalidInput, match="at least two waypoint poses"):
        redik.CartesianPath(poses)  # type: ignore[arg-type]


def test_cartesian_path_refuses_junk_times():
    # Found by test_cartesian_path_and_follow_path: times="" raised a raw ValueError.
    with pytest.raises(redik.InvalidInput, match="times must hold real numbers"):
        redik.CartesianPath([np.eye(4), np.eye(4)], "")  # type: ignore[arg-type]


def test_solve_pose_refuses_a_non_bool_respect_limits_and_junk_seeds(panda):
    # Found by test_solve_pose: respect_limits=None was read as False and the returned q
    # left the joint limits; a junk seed raised inside numpy.
    T = panda.fk(panda.home)
    with pytest.raises(redik.InvalidInput, match="respect_limits must be True or False"):
        redik.solve_pose(panda, T, respect_limits=None)  # type: ignore[arg-type]
    for seed in ("", -1, [0.5]):
        with pytest.raises(redik.InvalidInput, match="seed must be"):
            redik.solve_pose(panda, T, method="newton", seed=seed)  # type: ignore[arg-type]
    with pytest.raises(redik.InvalidInput, match="method must be one of"):
        redik.solve_pose(panda, T, method=np.array([]))  # type: ignore[arg-type]


def test_problem_and_tasks_refuse_junk_arguments(panda):
    # Found by test_problem_and_task_targets: tasks=1.0 / None raised "not iterable",
    # backend=None a TypeError inside make_backend, damping="" a numpy TypeError,
    # max_iterations=None a comparison TypeError, gain/priority junk raw ValueErrors.
    task = redik.FrameTask("ee", target=panda.fk(panda.home))
    for tasks in (1.0, None, np.array(0.0)):
        with pytest.raises(redik.InvalidInput, match="tasks must be a list"):
            redik.Problem(panda, tasks)  # type: ignore[arg-type]
    for backend in (None, [], 3):
        with pytest.raises(redik.BackendError, match="a back-end is a name"):
            redik.Problem(panda, [task], backend=backend)  # type: ignore[arg-type]
    with pytest.raises(redik.InvalidInput, match="damping"):
        redik.Problem(panda, [task], damping="")  # type: ignore[arg-type]
    problem = redik.Problem(panda, [task])
    with pytest.raises(redik.InvalidInput, match="max_iterations"):
        redik.SolveOptions(max_iterations=None)  # type: ignore[arg-type]
    with pytest.raises(redik.InvalidInput, match="pos_tol"):
        redik.SolveOptions(pos_tol=math.nan)
    with pytest.raises(redik.InvalidInput, match="options must be a SolveOptions"):
        redik.solve_problem(problem, panda.home, {"max_iterations": 3})  # type: ignore[arg-type]
    with pytest.raises(redik.InvalidInput, match="gain"):
        redik.JointLimitAvoidanceTask(1.0, "")  # type: ignore[arg-type]
    with pytest.raises(redik.InvalidInput, match="priority"):
        redik.DampingTask(1.0, math.nan)  # type: ignore[arg-type]
    with pytest.raises(redik.InvalidInput, match="gain"):
        redik.ManipulabilityTask(gain=None)  # type: ignore[arg-type]


def test_huge_task_costs_are_refused_and_daqp_failures_are_backend_errors(panda):
    # Found by test_problem_and_task_targets: a FrameTask cost of 1e100 reached daqp, whose
    # set-up failed; the next solve raised a raw RuntimeError ("Model has not been set up").
    with pytest.raises(redik.InvalidInput, match=r"position_cost must be in \[0, 1e\+06\]"):
        redik.FrameTask("ee", target=panda.fk(panda.home), position_cost=1e100)
    from redik.qp.backends import DaqpBackend
    from redik.qp.problem_data import QP

    with pytest.raises(redik.BackendError, match="daqp"):
        DaqpBackend().solve(QP(np.full((2, 2), np.inf), np.ones(2), -np.ones(2), np.ones(2)))


def test_solve_batch_refuses_junk_options(panda):
    # Found by test_solve_batch: junk q0, chunk_size, engine and seed raised raw numpy or
    # Python errors.
    T = panda.fk(panda.home)[None]
    bad = [
        ({"q0": ""}, "q0 must hold real numbers"),
        ({"chunk_size": 1.5}, "chunk_size must be an integer ≥ 1"),
        ({"chunk_size": ""}, "chunk_size"),
        ({"engine": np.array([])}, "engine must be an Engine or one of"),
        ({"seed": ""}, "seed must be"),
        ({"seed": -1}, "seed must be"),
        ({"workers": "x"}, "workers must be"),
    ]
    for kwargs, message in bad:
        with pytest.raises(redik.InvalidInput, match=message):
            redik.solve_batch(panda, T, restarts=0, max_iterations=1, **kwargs)


def test_explore_self_motion_refuses_junk_options(panda):
    # Found by test_explore_self_motion: max_samples=None raised a TypeError deep in the
    # explorer; spacing="" and junk initial raw ValueErrors.
    T = panda.fk(panda.home)
    bad = [
        ({"max_samples": None}, "max_samples must be"),
        ({"spacing": ""}, "spacing must be"),
        ({"initial": ""}, "initial must hold real numbers"),
        ({"seed": "x"}, "seed must be"),
    ]
    for kwargs, message in bad:
        with pytest.raises(redik.InvalidInput, match=message):
            redik.explore_self_motion(panda, T, n_starts=1, **kwargs)


def test_path_sampling_refuses_an_infinite_rate_or_too_many_samples():
    # Found by test_cartesian_path_and_follow_path at 250 examples: rate=inf raised
    # OverflowError (int of inf); times [0, 1e300] would allocate 1e302 samples.
    path = redik.CartesianPath([np.eye(4), np.eye(4)])
    with pytest.raises(redik.InvalidInput, match="rate must be a finite positive number"):
        path.sample(math.inf)
    with pytest.raises(redik.InvalidInput, match="MAX_SAMPLES"):
        redik.CartesianPath([np.eye(4), np.eye(4)], [0.0, 1e300]).sample(1.0)


def test_newton_refuses_an_empty_q0():
    # Found by test_newton_and_gradient at 250 examples: q0=[] gave a 2 × 0 Jacobian and a
    # raw numpy ValueError inside np.linalg.solve.
    with pytest.raises(redik.InvalidInput, match="q0 must hold at least one"):
        redik.solve_equations(lambda q: np.array([1.0, 2.0]), [0.0, 1.0], [])


def test_circular_path_refuses_junk_center_normal_and_duration():
    # Found by test_cartesian_path_and_follow_path once CircularPath was added: center=""
    # and normal="" raised raw ValueErrors, duration=None a comparison TypeError.
    T = np.eye(4)
    T[0, 3] = 0.5
    for kwargs, message in (
        ({"center": ""}, "center must hold real numbers"),
        ({"normal": ""}, "normal must hold real numbers"),
        ({"normal": [0.0, 0.0, 0.0]}, "normal non-zero"),
        ({"duration": None}, "duration must be a finite positive number"),
    ):
        arguments = {"center": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0], "duration": 1.0}
        with pytest.raises(redik.InvalidInput, match=message):
            redik.apps.trajectory.CircularPath(T, **{**arguments, **kwargs})
    path = redik.apps.trajectory.CircularPath(
        T, [0.0, 0.0, 0.0], [0.0, 0.0, 1e300], 1.0
    )  # no overflow
    assert path.radius == pytest.approx(0.5)
