"""Strict priorities: higher levels are never degraded; lower levels optimal in what is left."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest

import redik
from redik.limits import ConfigurationLimit
from redik.qp import QP, Problem, make_backend, solve_lexicographic
from redik.qp.hierarchy import SLACK_DAMPING, free_directions
from redik.tasks import (
    DampingTask,
    FrameTask,
    KinematicState,
    ManipulabilityTask,
    PositionTask,
    PostureTask,
)


def level_residual(problem: Problem, level: int, q: np.ndarray, dq: np.ndarray) -> float:
    """½‖A Δq − b‖² + joint terms of a level, evaluated without damping."""
    state = KinematicState.for_robot(problem.robot)
    state.update(q)
    H, c = problem._assembly.objectives(state)[level]
    H = H - problem.damping * np.eye(len(dq))
    return float(0.5 * dq @ H @ dq + c @ dq)


def test_level0_is_identical_with_and_without_conflicting_lower_levels(rng):
    robot = redik.load("panda")
    for _ in range(5):
        q = robot.random_q(rng)
        q = np.clip(q, robot.lower + 0.3, robot.upper - 0.3)
        T = robot.fk(robot.random_q(rng))
        alone = Problem(robot, [PositionTask("ee", target=T[:3, 3])], limits=[])
        stacked = Problem(
            robot,
            [
                PositionTask("ee", target=T[:3, 3]),
                PostureTask(robot.random_q(rng), cost=5.0, priority=1),  # pulls elsewhere
                ManipulabilityTask(cost=1.0, gain=3.0, priority=2),
            ],
            limits=[],
        )
        dq_alone, dq_stacked = alone.step(q), stacked.step(q)
        J = robot.jacobian(q, reference="world")[:3]
        # The task-space step is the same; the joint step is not (the null space is used).
        np.testing.assert_allclose(J @ dq_stacked, J @ dq_alone, atol=1e-9)
        assert np.linalg.norm(dq_stacked - dq_alone) > 1e-3
        assert (
            level_residual(stacked, 0, q, dq_stacked)
            <= level_residual(alone, 0, q, dq_alone) + 1e-10
        )


def test_lower_level_is_optimal_within_the_higher_optimal_set(rng):
    """Compare with the textbook two-stage program: min f1 s.t. J0 Δq = J0 Δq0*, box."""
    robot = redik.load("panda")
    for _ in range(4):
        q = robot.random_q(rng)
        T = robot.fk(robot.random_q(rng))
        q_nominal = robot.random_q(rng)
        problem = Problem(
            robot,
            [FrameTask("ee", target=T), PostureTask(q_nominal, priority=1)],
            [ConfigurationLimit()],
        )
        dq = problem.step(q)
        # Stage 1 then stage 2 in cvxpy, the box the limit imposes.
        box = problem.limits[0]
        lb, ub = box.lower - q, box.upper - q
        state = KinematicState.for_robot(robot)
        state.update(q)
        (H0, c0), (H1, c1) = problem._assembly.objectives(state)
        x = cp.Variable(7)
        box = [x >= lb, x <= ub]
        cp.Problem(cp.Minimize(0.5 * cp.quad_form(x, cp.psd_wrap(H0)) + c0 @ x), box).solve()
        A0 = problem._assembly.levels[0].A
        stage2 = cp.Problem(
            cp.Minimize(0.5 * cp.quad_form(x, cp.psd_wrap(H1)) + c1 @ x),
            [*box, A0 @ x == A0 @ dq],
        )
        stage2.solve()
        value = 0.5 * dq @ H1 @ dq + c1 @ dq
        assert value <= stage2.value + 1e-7
        # and dq lies in level 0's optimal set: its level-0 objective is the optimum.
        f0 = 0.5 * dq @ H0 @ dq + c0 @ dq
        f0_star = 0.5 * x.value @ H0 @ x.value + c0 @ x.value  # any stage-2 point is optimal
        assert abs(f0 - f0_star) < 1e-7


def test_solve_lexicographic_on_a_synthetic_hierarchy():
    # Level 0 fixes x0 + x1 = 1; level 1 wants x = (3, 0, 0); level 2 wants x2 = −1.
    A0 = np.array([[1.0, 1.0, 0.0]])
    H0, c0 = A0.T @ A0, -A0.T @ np.array([1.0])
    H1, c1 = np.diag([1.0, 1.0, 0.0]), -np.array([3.0, 0.0, 0.0])
    H2, c2 = np.diag([0.0, 0.0, 1.0]), np.array([0.0, 0.0, 1.0])
    eps = 1e-9
    objectives = [(H + eps * np.eye(3), c) for H, c in ((H0, c0), (H1, c1), (H2, c2))]
    backends = [make_backend("daqp") for _ in objectives]
    x = solve_lexicographic(objectives, backends, damping=eps)
    np.testing.assert_allclose(x, [2.0, -1.0, -1.0], atol=1e-6)
    # With a box x2 ≥ −0.5, the last level stops at the bound; the others are unchanged.
    lb, ub = np.array([-10.0, -10.0, -0.5]), np.full(3, 10.0)
    x = solve_lexicographic(objectives, backends, lb, ub, damping=eps)
    np.testing.assert_allclose(x, [2.0, -1.0, -0.5], atol=1e-6)


def test_a_second_order_term_changes_level_1_model_only_when_it_stays_convex():
    # Level 0 fixes x0 + x1 = 1 (null space: (1, −1)/√2); level 1 wants x = (3, 0, 0).
    A0 = np.array([[1.0, 1.0, 0.0]])
    eps = 1e-9
    objectives = [
        (A0.T @ A0 + eps * np.eye(3), -A0.T @ np.array([1.0])),
        (np.diag([1.0, 1.0, 1.0]) + eps * np.eye(3), -np.array([3.0, 0.0, 0.0])),
    ]
    plain = solve_lexicographic(objectives, [make_backend("daqp") for _ in objectives], damping=eps)

    def run(m, **bounds):
        backends = [make_backend("daqp") for _ in objectives]
        seen = []

        def curvature1(N):
            seen.append(N.shape)
            return m * np.eye(N.shape[1])

        x = solve_lexicographic(objectives, backends, damping=eps, curvature1=curvature1, **bounds)
        assert seen and seen[0][0] == 3
        return x

    # The reduced model: h = 1 (+ m) along u = (1, −1, 0)/√2 and 1 along e₂; the level-1
    # gradient at level 0's x = (½, ½, 0) along u is −3/√2: the step along u is 3/(√2 (1 + m)).
    u = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0)
    for m in (1.0, -0.5):
        np.testing.assert_allclose(run(m), [0.5, 0.5, 0.0] + 3.0 / np.sqrt(2.0) / (1 + m) * u,
                                   atol=1e-7)  # fmt: skip
    # Not convex enough (1 − 0.995 < the margin): level 1's own Hessian, the plain step.
    np.testing.assert_allclose(run(-0.995), plain, atol=1e-9)
    # Through the one-variable path (a box and a third level-0 row leave one direction).
    objectives[0] = (objectives[0][0] + np.diag([0.0, 0.0, 1.0]), objectives[0][1])
    lb, ub = np.full(3, -10.0), np.full(3, 10.0)
    plain = solve_lexicographic(
        objectives, [make_backend("daqp") for _ in objectives], lb, ub, damping=eps
    )
    np.testing.assert_allclose(plain, [2.0, -1.0, 0.0], atol=1e-6)
    np.testing.assert_allclose(run(1.0, lb=lb, ub=ub), [1.25, -0.25, 0.0], atol=1e-6)
    np.testing.assert_allclose(run(-0.995, lb=lb, ub=ub), plain, atol=1e-9)


def test_a_least_squares_level_skips_a_tolerance_based_back_end_when_no_bound_binds(rng):
    from redik.qp.hierarchy import least_squares_minimiser

    A, b = rng.normal(size=(6, 7)), rng.normal(size=6)
    eps = 1e-9
    H, c = A.T @ A + eps * np.eye(7), -A.T @ b
    # The reference from the augmented least squares [A; √ε I] x ≈ [b; 0] (H's own solve
    # loses ~1e-7 to its condition number σ²/ε).
    exact = np.linalg.lstsq(np.vstack([A, np.sqrt(eps) * np.eye(7)]), np.r_[b, np.zeros(7)])[0]
    wide = np.full(7, 1e3)
    np.testing.assert_allclose(least_squares_minimiser(A, b, eps, -wide, wide, None, None, None),
                               exact, atol=1e-9)  # fmt: skip
    tight = np.abs(exact).max() / 2
    assert least_squares_minimiser(A, b, eps, -wide / wide * tight, wide / wide * tight,
                                   None, None, None) is None  # fmt: skip
    row = np.eye(7)[:1]
    assert least_squares_minimiser(A, b, eps, None, None, row, exact[:1] + 0.1, [np.inf]) is None
    assert (
        least_squares_minimiser(
            rng.normal(size=(7, 7)), rng.normal(size=7), eps, None, None, None, None, None
        )
        is None
    )  # fmt: skip  (not wide)
    # A two-level step on proxsuite is then exact where no bound binds (ProxQP alone stops
    # up to ~1e-7 away along the near-null directions of H = AᵀA + εI), and a binding
    # bound still goes to the back-end.
    H1, c1 = np.eye(7) + eps * np.eye(7), -np.arange(7.0)
    objectives = [(H, c), (H1, c1)]
    for bound, atol in ((wide, 1e-10), (np.full(7, tight), 1e-5)):
        x, reference = (
            solve_lexicographic(
                objectives, [make_backend(name) for _ in objectives], -bound, bound,
                damping=eps, rows0=A, rhs0=b,
            )
            for name in ("proxsuite", "quadprog")
        )  # fmt: skip
        np.testing.assert_allclose(x, reference, atol=atol)


def test_free_directions_drop_the_linear_term_direction():
    H = np.diag([1.0, 0.0, 0.0])
    N = free_directions(H, np.zeros(3), 1e-10)
    assert N.shape == (3, 2) and np.allclose(N[0], 0.0)
    # A linear term along x1 also fixes x1: one direction left, along x2.
    N = free_directions(H, np.array([0.0, 1.0, 0.0]), 1e-10)
    assert N.shape == (3, 1) and abs(abs(N[2, 0]) - 1.0) < 1e-12
    # The shift (regularisation) is discounted.
    assert free_directions(H + 1e-6 * np.eye(3), np.zeros(3), 1e-10, 1e-6).shape == (3, 2)


def test_damping_task_at_the_lowest_level_gives_the_damped_minimum_norm_step(rng):
    robot = redik.load("panda")
    q = np.clip(robot.random_q(rng), robot.lower + 0.3, robot.upper - 0.3)
    target = robot.fk(robot.random_q(rng))[:3, 3]
    problem = Problem(
        robot, [PositionTask("ee", target=target), DampingTask(priority=1)], limits=[]
    )
    dq = problem.step(q)
    J = robot.jacobian(q, reference="world")[:3]
    e = robot.fk(q)[:3, 3] - target
    # Level 0 alone leaves the null space of J free (its damping only shrinks the range
    # part); the damping level then removes any null-space motion: Jᵀ(JJᵀ + εI)⁻¹.
    reference = -J.T @ np.linalg.solve(J @ J.T + problem.damping * np.eye(3), e)
    np.testing.assert_allclose(dq, reference, atol=1e-9)


def test_row_null_space_spans_the_free_directions_and_defers_when_rank_deficient(rng):
    from redik.qp.hierarchy import row_null_space

    for m, n in ((6, 7), (3, 7), (5, 6)):
        A = rng.normal(size=(m, n))
        N = row_null_space(A, 1e-10)
        assert N.shape == (n, n - m)
        np.testing.assert_allclose(N.T @ N, np.eye(n - m), atol=1e-12)
        np.testing.assert_allclose(A @ N, 0.0, atol=1e-12)
        reference = free_directions(A.T @ A + 1e-6 * np.eye(n), np.zeros(n), 1e-10, 1e-6)
        np.testing.assert_allclose(N @ N.T, reference @ reference.T, atol=1e-9)
    singular = rng.normal(size=(6, 7))
    singular[5] = singular[4]  # rank 5: the QR is not rank-revealing, eigh decides
    assert row_null_space(singular, 1e-10) is None
    assert free_directions(singular.T @ singular, np.zeros(7), 1e-10).shape == (7, 2)
    assert row_null_space(rng.normal(size=(7, 7)), 1e-10) is None


def test_the_one_variable_level_is_solved_exactly(rng):
    from redik.qp.hierarchy import _solve_one_variable

    reference = make_backend("quadprog")
    for _ in range(500):
        rows = int(rng.integers(1, 9))
        a = rng.normal(size=rows) * (rng.random(rows) > 0.2)  # some rows do not involve z
        lower, upper = -rng.exponential(size=rows), rng.exponential(size=rows)
        lower[rng.random(rows) < 0.2] = -np.inf
        upper[rng.random(rows) < 0.2] = np.inf
        h, g = rng.exponential(), 3.0 * rng.normal()
        z = _solve_one_variable(h, g, a.tolist(), lower.tolist(), upper.tolist())
        qp = QP(np.array([[h]]), np.array([g]), C=a[:, None], l=lower, u=upper)
        assert z == pytest.approx(reference.solve(qp)[0], abs=1e-9)
    # A bound the previous level violated by its tolerance is relaxed to 0, not enforced.
    assert _solve_one_variable(1.0, -1.0, [1.0], [-1.0], [-1e-12]) == 0.0
    # A row without z (a = 0) that the previous level violated leaves z free, either way.
    assert _solve_one_variable(1.0, 1.0, [0.0], [-1.0], [-1e-12]) == -1.0
    assert _solve_one_variable(1.0, -1.0, [0.0], [1e-12], [1.0]) == 1.0


def test_a_round_off_component_on_a_joint_at_its_bound_does_not_block_the_direction():
    """A self-motion direction with an exact zero on a joint, computed as ±1e-16, while level
    0 leaves that joint on its bound: the row moves by round-off only and must not stop the
    whole motion at z = 0."""
    from redik.qp.hierarchy import _solve_one_variable

    for gain in (1e-16, -1e-16, 1e-12):
        for upper, lower in ((0.0, -1.0), (1.0, 0.0)):
            assert _solve_one_variable(1.0, -1.0, [gain, 1.0], [lower, -5.0], [upper, 5.0]) == 1.0
    # A gain above the round-off still binds.
    assert _solve_one_variable(1.0, -1.0, [1e-9], [-1.0], [0.0]) == 0.0
    # Through the hierarchy: level 0 pins x0 on its bound; the one free direction of level 1
    # carries a 1e-16 component on x0 and must still reach x1 = 3.
    A0 = np.array([[1.0, 1e-16, 0.0], [0.0, 0.0, 1.0]])
    eps = 1e-12
    objectives = [
        (A0.T @ A0 + eps * np.eye(3), -A0.T @ np.array([0.5, 0.0])),
        (np.diag([0.0, 1.0, 0.0]) + eps * np.eye(3), -np.array([0.0, 3.0, 0.0])),
    ]
    lb, ub = np.array([-1.0, -10.0, -10.0]), np.array([0.5, 10.0, 10.0])
    x = solve_lexicographic(objectives, [make_backend("daqp") for _ in objectives], lb, ub,
                            damping=eps, rows0=A0)  # fmt: skip
    np.testing.assert_allclose(x, [0.5, 3.0, 0.0], atol=1e-6)


def test_a_one_dimensional_lower_level_with_rows_matches_the_general_path():
    # Level 0 fixes x0 + x1 = 1 and x2 = 0: one free direction, (1, −1, 0)/√2. Level 1
    # wants x0 = 3; the row x0 − x1 ≤ 2 stops it at x = (1.5, −0.5, 0).
    A0 = np.array([[1.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    eps = 1e-9
    objectives = [
        (A0.T @ A0 + eps * np.eye(3), -A0.T @ np.array([1.0, 0.0])),
        (np.diag([1.0, 0.0, 0.0]) + eps * np.eye(3), -np.array([3.0, 0.0, 0.0])),
    ]
    C, l, u = np.array([[1.0, -1.0, 0.0]]), np.array([-np.inf]), np.array([2.0])
    backends = [make_backend("daqp") for _ in objectives]
    for rows0 in (A0, None):  # QR null space, eigendecomposition
        x = solve_lexicographic(objectives, backends, C=C, l=l, u=u, damping=eps, rows0=rows0)
        np.testing.assert_allclose(x, [1.5, -0.5, 0.0], atol=1e-6)


def test_a_one_dimensional_lower_level_without_constraints():
    A0 = np.array([[1.0, 1.0]])
    eps = 1e-9
    objectives = [
        (A0.T @ A0 + eps * np.eye(2), -A0.T @ np.array([1.0])),
        (np.diag([1.0, 0.0]) + eps * np.eye(2), -np.array([3.0, 0.0])),
    ]
    backends = [make_backend("daqp") for _ in objectives]
    x = solve_lexicographic(objectives, backends, damping=eps, rows0=A0)
    np.testing.assert_allclose(x, [3.0, -2.0], atol=1e-6)


def test_ranked_rows_bind_the_levels_from_theirs_down_and_yield_to_those_above():
    # Level 0 wants x0 = 1, level 1 wants x1 = 1; the rows x0 ≤ 0, x1 ≤ 0.5.
    eps = 1e-9
    objectives = [
        (np.diag([1.0, 0.0]) + eps * np.eye(2), np.array([-1.0, 0.0])),
        (np.diag([0.0, 1.0]) + eps * np.eye(2), np.array([0.0, -1.0])),
    ]
    G, h = np.eye(2), np.array([0.0, 0.5])

    def solve(**kwargs):
        backends = [make_backend("daqp") for _ in objectives]
        return solve_lexicographic(objectives, backends, damping=eps, **kwargs)

    np.testing.assert_allclose(solve(), [1.0, 1.0], atol=1e-6)
    hard = solve(C=G, l=np.full(2, -np.inf), u=h)
    np.testing.assert_allclose(hard, [0.0, 0.5], atol=1e-6)
    for index, expected in ((0, [0.0, 0.5]), (1, [1.0, 0.5]), (2, [1.0, 1.0])):
        # Before level 0: hard; between the levels: level 0 breaks x0 ≤ 0 (its least
        # violation), level 1 keeps x1 ≤ 0.5; after level 1: no freedom left to use.
        x = solve(ranked=[(index, G, h, make_backend("daqp"))])
        np.testing.assert_allclose(x, expected, atol=1e-6, err_msg=f"ranked at {index}")
    # Rows no point meets (x0 ≤ 0 and x0 ≥ 1): hard, infeasible; ranked above level 0, the
    # least violation (x0 = ½, damped by ρ: 1/(2 + ρ)), which level 0 then keeps.
    G2, h2 = np.array([[1.0, 0.0], [-1.0, 0.0]]), np.array([0.0, -1.0])
    with pytest.raises(redik.InfeasibleProblem):
        solve(C=G2, l=np.full(2, -np.inf), u=h2)
    x = solve(ranked=[(0, G2, h2, make_backend("daqp"))])
    assert x[0] == pytest.approx(1.0 / (2.0 + SLACK_DAMPING), abs=1e-6)
    assert x[1] == pytest.approx(1.0, abs=1e-6)
