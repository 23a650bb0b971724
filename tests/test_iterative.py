"""Newton–Raphson and gradient descent on user functions: rates, shapes, statuses, misuse."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from redik.core.exceptions import InvalidInput, RedikError
from redik.solvers.iterative import (
    finite_difference_jacobian,
    gradient_descent,
    gradient_then_newton,
    newton_raphson,
    solve_equations,
)

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


def test_finite_difference_jacobian_matches_the_analytic_one(rng):
    for _ in range(5):
        q = rng.uniform(-3, 3, size=2)
        np.testing.assert_allclose(
            finite_difference_jacobian(two_link, q), two_link_jacobian(q), atol=1e-9
        )


@pytest.mark.parametrize("jac", [two_link_jacobian, None], ids=["analytic", "finite-diff"])
def test_newton_converges_quadratically_on_a_2r_arm(jac):
    result = newton_raphson(two_link, X_D, [0.2, 1.4], jac=jac, tol=1e-12)
    assert result.success and result.status == "converged"
    np.testing.assert_allclose(two_link(result.q), X_D, atol=1e-12)
    e = result.error_history
    assert e[0] == pytest.approx(np.linalg.norm(X_D - two_link(np.array([0.2, 1.4]))))
    # Terminal rate: e_{k+1} ≈ C e_k² with a bounded C, once in the quadratic regime.
    terminal = [(a, b) for a, b in itertools.pairwise(e) if 1e-9 < a < 1e-2]
    assert terminal, e
    for a, b in terminal:
        assert b <= 10.0 * a**2
    assert result.history.shape == (result.iterations + 1, 2)
    np.testing.assert_array_equal(result.history[0], [0.2, 1.4])


def test_gradient_with_armijo_never_increases_the_error():
    result = gradient_descent(two_link, X_D, [0.2, 1.4], jac=two_link_jacobian, step="armijo",
                              tol=1e-8, max_iterations=5000)  # fmt: skip
    assert result.status == "converged"
    assert np.all(np.diff(result.error_history) <= 0.0)
    # Linear, not quadratic: many more iterations than Newton needs.
    assert result.iterations > newton_raphson(two_link, X_D, [0.2, 1.4], tol=1e-8).iterations


def test_gradient_with_a_too_large_constant_step_can_increase_the_error():
    result = gradient_descent(
        two_link, X_D, [0.2, 1.4], jac=two_link_jacobian, step=2.5, max_iterations=20
    )
    assert np.any(np.diff(result.error_history) > 0.0)
    assert np.all(np.isfinite(result.q))


def test_fat_jacobian_takes_the_least_norm_step():
    """r = 1 < n = 3: a linear task is solved in one step by the minimum-norm correction."""
    a = np.array([1.0, 2.0, -1.0])
    result = newton_raphson(
        lambda q: np.array([a @ q]), [3.0], np.zeros(3), jac=lambda q: a[None, :]
    )
    assert result.status == "converged" and result.iterations == 1
    np.testing.assert_allclose(result.q, a * 3.0 / (a @ a))


def test_tall_jacobian_converges_to_the_least_squares_point():
    """r = 3 > n = 1 with an inconsistent target: Newton (J⁺) lands on the least-squares q."""
    b = np.array([1.0, 2.0, 2.0])
    x_d = np.array([1.0, 1.0, 5.0])
    result = newton_raphson(lambda q: b * q[0], x_d, [0.0], q_tol=1e-12, max_iterations=10)
    assert not result.success
    assert result.status == "stalled"
    np.testing.assert_allclose(result.q, [b @ x_d / (b @ b)], atol=1e-12)


def test_square_jacobian_matches_the_inverse():
    A = np.array([[2.0, 1.0], [1.0, 3.0]])
    result = newton_raphson(lambda q: A @ q, [1.0, 2.0], [5.0, -5.0], jac=lambda q: A)
    assert result.iterations == 1
    np.testing.assert_allclose(result.q, np.linalg.solve(A, [1.0, 2.0]))


def test_singular_start_is_reported_without_moving():
    # Outstretched 2R arm (q2 = 0): rank-1 Jacobian.
    q0 = np.array([0.3, 0.0])
    result = newton_raphson(two_link, X_D, q0, jac=two_link_jacobian, singular_tol=1e-6)
    assert result.status == "singular" and not result.success
    assert result.iterations == 0
    np.testing.assert_array_equal(result.q, q0)
    assert "σ_min" in result.message


def test_error_in_the_kernel_of_the_transpose_stalls():
    """Outstretched arm, target straight out beyond reach: Jᵀe = 0, the step vanishes."""
    q0 = np.array([0.0, 0.0])
    x_d = np.array([3.0, 0.0])
    result = gradient_descent(two_link, x_d, q0, jac=two_link_jacobian, q_tol=1e-12)
    assert result.status == "stalled" and not result.success
    np.testing.assert_array_equal(result.q, q0)
    armijo = gradient_descent(two_link, x_d, q0, jac=two_link_jacobian, step="armijo", q_tol=1e-12)
    assert armijo.status == "stalled"


def test_max_iterations_status():
    result = gradient_descent(two_link, X_D, [0.2, 1.4], step=0.01, max_iterations=3)
    assert result.status == "max_iterations" and result.iterations == 3


def test_non_finite_values_never_leave_the_solver():
    def explodes(q):
        return np.array([np.inf if q[0] > 1.0 else q[0] ** 3 - 8.0])

    result = newton_raphson(explodes, [0.0], [0.5])
    assert result.status == "diverged"
    assert np.all(np.isfinite(result.q)) and np.all(np.isfinite(result.history))
    assert result.q[0] <= 1.0

    # √q = 0.1 from q = 4: the first Newton step overshoots to q < 0, where √q is NaN.
    with np.errstate(invalid="ignore"):
        result = newton_raphson(
            lambda q: np.sqrt(q), [0.1], [4.0], jac=lambda q: 0.5 / np.sqrt(q)[None]
        )
    assert result.status == "diverged"
    np.testing.assert_array_equal(result.q, [4.0])


@pytest.mark.parametrize(
    "kwargs",
    [
        {"x_d": [np.nan, 0.0]},
        {"x_d": ["a", "b"]},
        {"x_d": [1.0, 2.0, 3.0]},
        {"q0": [np.inf, 0.0]},
        {"q0": [[0.0, 1.0]]},
        {"tol": -1e-3},
        {"tol": (1e-3, 1e-3)},  # a pair needs a pose residual of length 6
        {"step": -1.0},
        {"step": np.inf},
        {"fd_step": np.inf},
        {"fd_step": "0.1"},
        {"max_iterations": -1},
        {"jac": lambda q: np.eye(3)},
        {"f": "not callable"},
    ],
)
def test_bad_inputs_raise_redik_errors(kwargs):
    arguments = {"f": two_link, "x_d": X_D, "q0": [0.1, 0.2], **kwargs}
    with pytest.raises(RedikError):
        newton_raphson(**arguments)


def test_gradient_rejects_an_unknown_step_name():
    with pytest.raises(InvalidInput):
        gradient_descent(two_link, X_D, [0.1, 0.2], step="wolfe")


def test_the_jacobian_is_evaluated_once_per_iteration():
    calls = []

    def f(q):
        return np.array([np.cos(q[0]) + np.cos(q[0] + q[1]), np.sin(q[0]) + np.sin(q[0] + q[1])])

    def jac(q):
        calls.append(q.copy())
        s1, s12, c1, c12 = np.sin(q[0]), np.sin(q[0] + q[1]), np.cos(q[0]), np.cos(q[0] + q[1])
        return np.array([[-s1 - s12, -s12], [c1 + c12, c12]])

    result = newton_raphson(f, np.array([1.2, 0.7]), np.array([0.3, 0.4]), jac=jac)
    assert result.status == "converged"
    assert len(calls) == result.iterations  # jac(q0), checked up front, is reused
    np.testing.assert_array_equal(calls[0], [0.3, 0.4])


# --------------------------------------------------------------------------------------
# The course's options (issue 15)


@pytest.mark.parametrize(
    ("q0", "jac"),
    [([0.3, np.pi], two_link_jacobian), ([0.3, 0.0], None)],
    ids=["folded-analytic", "outstretched-finite-diff"],
)
def test_singular_start_without_the_check_ends_as_diverged(q0, jac):
    """J singular up to rounding (sin π ≈ 1e-16; a finite-difference J of the outstretched
    arm): J⁻¹e is ~1e16 — finite, but nonsense. Before the blow-up bound this ran on to
    ``max_iterations`` with q ≈ 1e10."""
    result = newton_raphson(two_link, X_D, q0, jac=jac, max_iterations=10)
    assert result.status == "diverged" and "blew up" in result.message
    np.testing.assert_array_equal(result.q, q0)  # the last sane iterate
    assert np.all(np.abs(result.history) < 1e3)


def test_max_growth_bounds_the_error_too():
    # f = q³ from a far start: Newton is fine, but a huge constant gradient step explodes e.
    result = gradient_descent(lambda q: q**3, [1.0], [2.0], step=50.0, max_iterations=20)
    assert result.status == "diverged"
    assert np.all(np.abs(result.error_history) <= 1e8 * max(1.0, result.error_history[0]))


def test_newton_armijo_step_never_increases_the_error_and_ends_quadratic():
    """From an arm folded back, full Newton steps overshoot; λ^k from backtracking does not,
    and λ = 1 is accepted near the root (quadratic terminal rate)."""
    q0 = [0.2, 2.9]
    full = newton_raphson(two_link, X_D, q0, jac=two_link_jacobian, tol=1e-12, max_iterations=100)
    assert np.any(np.diff(full.error_history) > 0.0)
    adaptive = newton_raphson(two_link, X_D, q0, jac=two_link_jacobian, step="armijo", tol=1e-12)
    assert adaptive.status == "converged"
    assert np.all(np.diff(adaptive.error_history) < 0.0)
    e = adaptive.error_history
    terminal = [(a, b) for a, b in itertools.pairwise(e) if 1e-9 < a < 1e-2]
    assert terminal and all(b <= 10.0 * a**2 for a, b in terminal)


def test_gain_matrix_weighs_the_transpose_step():
    K = np.diag([4.0, 0.5])
    q0 = np.array([0.2, 1.4])
    result = gradient_descent(two_link, X_D, q0, jac=two_link_jacobian, step=0.1, gain=K,
                              max_iterations=1, tol=0)  # fmt: skip
    J, e = two_link_jacobian(q0), X_D - two_link(q0)
    np.testing.assert_allclose(result.history[1], q0 + 0.1 * J.T @ K @ e, atol=1e-15)
    # A vector is the diagonal, a number k is k I.
    as_vector = gradient_descent(
        two_link, X_D, q0, step=0.1, gain=[4.0, 0.5], max_iterations=1, tol=0
    )
    np.testing.assert_allclose(as_vector.history[1], result.history[1], atol=1e-9)
    scalar = gradient_descent(two_link, X_D, q0, jac=two_link_jacobian, step=0.1, gain=2.0,
                              max_iterations=1, tol=0)  # fmt: skip
    np.testing.assert_allclose(scalar.history[1], q0 + 0.2 * J.T @ e, atol=1e-15)
    weighted = gradient_descent(two_link, X_D, q0, jac=two_link_jacobian, step="armijo", gain=K,
                                tol=1e-8, max_iterations=5000)  # fmt: skip
    assert weighted.status == "converged"
    merit = [0.5 * (X_D - two_link(q)) @ K @ (X_D - two_link(q)) for q in weighted.history]
    assert np.all(np.diff(merit) <= 0.0)


@pytest.mark.parametrize(
    ("gain", "match"),
    [
        (np.array([[1.0, 2.0], [0.0, 1.0]]), "symmetric"),
        (np.diag([1.0, -1.0]), "positive definite"),
        (np.ones(3), "length-2 vector"),
        (0.0, "positive definite"),
        ("fast", "real numbers"),
        ([[1.0, 0.0], [0.0]], "real numbers"),
    ],
)
def test_bad_gains_are_refused(gain, match):
    with pytest.raises(InvalidInput, match=match):
        gradient_descent(two_link, X_D, [0.2, 1.4], gain=gain)


def test_hybrid_uses_the_gradient_far_away_and_newton_near():
    q0 = [0.2, 2.9]
    result = gradient_then_newton(
        two_link, X_D, q0, jac=two_link_jacobian, switch_error=0.1, tol=1e-12
    )
    assert result.status == "converged" and result.method == "hybrid"
    e = result.error_history
    far = np.flatnonzero(e > 0.1)
    assert np.all(np.diff(e[: far[-1] + 2]) < 0.0)  # Armijo gradient phase: monotone
    near = [(a, b) for a, b in itertools.pairwise(e) if 1e-9 < a < 1e-2]
    assert near and all(b <= 10.0 * a**2 for a, b in near)  # Newton phase: quadratic
    slow = gradient_descent(two_link, X_D, q0, jac=two_link_jacobian, step="armijo", tol=1e-12,
                            max_iterations=5000)  # fmt: skip
    assert result.iterations < slow.iterations


def test_hybrid_checks_singularity_only_in_its_newton_phase():
    # From the outstretched arm the gradient phase moves off the singularity first.
    result = gradient_then_newton(
        two_link, X_D, [0.3, 0.0], jac=two_link_jacobian, singular_tol=1e-6
    )
    assert result.status == "converged"
    newton_only = newton_raphson(
        two_link, X_D, [0.3, 0.0], jac=two_link_jacobian, singular_tol=1e-6
    )
    assert newton_only.status == "singular"


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"gradient_step": -1.0}, "gradient_step"),
        ({"newton_step": "wolfe"}, "newton_step"),
        ({"switch_error": 0.0}, "switch_error"),
        ({"singular_tol": -1.0}, "singular_tol"),
    ],
)
def test_hybrid_names_the_bad_option(kwargs, match):
    with pytest.raises(InvalidInput, match=match):
        gradient_then_newton(two_link, X_D, [0.2, 1.4], **kwargs)


def test_gradient_singularity_check():
    result = gradient_descent(two_link, X_D, [0.3, 0.0], jac=two_link_jacobian, singular_tol=1e-6)
    assert result.status == "singular" and result.iterations == 0 and "σ_min" in result.message


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
    result = gradient_descent(planar_3r_pose, x_d, q0, step="armijo", gain=K, tol=(1e-3, 2e-2),
                              max_iterations=5000)  # fmt: skip
    assert result.status == "converged"
    assert result.position_error <= 1e-3 and result.rotation_error <= 2e-2
    halves = [(np.linalg.norm(e[:3]), np.linalg.norm(e[3:]))
              for e in (x_d - planar_3r_pose(q) for q in result.history)]  # fmt: skip
    met = [p <= 1e-3 and r <= 2e-2 for p, r in halves]
    assert met.index(True) == len(met) - 1  # the first iterate that meets both
    assert result.error > 1e-3  # one bound on ‖e‖ = 1e-3 would have gone on
    single = gradient_descent(
        planar_3r_pose, x_d, q0, step="armijo", gain=K, tol=1e-3, max_iterations=5000
    )
    assert single.iterations > result.iterations


def test_relative_change_stop():
    """Beyond reach (‖x_d‖ > 1.8): the gradient settles at the closest point; the relative
    change stop ends it there as "stalled" (no root), and as "converged" when tol is met."""
    far = gradient_descent(two_link, np.array([3.0, 0.5]), [0.2, 0.4], step="armijo", rel_tol=1e-6,
                           max_iterations=1000)  # fmt: skip
    assert far.status == "stalled" and "relative change" in far.message
    assert far.iterations < 1000
    e = np.array([3.0, 0.5]) - np.array([two_link(q) for q in far.history[-2:]])
    assert np.linalg.norm(e[1] - e[0]) / np.linalg.norm(e[0]) <= 1e-6
    near = newton_raphson(two_link, X_D, [0.2, 1.4], rel_tol=0.5, tol=1e-1, max_iterations=100)
    assert near.status == "converged"
    # tol = 0 on a linear f: Newton lands exactly on the root, where ‖e_k‖ = 0 and the
    # relative change is 0/0; the iterate is a root, so the run ends "converged".
    exact = newton_raphson(lambda q: q, [1.0], [0.0], tol=0, rel_tol=1e-3, max_iterations=5)
    assert exact.status == "converged" and exact.error == 0.0 and exact.iterations == 2


def test_tol_zero_runs_every_iteration():
    result = newton_raphson(
        two_link, X_D, [0.2, 1.4], jac=two_link_jacobian, tol=0, max_iterations=12
    )
    assert result.iterations == 12 and result.history.shape == (13, 2)
    assert result.error < 1e-14  # converged long before; the table still has 12 rows
    assert result.status == ("converged" if result.error == 0.0 else "max_iterations")
    early = newton_raphson(
        two_link, X_D, [0.2, 1.4], jac=two_link_jacobian, tol=0, max_iterations=2
    )
    assert early.iterations == 2 and early.status == "max_iterations" and not early.success
    exact = newton_raphson(
        lambda q: 2.0 * q, [4.0], [0.0], tol=0, max_iterations=10
    )  # linear: exact in 1
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
        newton_raphson(two_link, X_D, q, fd_scheme="complex")


def test_solve_equations_runs_the_named_method_with_its_options():
    q0 = [0.2, 1.4]
    for method, solver, options in (
        ("newton", newton_raphson, {"step": "armijo"}),
        ("gradient", gradient_descent, {"step": 0.3, "gain": 2.0}),
        ("hybrid", gradient_then_newton, {"switch_error": 0.05}),
    ):
        result = solve_equations(two_link, X_D, q0, method, two_link_jacobian, **options)
        expected = solver(two_link, X_D, q0, two_link_jacobian, **options)
        assert result.method == method
        np.testing.assert_array_equal(result.history, expected.history)
    with pytest.raises(InvalidInput, match=r"method must be one of \['newton', 'gradient'"):
        solve_equations(two_link, X_D, q0, "transpose")
    with pytest.raises(InvalidInput, match=r"unknown option\(s\) \['gain'\] for method='newton'"):
        solve_equations(two_link, X_D, q0, gain=2.0)
