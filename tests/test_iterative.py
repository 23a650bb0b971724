"""Newton–Raphson and gradient descent on user functions: rates, shapes, statuses, misuse."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from redik.exceptions import InvalidInput, RedikError
from redik.iterative import finite_difference_jacobian, gradient, newton

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
    result = newton(two_link, X_D, [0.2, 1.4], jac=jac, tol=1e-12)
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
    result = gradient(two_link, X_D, [0.2, 1.4], jac=two_link_jacobian, step="armijo", tol=1e-8,
                      max_iter=5000)  # fmt: skip
    assert result.status == "converged"
    assert np.all(np.diff(result.error_history) <= 0.0)
    # Linear, not quadratic: many more iterations than Newton needs.
    assert result.iterations > newton(two_link, X_D, [0.2, 1.4], tol=1e-8).iterations


def test_gradient_with_a_too_large_constant_step_can_increase_the_error():
    result = gradient(two_link, X_D, [0.2, 1.4], jac=two_link_jacobian, step=2.5, max_iter=20)
    assert np.any(np.diff(result.error_history) > 0.0)
    assert np.all(np.isfinite(result.q))


def test_fat_jacobian_takes_the_least_norm_step():
    """r = 1 < n = 3: a linear task is solved in one step by the minimum-norm correction."""
    a = np.array([1.0, 2.0, -1.0])
    result = newton(lambda q: np.array([a @ q]), [3.0], np.zeros(3), jac=lambda q: a[None, :])
    assert result.status == "converged" and result.iterations == 1
    np.testing.assert_allclose(result.q, a * 3.0 / (a @ a))


def test_tall_jacobian_converges_to_the_least_squares_point():
    """r = 3 > n = 1 with an inconsistent target: Newton (J⁺) lands on the least-squares q."""
    b = np.array([1.0, 2.0, 2.0])
    x_d = np.array([1.0, 1.0, 5.0])
    result = newton(lambda q: b * q[0], x_d, [0.0], q_tol=1e-12, max_iter=10)
    assert not result.success
    assert result.status == "stalled"
    np.testing.assert_allclose(result.q, [b @ x_d / (b @ b)], atol=1e-12)


def test_square_jacobian_matches_the_inverse():
    A = np.array([[2.0, 1.0], [1.0, 3.0]])
    result = newton(lambda q: A @ q, [1.0, 2.0], [5.0, -5.0], jac=lambda q: A)
    assert result.iterations == 1
    np.testing.assert_allclose(result.q, np.linalg.solve(A, [1.0, 2.0]))


def test_singular_start_is_reported_without_moving():
    # Outstretched 2R arm (q2 = 0): rank-1 Jacobian.
    q0 = np.array([0.3, 0.0])
    result = newton(two_link, X_D, q0, jac=two_link_jacobian, singular_tol=1e-6)
    assert result.status == "singular" and not result.success
    assert result.iterations == 0
    np.testing.assert_array_equal(result.q, q0)
    assert "σ_min" in result.message


def test_error_in_the_kernel_of_the_transpose_stalls():
    """Outstretched arm, target straight out beyond reach: Jᵀe = 0, the step vanishes."""
    q0 = np.array([0.0, 0.0])
    x_d = np.array([3.0, 0.0])
    result = gradient(two_link, x_d, q0, jac=two_link_jacobian, q_tol=1e-12)
    assert result.status == "stalled" and not result.success
    np.testing.assert_array_equal(result.q, q0)
    armijo = gradient(two_link, x_d, q0, jac=two_link_jacobian, step="armijo", q_tol=1e-12)
    assert armijo.status == "stalled"


def test_max_iterations_status():
    result = gradient(two_link, X_D, [0.2, 1.4], step=0.01, max_iter=3)
    assert result.status == "max_iterations" and result.iterations == 3


def test_non_finite_values_never_leave_the_solver():
    def explodes(q):
        return np.array([np.inf if q[0] > 1.0 else q[0] ** 3 - 8.0])

    result = newton(explodes, [0.0], [0.5])
    assert result.status == "diverged"
    assert np.all(np.isfinite(result.q)) and np.all(np.isfinite(result.history))
    assert result.q[0] <= 1.0

    # √q = 0.1 from q = 4: the first Newton step overshoots to q < 0, where √q is NaN.
    with np.errstate(invalid="ignore"):
        result = newton(lambda q: np.sqrt(q), [0.1], [4.0], jac=lambda q: 0.5 / np.sqrt(q)[None])
    assert result.status == "diverged"
    np.testing.assert_array_equal(result.q, [4.0])


@pytest.mark.parametrize(
    "kwargs",
    [
        {"x_d": [np.nan, 0.0]},
        {"x_d": [1.0, 2.0, 3.0]},
        {"q0": [np.inf, 0.0]},
        {"q0": [[0.0, 1.0]]},
        {"tol": -1e-3},
        {"tol": (1e-3, 1e-3)},  # a pair needs a pose residual of length 6
        {"step": -1.0},
        {"max_iter": -1},
        {"jac": lambda q: np.eye(3)},
        {"f": "not callable"},
    ],
)
def test_bad_inputs_raise_redik_errors(kwargs):
    arguments = {"f": two_link, "x_d": X_D, "q0": [0.1, 0.2], **kwargs}
    with pytest.raises(RedikError):
        newton(**arguments)


def test_gradient_rejects_an_unknown_step_name():
    with pytest.raises(InvalidInput):
        gradient(two_link, X_D, [0.1, 0.2], step="wolfe")


def test_the_jacobian_is_evaluated_once_per_iteration():
    calls = []

    def f(q):
        return np.array([np.cos(q[0]) + np.cos(q[0] + q[1]), np.sin(q[0]) + np.sin(q[0] + q[1])])

    def jac(q):
        calls.append(q.copy())
        s1, s12, c1, c12 = np.sin(q[0]), np.sin(q[0] + q[1]), np.cos(q[0]), np.cos(q[0] + q[1])
        return np.array([[-s1 - s12, -s12], [c1 + c12, c12]])

    result = newton(f, np.array([1.2, 0.7]), np.array([0.3, 0.4]), jac=jac)
    assert result.status == "converged"
    assert len(calls) == result.iterations  # jac(q0), checked up front, is reused
    np.testing.assert_array_equal(calls[0], [0.3, 0.4])
