"""The iterative methods on a user's function: rates, shapes, stopping rules, misuse, and the
course notes' worked examples (000: the Case Study and the minimum-coordinate algorithm; 002:
the 2R case study and the RRP numerical tests), reproduced at their printed precision."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import redik
from redik.core.exceptions import InvalidInput, RedikError
from redik.solvers.iterative import finite_difference_jacobian, solve_equations

L1, L2 = 1.0, 0.8


def two_link(q: np.ndarray) -> np.ndarray:
    """Planar 2R arm: tip position (x, y)."""
    return np.array(
        [
            L1 * np.cos(q[0]) + L2 * np.cos(q[0] + q[1]),
            L1 * np.sin(q[0]) + L2 * np.sin(q[0] + q[1]),
        ]
    )


def two_link_jacobian(q: np.ndarray) -> np.ndarray:
    s1, c1 = np.sin(q[0]), np.cos(q[0])
    s12, c12 = np.sin(q[0] + q[1]), np.cos(q[0] + q[1])
    return np.array([[-L1 * s1 - L2 * s12, -L2 * s12], [L1 * c1 + L2 * c12, L2 * c12]])


X_D = two_link(np.array([0.4, 1.1]))


def quadratic_pairs(errors: np.ndarray) -> list[tuple[float, float]]:
    """Consecutive ``(e_k, e_k+1)`` in the terminal regime of a run."""
    return [(a, b) for a, b in itertools.pairwise(errors) if 1e-9 < a < 1e-2]


def test_finite_difference_jacobian_matches_the_analytic_one(rng):
    for _ in range(5):
        q = rng.uniform(-3, 3, size=2)
        np.testing.assert_allclose(
            finite_difference_jacobian(two_link, q), two_link_jacobian(q), atol=1e-9
        )


@pytest.mark.parametrize("jac", [two_link_jacobian, None], ids=["analytic", "finite-diff"])
def test_newton_converges_quadratically_on_a_2r_arm(jac):
    result = solve_equations(two_link, X_D, [0.2, 1.4], jac=jac, tol=1e-12)
    assert result.success and result.status == "converged" and result.method == "newton"
    np.testing.assert_allclose(two_link(result.q), X_D, atol=1e-12)
    e = result.error_history
    assert e[0] == pytest.approx(np.linalg.norm(X_D - two_link(np.array([0.2, 1.4]))))
    terminal = quadratic_pairs(e)
    assert terminal and all(b <= 10.0 * a**2 for a, b in terminal)
    assert result.history.shape == (result.iterations + 1, 2)
    np.testing.assert_array_equal(result.history[0], [0.2, 1.4])


def test_transpose_with_armijo_never_increases_the_error():
    result = solve_equations(two_link, X_D, [0.2, 1.4], "transpose", two_link_jacobian,
                             step="armijo", tol=1e-8, max_iterations=5000)  # fmt: skip
    assert result.status == "converged"
    assert np.all(np.diff(result.error_history) <= 0.0)
    newton = solve_equations(two_link, X_D, [0.2, 1.4], tol=1e-8)
    assert result.iterations > newton.iterations  # linear, not quadratic


def test_transpose_with_a_too_large_constant_step_can_increase_the_error():
    result = solve_equations(
        two_link, X_D, [0.2, 1.4], "transpose", two_link_jacobian, step=2.5, max_iterations=20
    )
    assert np.any(np.diff(result.error_history) > 0.0)
    assert np.all(np.isfinite(result.q))


def test_fat_jacobian_takes_the_least_norm_step():
    """r = 1 < n = 3: a linear task is solved in one step by the minimum-norm correction."""
    a = np.array([1.0, 2.0, -1.0])
    result = solve_equations(lambda q: np.array([a @ q]), [3.0], np.zeros(3), jac=lambda q: a[None])
    assert result.status == "converged" and result.iterations == 1
    np.testing.assert_allclose(result.q, a * 3.0 / (a @ a))


def test_tall_jacobian_converges_to_the_least_squares_point():
    """r = 3 > n = 1 with an inconsistent target: Newton (J⁺) lands on the least-squares q,
    where the increment vanishes with the error above tol: stalled."""
    b = np.array([1.0, 2.0, 2.0])
    x_d = np.array([1.0, 1.0, 5.0])
    result = solve_equations(lambda q: b * q[0], x_d, [0.0], q_tol=1e-12, max_iterations=10)
    assert not result.success and result.status == "stalled"
    assert "q_tol" in result.message
    np.testing.assert_allclose(result.q, [b @ x_d / (b @ b)], atol=1e-12)


def test_square_jacobian_matches_the_inverse():
    A = np.array([[2.0, 1.0], [1.0, 3.0]])
    result = solve_equations(lambda q: A @ q, [1.0, 2.0], [5.0, -5.0], jac=lambda q: A)
    assert result.iterations == 1
    np.testing.assert_allclose(result.q, np.linalg.solve(A, [1.0, 2.0]))


def test_singular_start_is_reported_without_moving():
    q0 = np.array([0.3, 0.0])  # outstretched 2R arm: rank-1 Jacobian
    result = solve_equations(two_link, X_D, q0, jac=two_link_jacobian, singular_tol=1e-6)
    assert result.status == "singular" and not result.success and result.iterations == 0
    np.testing.assert_array_equal(result.q, q0)
    assert "σ_min" in result.message


def test_error_in_the_kernel_of_the_transpose_stalls():
    """Outstretched arm, target straight out beyond reach: Jᵀe = 0, the step vanishes."""
    q0 = np.array([0.0, 0.0])
    x_d = np.array([3.0, 0.0])
    constant = solve_equations(two_link, x_d, q0, "transpose", two_link_jacobian, q_tol=1e-12)
    assert constant.status == "stalled" and not constant.success
    np.testing.assert_array_equal(constant.q, q0)
    armijo = solve_equations(
        two_link, x_d, q0, "transpose", two_link_jacobian, step="armijo", q_tol=1e-12
    )
    assert armijo.status == "stalled" and armijo.iterations == 0


def test_max_iterations_status():
    result = solve_equations(two_link, X_D, [0.2, 1.4], "transpose", step=0.01, max_iterations=3)
    assert result.status == "max_iterations" and result.iterations == 3


def test_non_finite_values_never_leave_the_solver():
    def explodes(q):
        return np.array([np.inf if q[0] > 1.0 else q[0] ** 3 - 8.0])

    result = solve_equations(explodes, [0.0], [0.5])
    assert result.status == "diverged"
    assert np.all(np.isfinite(result.q)) and np.all(np.isfinite(result.history))
    assert result.q[0] <= 1.0

    # √q = 0.1 from q = 4: the first Newton step overshoots to q < 0, where √q is NaN.
    with np.errstate(invalid="ignore"):
        result = solve_equations(
            lambda q: np.sqrt(q), [0.1], [4.0], jac=lambda q: 0.5 / np.sqrt(q)[None]
        )
    assert result.status == "diverged"
    np.testing.assert_array_equal(result.q, [4.0])


@pytest.mark.parametrize(
    ("q0", "jac"),
    [([0.3, np.pi], two_link_jacobian), ([0.3, 0.0], None)],
    ids=["folded-analytic", "outstretched-finite-diff"],
)
def test_singular_start_without_the_check_ends_as_diverged(q0, jac):
    """J singular up to rounding (sin π ≈ 1e-16; a finite-difference J of the outstretched
    arm): J⁻¹e is ~1e16 — finite, but nonsense."""
    result = solve_equations(two_link, X_D, q0, jac=jac, max_iterations=10)
    assert result.status == "diverged" and "blew up" in result.message
    np.testing.assert_array_equal(result.q, q0)  # the last sane iterate
    assert np.all(np.abs(result.history) < 1e3)


def test_max_growth_bounds_the_error_too():
    # f = q³ from a far start: a huge constant transpose step explodes e.
    result = solve_equations(
        lambda q: q**3, [1.0], [2.0], "transpose", step=50.0, max_iterations=20
    )
    assert result.status == "diverged"
    assert np.all(np.abs(result.error_history) <= 1e8 * max(1.0, result.error_history[0]))


def test_newton_armijo_step_never_increases_the_error_and_ends_quadratic():
    """From an arm folded back, full Newton steps overshoot; λ^k from backtracking does not,
    and λ = 1 is accepted near the root (quadratic terminal rate)."""
    q0 = [0.2, 2.9]
    full = solve_equations(two_link, X_D, q0, jac=two_link_jacobian, tol=1e-12)
    assert np.any(np.diff(full.error_history) > 0.0)
    adaptive = solve_equations(two_link, X_D, q0, jac=two_link_jacobian, step="armijo", tol=1e-12)
    assert adaptive.status == "converged"
    assert np.all(np.diff(adaptive.error_history) < 0.0)
    terminal = quadratic_pairs(adaptive.error_history)
    assert terminal and all(b <= 10.0 * a**2 for a, b in terminal)


def test_gain_matrix_weighs_the_transpose_step():
    K = np.diag([4.0, 0.5])
    q0 = np.array([0.2, 1.4])
    options = {"jac": two_link_jacobian, "step": 0.1, "max_iterations": 1, "tol": 0}
    result = solve_equations(two_link, X_D, q0, "transpose", gain=K, **options)
    J, e = two_link_jacobian(q0), X_D - two_link(q0)
    np.testing.assert_allclose(result.history[1], q0 + 0.1 * J.T @ K @ e, atol=1e-15)
    # A vector is the diagonal, a number k is k I.
    as_vector = solve_equations(two_link, X_D, q0, "transpose", gain=[4.0, 0.5], **options)
    np.testing.assert_allclose(as_vector.history[1], result.history[1], atol=1e-15)
    scalar = solve_equations(two_link, X_D, q0, "transpose", gain=2.0, **options)
    np.testing.assert_allclose(scalar.history[1], q0 + 0.2 * J.T @ e, atol=1e-15)


@pytest.mark.parametrize(
    "K",
    [np.diag([4.0, 0.5]), np.array([[1.0, -1.0], [1.0, 1.0]]) / math.sqrt(2.0)],
    ids=["symmetric", "rotation"],
)
def test_armijo_never_increases_the_merit_of_the_symmetric_part(K):
    """The merit of a gain K is F = ½ eᵀK_s e with K_s = (K + Kᵀ)/2 (eᵀKe = eᵀK_s e): the
    Armijo search keeps it monotone for a non-symmetric K too."""
    result = solve_equations(two_link, X_D, [0.2, 1.4], "transpose", two_link_jacobian,
                             step="armijo", gain=K, tol=1e-8, max_iterations=300)  # fmt: skip
    assert result.iterations > 10
    K_s = 0.5 * (K + K.T)
    merit = [(X_D - two_link(q)) @ K_s @ (X_D - two_link(q)) for q in result.history]
    assert np.all(np.diff(merit) <= 0.0)


@pytest.mark.parametrize(
    ("gain", "match"),
    [
        (np.array([[1.0, 3.0], [-3.0, -0.5]]), r"smallest eigenvalue of \(K \+ Kᵀ\)/2 is -0.5"),
        (np.diag([1.0, -1.0]), r"positive definite.* K = \[\[1.0, 0.0\], \[0.0, -1.0\]\]"),
        (np.ones(3), "length-2 vector"),
        (0.0, "positive definite"),
        ("fast", "real numbers"),
        ([[1.0, 0.0], [0.0]], "real numbers"),
    ],
)
def test_bad_gains_are_refused(gain, match):
    with pytest.raises(InvalidInput, match=match):
        solve_equations(two_link, X_D, [0.2, 1.4], "transpose", gain=gain)


def test_hybrid_uses_the_transpose_far_away_and_newton_near():
    q0 = [0.2, 2.9]
    result = solve_equations(two_link, X_D, q0, "hybrid", two_link_jacobian, switch_error=0.1,
                             tol=1e-12)  # fmt: skip
    assert result.status == "converged" and result.method == "hybrid"
    e = result.error_history
    far = np.flatnonzero(e > 0.1)
    assert np.all(np.diff(e[: far[-1] + 2]) < 0.0)  # Armijo transpose phase: monotone
    near = quadratic_pairs(e)
    assert near and all(b <= 10.0 * a**2 for a, b in near)  # Newton phase: quadratic
    slow = solve_equations(two_link, X_D, q0, "transpose", two_link_jacobian, step="armijo",
                           tol=1e-12, max_iterations=5000)  # fmt: skip
    assert result.iterations < slow.iterations


def test_hybrid_checks_singularity_only_in_its_newton_phase():
    # From the outstretched arm the transpose phase moves off the singularity first.
    options = {"jac": two_link_jacobian, "singular_tol": 1e-6}
    assert solve_equations(two_link, X_D, [0.3, 0.0], "hybrid", **options).status == "converged"
    assert solve_equations(two_link, X_D, [0.3, 0.0], **options).status == "singular"


def test_a_newton_step_that_raises_the_error_hands_over_to_the_transpose():
    """Inside the switch radius a Newton step that would increase the error is not taken."""
    result = solve_equations(two_link, X_D, [0.2, 2.9], "hybrid", two_link_jacobian,
                             switch_error=10.0, tol=1e-12)  # fmt: skip
    assert result.status == "converged"
    assert np.all(np.diff(result.error_history) < 0.0)


@pytest.mark.parametrize(
    ("method", "kwargs", "match"),
    [
        ("hybrid", {"transpose_step": -1.0}, "transpose_step"),
        ("hybrid", {"newton_step": "wolfe"}, "newton_step"),
        ("hybrid", {"switch_error": 0.0}, "switch_error"),
        ("hybrid", {"singular_tol": -1.0}, "singular_tol"),
        ("newton", {"singular_test": "cond"}, "singular_test"),
        ("newton", {"gain": 2.0}, r"unknown option\(s\) \['gain'\] for method='newton'"),
        ("gradient", {}, r"method must be one of \['newton', 'transpose', 'hybrid'\]"),
        ("transpose", {"step": "wolfe"}, "step"),
    ],
)
def test_bad_options_are_named(method, kwargs, match):
    with pytest.raises(InvalidInput, match=match):
        solve_equations(two_link, X_D, [0.2, 1.4], method, **kwargs)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"x_d": [np.nan, 0.0]},
        {"x_d": ["a", "b"]},
        {"x_d": [1.0, 2.0, 3.0]},
        {"q0": [np.inf, 0.0]},
        {"q0": [[0.0, 1.0]]},
        {"tol": -1e-3},
        {"tol": (1e-3, 1e-3)},  # a pair needs the orientation part of a length-2 residual
        {"tol": (1e-3, 1e-3, 1e-3)},
        {"step": -1.0},
        {"step": np.inf},
        {"fd_step": np.inf},
        {"fd_step": "0.1"},
        {"max_iterations": -1},
        {"jac": lambda q: np.eye(3)},
        {"f": "not callable"},
        {"singular_test": "det", "x_d": [1.0], "f": lambda q: q[:1]},  # J is 1 × 2
    ],
)
def test_bad_inputs_raise_redik_errors(kwargs):
    arguments = {"f": two_link, "x_d": X_D, "q0": [0.1, 0.2], **kwargs}
    with pytest.raises(RedikError):
        solve_equations(**arguments)


def test_the_jacobian_is_evaluated_once_per_iteration():
    calls = []

    def jac(q):
        calls.append(q.copy())
        return two_link_jacobian(q)

    result = solve_equations(two_link, X_D, np.array([0.3, 0.4]), jac=jac)
    assert result.status == "converged"
    assert len(calls) == result.iterations  # jac(q0), checked up front, is reused
    np.testing.assert_array_equal(calls[0], [0.3, 0.4])


def planar_3r_pose(q: np.ndarray) -> np.ndarray:
    """A 6-vector pose residual of a unit 3R planar arm: (x, y, 0) and (0, 0, φ)."""
    c = np.cumsum(q)
    return np.array([np.cos(c).sum(), np.sin(c).sum(), 0.0, 0.0, 0.0, c[-1]])


def test_separate_position_and_orientation_tolerances():
    """tol = (ε_p, ε_R) stops at the first iterate with ‖e_p‖ ≤ ε_p and ‖e_R‖ ≤ ε_R. A gain
    that favours position makes the two halves converge at different rates."""
    x_d = planar_3r_pose(np.array([0.3, 0.9, -0.4]))
    q0 = [0.5, 0.5, 0.5]
    K = np.diag([1.0, 1.0, 1.0, 1.0, 1.0, 0.05])
    options = {"step": "armijo", "gain": K, "max_iterations": 5000}
    result = solve_equations(planar_3r_pose, x_d, q0, "transpose", tol=(1e-3, 2e-2), **options)
    assert result.status == "converged"
    assert result.position_error <= 1e-3 and result.rotation_error <= 2e-2
    halves = [(np.linalg.norm(e[:3]), np.linalg.norm(e[3:]))
              for e in (x_d - planar_3r_pose(q) for q in result.history)]  # fmt: skip
    met = [p <= 1e-3 and r <= 2e-2 for p, r in halves]
    assert met.index(True) == len(met) - 1  # the first iterate that meets both
    assert result.error > 1e-3  # one bound on ‖e‖ = 1e-3 would have gone on
    single = solve_equations(planar_3r_pose, x_d, q0, "transpose", tol=1e-3, **options)
    assert single.iterations > result.iterations


def test_orientation_size_splits_any_residual():
    """A residual (x, y, z, φ): the orientation is its last entry, named explicitly."""

    def f(q):
        return np.array([*planar_3r_pose(q)[:2], 0.0, planar_3r_pose(q)[5]])

    x_d = f(np.array([0.3, 0.9, -0.4]))
    with pytest.raises(InvalidInput, match="orientation_size"):
        solve_equations(f, x_d, [0.1, 0.5, 0.1], tol=(1e-6, 1e-4))
    result = solve_equations(f, x_d, [0.1, 0.5, 0.1], tol=(1e-6, 1e-4), orientation_size=1)
    e = x_d - f(result.q)
    assert result.success and np.linalg.norm(e[:3]) <= 1e-6 and abs(e[3]) <= 1e-4
    assert result.position_error == pytest.approx(np.linalg.norm(e[:3]))


def test_relative_change_stop_without_a_root_is_stalled():
    """Beyond reach (‖x_d‖ > 1.8): the transpose settles at the closest point; the relative
    change of f ends it there, "stalled" since the error test is not met."""
    far = solve_equations(two_link, np.array([3.0, 0.5]), [0.2, 0.4], "transpose", step="armijo",
                          rel_tol=1e-6, max_iterations=1000)  # fmt: skip
    assert far.status == "stalled" and "relative change" in far.message
    assert far.iterations < 1000
    x = np.array([two_link(q) for q in far.history[-2:]])
    assert np.linalg.norm(x[1] - x[0]) <= 1e-6 * np.linalg.norm(x[0])


def test_tol_zero_runs_every_iteration():
    """An iterate table: tol = 0 never ends a run early; at the end only an exact root is
    "converged"."""
    table = solve_equations(two_link, X_D, [0.2, 1.4], jac=two_link_jacobian, tol=0,
                            max_iterations=12)  # fmt: skip
    assert table.iterations == 12 and table.history.shape == (13, 2)
    assert table.error < 1e-14  # converged long before; the table still has 12 rows
    early = solve_equations(two_link, X_D, [0.2, 1.4], jac=two_link_jacobian, tol=0,
                            max_iterations=2)  # fmt: skip
    assert early.status == "max_iterations" and not early.success
    exact = solve_equations(lambda q: 2.0 * q, [4.0], [0.0], tol=0, max_iterations=10)
    assert exact.status == "converged" and exact.iterations == 10 and exact.error == 0.0
    np.testing.assert_array_equal(exact.history[1:], 2.0)


def test_forward_differences_default_step_is_accurate():
    q = np.array([0.4, 1.1])
    J = finite_difference_jacobian(two_link, q, scheme="forward")
    np.testing.assert_allclose(J, two_link_jacobian(q), atol=1e-7)
    with pytest.raises(InvalidInput, match="scheme"):
        finite_difference_jacobian(two_link, q, scheme="backward")
    with pytest.raises(InvalidInput, match="q must hold real numbers"):
        finite_difference_jacobian(two_link, ["a", "b"])
    with pytest.raises(InvalidInput, match="NaN"):
        finite_difference_jacobian(two_link, [np.nan, 0.0])
    with pytest.raises(InvalidInput, match="callable"):
        finite_difference_jacobian("two_link", q)
    with pytest.raises(InvalidInput, match="step"):
        finite_difference_jacobian(two_link, q, step=0.0)
    with pytest.raises(InvalidInput, match="fd_scheme"):
        solve_equations(two_link, X_D, q, fd_scheme="complex")


# --------------------------------------------------------------------------------------
# The course notes' worked examples


@pytest.fixture(scope="module")
def arm_2r():
    """The Case Study's unit-link 2R arm: its tip (x, y) and ∂(x, y)/∂θ."""
    arm = redik.load("planar_2r")
    return (lambda q: arm.fk(q)[:2, 3]), (lambda q: arm.jacobian(q, reference="world")[:2])


@pytest.fixture(scope="module")
def rrp():
    """002's RRP polar arm (d1 = 0.5): its end-effector position and ∂p/∂q."""
    robot = redik.load("rrp_polar")
    return (lambda q: robot.fk(q)[:3, 3]), (lambda q: robot.jacobian(q, reference="world")[:3])


def test_the_case_study_newton_table(arm_2r):
    """000, Case Study, "IK using Jacobian inverse": λ = 0.75 from (0.25, 0.75), ten rows."""
    tip, jacobian = arm_2r
    run = solve_equations(tip, [0.2, 1.3], [0.25, 0.75], jac=jacobian, step=0.75, tol=0,
                          max_iterations=10)  # fmt: skip
    printed = [(-0.33284, 2.6711), (0.80552, 2.1025), (0.46906, 1.9316), (0.53554, 1.7697),
               (0.55729, 1.7227), (0.56308, 1.7104), (0.56455, 1.7073), (0.56492, 1.7065),
               (0.56501, 1.7063), (0.56503, 1.7062)]  # fmt: skip
    for k, (theta1, theta2) in enumerate(printed, start=1):
        assert (round(run.history[k][0], 5), round(run.history[k][1], 4)) == (theta1, theta2)


def test_the_case_study_transpose_table(arm_2r):
    """000, "IK using Jacobian transpose", step 0.75: the table starts from (0.30, 0.40),
    not the stated (0.25, 0.75) (a slip of the notes); rows 1–5."""
    tip, jacobian = arm_2r
    run = solve_equations(tip, [0.2, 1.3], [0.30, 0.40], "transpose", jacobian, step=0.75,
                          tol=0, max_iterations=5)  # fmt: skip
    printed = [("1.8362", "1.3412"), ("0.4667", "1.1025"), ("1.1215", "1.6233"),
               ("0.45264", "1.415"), ("0.83519", "1.7273")]  # fmt: skip
    for k, row in enumerate(printed, start=1):
        for value, text in zip(run.history[k], row, strict=True):
            assert round(value, len(text.split(".")[1])) == float(text)


@pytest.mark.parametrize("tol", [None, 0.0])
@pytest.mark.parametrize("rule", ["rel_tol", "q_tol"])
def test_each_stopping_rule_of_the_notes_alone_ends_the_case_study_converged(arm_2r, rule, tol):
    """000, "Remarks": a relative change ‖f(θ^{k+1}) − f(θ^k)‖/‖f(θ^k)‖ ≤ ε of the task value
    x = f(θ), or a joint increment ‖θ^{k+1} − θ^k‖ < ε_q, is a stopping rule of its own.
    Without an error test (tol=None, or tol=0 as for an iterate table) the run stops, a
    success, after the iteration at which the rule holds on the Newton table (13 at 1e-6:
    the ratio of e = x_d − f(θ) would tend to λ and never fire; the increment is tested
    after the step, which is kept)."""
    tip, jacobian = arm_2r
    table = solve_equations(tip, [0.2, 1.3], [0.25, 0.75], jac=jacobian, step=0.75, tol=0,
                            max_iterations=30).history  # fmt: skip
    x = np.array([tip(q) for q in table])
    if rule == "rel_tol":
        fired = np.linalg.norm(np.diff(x, axis=0), axis=1) <= 1e-6 * np.linalg.norm(x[:-1], axis=1)
    else:
        fired = np.linalg.norm(np.diff(table, axis=0), axis=1) < 1e-6
    k = 1 + int(np.argmax(fired))
    run = solve_equations(tip, [0.2, 1.3], [0.25, 0.75], jac=jacobian, step=0.75, tol=tol,
                          max_iterations=30, **{rule: 1e-6})  # fmt: skip
    assert k == 13
    assert run.success and run.status == "converged" and run.iterations == k
    np.testing.assert_array_equal(run.history, table[: k + 1])


def test_the_minimum_coordinate_algorithm_with_separate_tolerances():
    """000, "Algorithm for Minimum-Coordinate Representation": θ += λ J⁺ e while e_p > ε_p or
    e_R > ε_R, on the planar pose x = (x, y, φ) of the unit 3R arm (target and thresholds
    chosen here: the notes give none)."""
    arm = redik.load("planar_3r")

    def pose(q):
        T = arm.fk(q)
        return np.array([T[0, 3], T[1, 3], math.atan2(T[1, 0], T[0, 0])])

    def jacobian(q):
        return arm.jacobian(q, reference="world")[[0, 1, 5]]  # ẋ, ẏ, φ̇ = ω_z

    x_d = pose([0.3, 0.9, -0.4])
    run = solve_equations(pose, x_d, [0.1, 0.5, 0.1], jac=jacobian, tol=(1e-6, 1e-4),
                          max_iterations=20)  # fmt: skip
    e = x_d - pose(run.q)
    assert run.success and np.linalg.norm(e[:2]) <= 1e-6 and abs(e[2]) <= 1e-4
    assert (run.position_error, run.rotation_error) == (np.linalg.norm(e[:2]), abs(e[2]))
    before = [x_d - pose(q) for q in run.history[:-1]]
    assert all(np.linalg.norm(d[:2]) > 1e-6 or abs(d[2]) > 1e-4 for d in before)


def test_a_rotation_gain_leaves_the_saddle_of_the_2r_case_study(arm_2r):
    """002, "A case study": r_d = (1, 1); at the saddle (π/4, 0) e ∈ ker J_rᵀ and the
    transpose is stuck; a gain K > 0 that rotates e (xᵀKx = cos 45° ‖x‖² > 0, not
    symmetric; K and α = 0.5 chosen here: the notes give none) escapes to a solution."""
    tip, jacobian = arm_2r
    saddle = [math.pi / 4, 0.0]
    stuck = solve_equations(tip, [1.0, 1.0], saddle, "transpose", jacobian, step=0.5,
                            q_tol=1e-9)  # fmt: skip
    assert stuck.status == "stalled" and np.allclose(stuck.q, saddle)
    K = np.array([[1.0, -1.0], [1.0, 1.0]]) / math.sqrt(2.0)
    escaped = solve_equations(tip, [1.0, 1.0], saddle, "transpose", jacobian, step=0.5, gain=K)
    assert escaped.success
    solutions = ([0.0, math.pi / 2], [math.pi / 2, -math.pi / 2])  # q' and q''
    assert min(np.abs(redik.lie.wrap_angle(escaped.q - s)).max() for s in solutions) < 1e-5


def test_rrp_numerical_test_1(rrp):
    """002, "Numerical test - 1": q⁰ = (0, 0, 1), ε = 1e-5, ε_q = 1e-6, k_max = 15. The
    transpose with α = 1 does not converge; with α = 0.7 it takes 11 iterations to an error
    of 0.57·10⁻⁵; Newton takes 5; both reach q* = (0.7854, 0.3398, 1.5)."""
    position, jacobian = rrp
    notes = {"tol": 1e-5, "q_tol": 1e-6, "max_iterations": 15, "jac": jacobian}
    one = solve_equations(position, [1, 1, 1], [0, 0, 1], "transpose", step=1.0, **notes)
    slow = solve_equations(position, [1, 1, 1], [0, 0, 1], "transpose", step=0.7, **notes)
    newton = solve_equations(position, [1, 1, 1], [0, 0, 1], **notes)
    assert not one.success
    assert slow.success and slow.iterations == 11 and round(slow.error * 1e5, 2) == 0.57
    assert newton.success and newton.iterations == 5
    for result in (slow, newton):
        assert tuple(np.round(result.q, 4)) == (0.7854, 0.3398, 1.5)


@pytest.mark.parametrize("q0", [[-math.pi / 4, math.pi / 2, 1.0], [0.0, math.pi / 2, 0.0]],
                         ids=["test-2", "test-3"])  # fmt: skip
def test_rrp_singular_starts_block_or_diverge_newton(rrp, q0):
    """002, "Numerical test - 2" and "- 3": from a singular start Newton with the check
    |det J_r| ≤ 10⁻⁴ (or σ_min) is blocked at once; without it the first step is ~10¹⁶ and
    the run diverges — ending "diverged" with the start, even though the robot's FK refuses
    such a q."""
    position, jacobian = rrp
    notes = {"tol": 1e-5, "q_tol": 1e-6, "max_iterations": 15, "jac": jacobian}
    for test in ("det", "sigma_min"):
        blocked = solve_equations(position, [1, 1, 1], q0, singular_tol=1e-4,
                                  singular_test=test, **notes)  # fmt: skip
        assert blocked.status == "singular" and blocked.iterations == 0
    assert "|det J|" in blocked.message or "σ_min" in blocked.message
    unchecked = solve_equations(position, [1, 1, 1], q0, **notes)
    assert unchecked.status == "diverged" and "blew up" in unchecked.message
    assert np.all(np.abs(unchecked.history) < 1e3)  # the last sane iterate is kept


def test_rrp_numerical_test_2_transpose_stops_in_the_kernel(rrp):
    """002, test 2, transpose α = 0.7: it moves toward the solution and stops where e lies in
    ker J_rᵀ — stalled, not converged (ε = 1e-5 unmet)."""
    position, jacobian = rrp
    run = solve_equations(position, [1, 1, 1], [-math.pi / 4, math.pi / 2, 1.0], "transpose",
                          jacobian, step=0.7, tol=1e-5, q_tol=1e-6, max_iterations=15)  # fmt: skip
    e = np.ones(3) - position(run.q)
    assert run.status == "stalled" and run.error < run.error_history[0]
    assert np.linalg.norm(jacobian(run.q).T @ e) < 1e-5 < np.linalg.norm(e)


def test_rrp_numerical_test_3(rrp):
    """002, "Numerical test - 3": the transpose with α = 0.7 leaves the double singularity
    (0, π/2, 0) and reaches q* in 19 iterations — beyond the tests' own k_max = 15 (a slip of
    the notes): held to 15 it ends at the budget."""
    position, jacobian = rrp
    notes = {"tol": 1e-5, "q_tol": 1e-6, "jac": jacobian, "step": 0.7}
    q0 = [0.0, math.pi / 2, 0.0]
    held = solve_equations(position, [1, 1, 1], q0, "transpose", max_iterations=15, **notes)
    run = solve_equations(position, [1, 1, 1], q0, "transpose", max_iterations=19, **notes)
    assert held.status == "max_iterations"
    assert run.success and run.iterations == 19
    assert tuple(np.round(run.q, 4)) == (0.7854, 0.3398, 1.5)
