"""The general 6R solver (redik.solvers.analytic.general) on arms with no closed form.

Every solution must reproduce the target by MuJoCo's FK (robot.fk, independent of the screw
chain and DH table the solver reads), the configuration that generated the target must be
among them, the count must be even and at most 16, and a dense multistart numeric solve must
find no root the solver lacks. A multistart is itself incomplete — near a singularity or on a
thin basin it can miss roots — so where it finds fewer, the test says so and checks only
that its roots are among the solver's.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

import redik
from redik.apps.bench.analytic import jaco, shadow_first_finger, two_special_arms
from redik.core.exceptions import InvalidInput, InvalidPose, ModelError
from redik.models.dh import DHRow
from redik.solvers import analytic
from redik.solvers.analytic import elimination, general, wrap_angle
from redik.solvers.analytic.geometry import classify, screws_of
from redik.solvers.pose import solve_all

FULL_TURN = [(-np.pi, np.pi)] * 6
FK_TOL = 1e-9


def _distance(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(wrap_angle(np.asarray(a) - np.asarray(b))).max())


def _random_screw_robot(rng: np.random.Generator, name: str = "random_6r") -> redik.Robot:
    """Six random axes through random points, a random flange pose: no two axes meet or are
    parallel (with probability one)."""
    axes = rng.normal(size=(6, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    points = rng.uniform(-0.5, 0.5, (6, 3))
    M = np.eye(4)
    M[:3, :3] = Rotation.random(random_state=int(rng.integers(1 << 30))).as_matrix()
    M[:3, 3] = rng.uniform(-0.5, 0.5, 3)
    S = np.vstack([axes.T, np.cross(-axes, points).T])
    return redik.Robot.from_screws(S, M, limits=FULL_TURN, name=name)


def _random_dh_rows(rng: np.random.Generator) -> list[DHRow]:
    """Every a_i, d_i and α_i non-zero."""
    sign = rng.choice([-1.0, 1.0], 6)
    return [
        DHRow(a, d, s * alpha)
        for a, d, s, alpha in zip(
            rng.uniform(0.1, 0.5, 6),
            rng.uniform(0.1, 0.5, 6),
            sign,
            rng.uniform(0.3, 1.3, 6),
            strict=True,
        )
    ]


def _check(robot: redik.Robot, solver, n_poses: int, seed: int) -> list[int]:
    """Solve poses of random q; check FK, the generating q and the count; return the counts."""
    rng = np.random.default_rng(seed)
    counts = []
    for _ in range(n_poses):
        q_true = rng.uniform(-np.pi, np.pi, 6)
        T = robot.fk(q_true)
        solutions = solver(T)
        assert solutions.reachable
        for q in solutions:
            assert np.abs(robot.fk(q) - T).max() < FK_TOL
        assert min(_distance(q, q_true) for q in solutions) < 1e-7
        assert len(solutions) <= elimination.MAX_SOLUTIONS and len(solutions) % 2 == 0
        pairwise = [_distance(a, b) for i, a in enumerate(solutions) for b in solutions[:i]]
        assert min(pairwise, default=1.0) > 1e-6  # distinct
        assert not solutions.singular  # a random pose is regular
        counts.append(len(solutions))
    return counts


def test_random_screw_arms_give_every_solution_verified_by_fk():
    rng = np.random.default_rng(11)
    counts = []
    for index in range(6):
        robot = _random_screw_robot(rng, f"screws_{index}")
        solver = analytic.solver_for(robot)
        assert isinstance(solver, general.GeneralSolver)
        assert (solver.method, solver.kind) == ("elimination", "general")
        counts += _check(robot, solver, 8, seed=index)
    assert max(counts) >= 6  # the poses are not all of the simplest kind


def test_dh_arms_with_every_parameter_nonzero():
    rng = np.random.default_rng(5)
    for index in range(4):
        robot = redik.Robot.from_dh(_random_dh_rows(rng), limits=FULL_TURN, name=f"dh_{index}")
        S, M = screws_of(robot)
        assert classify(S, M) is None
        solver = analytic.solver_for(robot)
        assert solver.kind == "general"
        _check(robot, solver, 8, seed=10 + index)


@pytest.mark.parametrize("special", ["a", "alpha"])
@pytest.mark.parametrize("joint", [0, 2, 4])
def test_one_intersecting_or_parallel_pair_anywhere(special, joint):
    """a_k = 0 (axes k+1 and k+2 meet) or α_k = 0 (parallel): no decomposition class fits;
    the elimination still applies (run backwards when the pair is the first one)."""
    rng = np.random.default_rng(100 + joint)
    rows = _random_dh_rows(rng)
    row = rows[joint]
    rows[joint] = DHRow(0.0, row.d, row.alpha) if special == "a" else DHRow(row.a, row.d, 0.0)
    robot = redik.Robot.from_dh(rows, limits=FULL_TURN, name="one_special_pair")
    solver = analytic.solver_for(robot)
    assert solver.kind == "general"
    _check(robot, solver, 6, seed=joint)


def test_solution_set_equals_a_dense_multistart_numeric_solve():
    rng = np.random.default_rng(2)
    robot = _random_screw_robot(rng)
    solver = analytic.solver_for(robot)
    for seed in range(3):
        q_true = np.random.default_rng(seed).uniform(-np.pi, np.pi, 6)
        T = robot.fk(q_true)
        exact = solver(T).as_array()
        numeric = [r.q for r in solve_all(robot, T, n_starts=250, seed=seed, pos_tol=1e-9)]
        assert len(numeric) == len(exact)
        for q in numeric:
            assert min(_distance(q, e) for e in exact) < 1e-5


def test_solve_all_analytic_uses_the_general_solver():
    robot = _random_screw_robot(np.random.default_rng(4))
    T = robot.fk(np.array([0.3, -0.8, 1.2, 0.4, -1.1, 2.0]))
    results = solve_all(robot, T, method="analytic")
    exact = analytic.solver_for(robot)(T).as_array()
    assert len(results) == len(exact) >= 2
    assert all(r.success and r.method == "analytic:general" for r in results)
    assert all(r.position_error < FK_TOL and r.rotation_error < FK_TOL for r in results)
    for r in results:
        assert min(_distance(r.q, e) for e in exact) < 1e-12
    with pytest.raises(InvalidInput, match="no options"):
        solve_all(robot, T, method="analytic", damping=1.0)


def test_solve_all_analytic_on_a_bundled_arm_gives_its_closed_form():
    robot = redik.load("ur5e")
    T = robot.fk(np.array([0.3, -1.2, 1.4, -1.6, -1.5, 0.4]))
    results = solve_all(robot, T, method="analytic")
    assert len(results) == len(analytic.solver_for(robot)(T)) == 8
    assert results[0].method == "analytic:three_parallel_two_intersecting"


def test_unreachable_target_and_limits():
    robot = _random_screw_robot(np.random.default_rng(3))
    solver = analytic.solver_for(robot)
    far = np.eye(4)
    far[:3, 3] = (50.0, 0.0, 0.0)
    result = solver(far)
    assert not result.reachable and len(result) == 0 and "reaches" in result.reason
    T = robot.fk(np.array([0.5, 0.2, -0.3, 1.0, -0.4, 0.1]))
    every = solver(T, limits=None)
    lower, upper = np.full(6, -0.5), np.full(6, 1.1)
    inside = solver(T, limits=(lower, upper))
    expected = [q for q in every if np.all((q >= lower) & (q <= upper))]
    assert len(inside) == len(expected) >= 1
    np.testing.assert_allclose(solver.raw(T, limits=None), every.as_array())


def test_bad_input_and_degenerate_arms_are_refused():
    robot = _random_screw_robot(np.random.default_rng(6))
    solver = analytic.solver_for(robot)
    bad = np.eye(4)
    bad[0, 3] = np.nan
    with pytest.raises(InvalidPose):
        solver(bad)
    with pytest.raises(InvalidInput):
        solver(np.eye(4), limits="joints")
    with pytest.raises(ModelError, match="prismatic"):
        analytic.general_solver(*screws_of(redik.load("stanford_arm")))


def test_singular_targets_where_two_solutions_merge_are_found(monkeypatch):
    """On det J = 0 two of the 16 roots coincide (a double root, split by rounding into a
    near-real complex pair): the configuration is still found, once, verified by FK, through
    the multiplicity step (the null space of the double root split by the shift)."""
    multiplicities = []
    split = elimination.monomials_of

    def spy(M, psi, k):
        multiplicities.append(k)
        return split(M, psi, k)

    monkeypatch.setattr(elimination, "monomials_of", spy)
    rng = np.random.default_rng(11)
    robot = _random_screw_robot(rng)
    solver = analytic.solver_for(robot)
    found = 0
    while found < 3:
        q0, direction = rng.uniform(-np.pi, np.pi, 6), rng.normal(size=6)

        def determinant(t: float, q0=q0, direction=direction) -> float:
            return float(np.linalg.det(robot.jacobian(q0 + t * direction)))

        grid = np.linspace(-1.0, 1.0, 100)
        values = [determinant(t) for t in grid]
        crossings = [i for i in range(99) if values[i] * values[i + 1] < 0.0]
        if not crossings:
            continue
        t = brentq(determinant, grid[crossings[0]], grid[crossings[0] + 1], xtol=1e-15)
        q_singular = q0 + t * direction
        T = robot.fk(q_singular)
        solutions = solver(T)
        nearest = min(solutions, key=lambda q: _distance(q, q_singular))
        assert _distance(nearest, q_singular) < 1e-7 and nearest.singular
        assert all(np.abs(robot.fk(q) - T).max() < FK_TOL for q in solutions)
        assert sum(bool(q.singular) for q in solutions) == 1
        found += 1
    assert multiplicities and set(multiplicities) == {2}


def test_a_pose_with_fourteen_solutions_all_found():
    """A random arm and pose (found by a seeded search) with 14 real solutions, close to the
    bound of 16: every one is found, verified, and a 600-start multistart finds the same 14."""
    rng = np.random.default_rng(36)
    robot = _random_screw_robot(rng)
    q_true = rng.uniform(-np.pi, np.pi, (40, 6))[4]
    T = robot.fk(q_true)
    exact = analytic.solver_for(robot)(T)
    assert len(exact) == 14 and not exact.singular
    assert min(_distance(q, q_true) for q in exact) < 1e-9
    assert all(np.abs(robot.fk(q) - T).max() < FK_TOL for q in exact)
    numeric = [r.q for r in solve_all(robot, T, n_starts=600, seed=0, pos_tol=1e-9)]
    assert len(numeric) == 14
    assert all(min(_distance(q, e) for e in exact) < 1e-6 for q in numeric)


def _multistart_within(robot, T, exact, seed, starts=600):
    """The multistart's distinct roots (tight tolerance), each checked to be one of
    ``exact``; returns how many it found."""
    numeric = [r.q for r in solve_all(robot, T, n_starts=starts, seed=seed, pos_tol=1e-9)]
    for q in numeric:
        assert min(_distance(q, e) for e in exact) < 1e-5, "the multistart found a root we lack"
    return len(numeric)


def test_the_jaco_is_solved_by_the_rebased_elimination():
    """Kinova's Jaco²: consecutive axes meet or are parallel but the wrist axes share no
    point, so no closed form; every standard split is singular (special pairs at both ends)
    and the elimination re-based through the target link is regular."""
    robot = jaco()
    solver = analytic.solver_for(robot)
    assert solver.kind == "general" and solver.elimination.split == "rebased"
    counts = _check(robot, solver, 6, seed=21)
    assert max(counts) >= 6


def test_the_shadow_finger_and_every_two_special_arm_are_solved():
    """The arms a single standard elimination refused: the Shadow hand's first finger (3∩4,
    4∥5∥6) and 40 arms with two special consecutive pairs, every combination — none refused,
    each finds its probes' and two more targets' generating configurations."""
    finger = shadow_first_finger()
    _check(finger, analytic.solver_for(finger), 4, seed=22)
    for name, robot in two_special_arms():
        solver = analytic.solver_for(robot)
        assert solver.kind in ("general", *analytic.geometry.KINDS), name
        rng = np.random.default_rng(7)
        for q in rng.uniform(-np.pi, np.pi, (2, 6)):
            T = robot.fk(q)
            solutions = solver(T, limits=None)
            assert min(_distance(s, q) for s in solutions) < 1e-7, name
            assert all(np.abs(robot.fk(s) - T).max() < FK_TOL for s in solutions), name


@pytest.mark.slow
@pytest.mark.parametrize("builder", [jaco, shadow_first_finger])
def test_special_arms_lack_no_root_of_a_600_start_multistart(builder):
    robot = builder()
    solver = analytic.solver_for(robot)
    rng = np.random.default_rng(23)
    for seed, q in enumerate(rng.uniform(-np.pi, np.pi, (2, 6))):
        T = robot.fk(q)
        exact = solver(T, limits=None).as_array()
        assert _multistart_within(robot, T, exact, seed) <= len(exact)
