r"""The classic iterative root finders on a user's own task function ``x = f(q)``.

``f`` maps ``n`` minimal coordinates to an ``r``-dimensional task; the error is
``e(q) = x_d − f(q)`` and every solver drives ``‖e‖`` to zero.

:func:`newton`
    Newton–Raphson (Lynch & Park, *Modern Robotics* §6.2.1):

    .. math:: q_{k+1} = q_k + λ\, J^{+}(q_k)\, e(q_k),

    with ``J⁺ = J⁻¹`` when ``J`` is square and invertible and the Moore–Penrose
    pseudo-inverse otherwise (fat ``J``: the least-norm step; tall ``J``: the least-squares
    step). Quadratic convergence near a regular root.
:func:`gradient`
    Gradient descent on :math:`F(q) = ½‖e(q)‖²`, the *Jacobian-transpose* method
    (Buss 2004, "Introduction to Inverse Kinematics with Jacobian Transpose, Pseudoinverse
    and Damped Least Squares methods", §4):

    .. math:: q_{k+1} = q_k + α\, J^{T}(q_k)\, e(q_k),

    since :math:`∇F = −J^{T} e`. With ``step="armijo"`` the step is found by backtracking
    from ``α = 1`` until :math:`F(q + α g) ≤ F(q) − c\, α ‖g‖²` (Nocedal & Wright,
    *Numerical Optimization* Alg. 3.1, ``c = 10⁻⁴``), so ``‖e‖`` never increases.

Both return an :class:`~redik.result.IKResult` whose ``history[0] = q0`` and ``history[k]``
is ``q`` after iteration ``k``, with ``error_history[k] = ‖e(history[k])‖``. Stopping rules,
each with its own ``status``: ``‖e‖ ≤ tol`` → ``"converged"``; ``‖Δq‖ ≤ q_tol`` with
``‖e‖ > tol`` → ``"stalled"``; the budget spent → ``"max_iterations"``; with ``singular_tol``,
``σ_min(J) ≤ singular_tol`` → ``"singular"`` (Newton only, without moving); a NaN or inf in
``f``, ``J`` or the step → ``"diverged"`` with the last finite iterate.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .exceptions import InvalidInput
from .lie import as_vector, real_array
from .result import IKResult

TaskFunction = Callable[[np.ndarray], np.ndarray]
"""A task function ``x = f(q)``: a length-``n`` vector to a length-``r`` vector."""

JacobianFunction = Callable[[np.ndarray], np.ndarray]
"""``J(q) = ∂f/∂q``, an ``r × n`` matrix."""

ARMIJO_SUFFICIENT_DECREASE = 1e-4
"""Armijo constant ``c``: accept ``α`` when ``F`` drops by at least ``c α ‖g‖²``."""

ARMIJO_SHRINK = 0.5
"""Backtracking factor applied to ``α`` after each rejected trial."""

ARMIJO_MAX_TRIALS = 60
"""Halvings tried before a line search gives up (``α`` then ≈ 10⁻¹⁸ of the first trial)."""

_MAX_MAGNITUDE = 1e150
"""Largest ``|x_d|``, ``|q0|`` entry and ``‖e‖`` taken: ``‖e‖²`` (Armijo's test) stays finite.
A larger error at an iterate counts as non-finite (the step is refused)."""


def finite_difference_jacobian(f: TaskFunction, q: np.ndarray) -> np.ndarray:
    r"""Central-difference Jacobian ``J[:, i] = (f(q + h_i e_i) − f(q − h_i e_i)) / 2h_i``.

    ``h_i = ε^{1/3} max(1, |q_i|)``, the step that balances the O(h²) truncation error
    against the O(ε/h) rounding error (Nocedal & Wright §8.1), so ``J`` is accurate to
    about ``ε^{2/3} ≈ 4·10⁻¹¹`` relative.
    """
    q = np.array(q, dtype=float)
    h = np.cbrt(np.finfo(float).eps) * np.maximum(1.0, np.abs(q))
    columns = []
    for i in range(q.size):
        saved = q[i]
        q[i] = saved + h[i]
        f_plus = np.asarray(f(q), dtype=float)
        q[i] = saved - h[i]
        f_minus = np.asarray(f(q), dtype=float)
        q[i] = saved
        columns.append((f_plus - f_minus) / (2.0 * h[i]))
    return np.stack(columns, axis=-1) if columns else np.empty((0, 0))


def newton(
    f: TaskFunction,
    x_d: np.ndarray,
    q0: np.ndarray,
    jac: JacobianFunction | None = None,
    step: float = 1.0,
    tol: float = 1e-6,
    q_tol: float | None = None,
    max_iter: int = 100,
    singular_tol: float | None = None,
) -> IKResult:
    r"""Newton–Raphson on ``x_d − f(q) = 0``: ``q ← q + λ J⁺(q) (x_d − f(q))``.

    Args:
        f: The task function ``x = f(q)``.
        x_d: The desired task value (length ``r``).
        q0: The initial guess (length ``n``).
        jac: ``J(q)`` (``r × n``); ``None`` uses :func:`finite_difference_jacobian`.
        step: The step scale ``λ`` (1 is the full Newton step).
        tol: Stop with ``"converged"`` when ``‖e‖ ≤ tol``.
        q_tol: Stop with ``"stalled"`` when ``‖Δq‖ ≤ q_tol`` and ``‖e‖ > tol``.
        max_iter: Iteration budget.
        singular_tol: Stop with ``"singular"`` when ``σ_min(J) ≤ singular_tol`` (the smallest
            of the ``min(r, n)`` singular values), before taking the step.

    Returns:
        An :class:`~redik.result.IKResult` (method ``"newton"``); see the module docstring.

    Raises:
        InvalidInput: a shape mismatch, a non-finite ``x_d``/``q0``, or a bad option.
    """
    _check_options(step, tol, q_tol, max_iter)
    if singular_tol is not None and not singular_tol >= 0.0:
        raise InvalidInput(f"singular_tol must be ≥ 0 or None, got {singular_tol!r}")
    run = _Run(f, x_d, q0, jac, "newton")
    if run.done(tol):
        return run.result("converged")
    for _ in range(max_iter):
        J = run.jacobian()
        if J is None:
            return run.result("diverged", "the Jacobian holds NaN or inf")
        if singular_tol is not None:
            sigma_min = float(np.linalg.svd(J, compute_uv=False)[-1]) if J.size else 0.0
            if sigma_min <= singular_tol:
                return run.result(
                    "singular", f"σ_min(J) = {sigma_min:.3g} ≤ singular_tol = {singular_tol:g}"
                )
        dq = step * _newton_step(J, run.e)
        if q_tol is not None and float(np.linalg.norm(dq)) <= q_tol:
            return run.result("stalled", f"‖Δq‖ ≤ q_tol = {q_tol:g} with ‖e‖ = {run.norm:.3g}")
        if not run.move(run.q + dq):
            return run.result("diverged", "the Newton step produced NaN or inf")
        if run.done(tol):
            return run.result("converged")
    return run.result("max_iterations")


def gradient(
    f: TaskFunction,
    x_d: np.ndarray,
    q0: np.ndarray,
    jac: JacobianFunction | None = None,
    step: float | str = 0.5,
    tol: float = 1e-6,
    q_tol: float | None = None,
    max_iter: int = 100,
) -> IKResult:
    r"""Jacobian transpose / gradient descent on ``½‖x_d − f(q)‖²``: ``q ← q + α Jᵀ e``.

    Args:
        f, x_d, q0, jac, tol, q_tol, max_iter: As for :func:`newton`.
        step: A constant ``α > 0``, or ``"armijo"`` for a backtracking line search that never
            lets ``‖e‖`` increase (when no trial decreases it, the search stops with
            ``"stalled"``: ``q`` is then a stationary point to working precision).

    Returns:
        An :class:`~redik.result.IKResult` (method ``"gradient"``).
    """
    armijo = step == "armijo"
    _check_options(1.0 if armijo else step, tol, q_tol, max_iter)
    run = _Run(f, x_d, q0, jac, "gradient")
    if run.done(tol):
        return run.result("converged")
    for _ in range(max_iter):
        J = run.jacobian()
        if J is None:
            return run.result("diverged", "the Jacobian holds NaN or inf")
        g = J.T @ run.e
        if armijo:
            found = _armijo(run, g, q_tol)
            if found is not None:
                return found
        else:
            dq = step * g
            if q_tol is not None and float(np.linalg.norm(dq)) <= q_tol:
                return run.result("stalled", f"‖Δq‖ ≤ q_tol = {q_tol:g} with ‖e‖ = {run.norm:.3g}")
            if not run.move(run.q + dq):
                return run.result("diverged", "the gradient step produced NaN or inf")
        if run.done(tol):
            return run.result("converged")
    return run.result("max_iterations")


# --------------------------------------------------------------------------------------
# Internals


class _Run:
    """The state of one solve: the current ``q``, ``e`` and the history so far."""

    def __init__(
        self,
        f: TaskFunction,
        x_d: np.ndarray,
        q0: np.ndarray,
        jac: JacobianFunction | None,
        method: str,
    ) -> None:
        if not callable(f):
            raise InvalidInput(f"f must be callable, got {f!r}")
        if jac is not None and not callable(jac):
            raise InvalidInput(f"jac must be callable or None, got {jac!r}")
        self.x_d = _finite_vector(x_d, "x_d")
        self.q = _finite_vector(q0, "q0").copy()
        self.f = f
        self.jac = jac
        self.method = method
        x = real_array(f(self.q.copy()), "f(q0)")
        if x.shape != self.x_d.shape:
            raise InvalidInput(
                f"f(q0) has shape {x.shape} but x_d has shape {self.x_d.shape}; "
                "f must return a vector of the task's length"
            )
        self._J0 = None  # jac(q0), checked here and used by the first iteration
        if jac is not None:
            J = real_array(jac(self.q.copy()), "jac(q0)")
            expected = (self.x_d.size, self.q.size)
            if J.shape != expected:
                raise InvalidInput(f"jac(q0) must have shape {expected} (r × n), got {J.shape}")
            self._J0 = J
        self.e = self.x_d - x
        with np.errstate(over="ignore", invalid="ignore"):
            self.norm = float(np.linalg.norm(self.e))
        if not self.norm <= _MAX_MAGNITUDE:
            raise InvalidInput(
                f"f(q0) must be finite with ‖x_d − f(q0)‖ ≤ {_MAX_MAGNITUDE:g}, got {x.tolist()}"
            )
        self.history = [self.q.copy()]
        self.errors = [self.norm]

    def done(self, tol: float) -> bool:
        return self.norm <= tol

    def jacobian(self) -> np.ndarray | None:
        if self._J0 is not None:
            J, self._J0 = self._J0, None
        elif self.jac is None:
            J = finite_difference_jacobian(self.f, self.q)
        else:
            J = np.asarray(self.jac(self.q.copy()), dtype=float)
        return J if np.all(np.isfinite(J)) else None

    def evaluate(self, q: np.ndarray) -> tuple[np.ndarray, float] | None:
        """``(e, ‖e‖)`` at ``q``, or None when ``q`` or ``f(q)`` is not finite (or so large
        that ``‖e‖²`` overflows)."""
        if not np.all(np.isfinite(q)):
            return None
        e = self.x_d - np.asarray(self.f(q.copy()), dtype=float)
        with np.errstate(over="ignore", invalid="ignore"):
            norm = float(np.linalg.norm(e))
        return (e, norm) if norm <= _MAX_MAGNITUDE else None

    def move(self, q: np.ndarray) -> bool:
        """Accept ``q`` as the next iterate; False (and no move) when it is not finite."""
        evaluated = self.evaluate(q)
        if evaluated is None:
            return False
        self.accept(q, *evaluated)
        return True

    def accept(self, q: np.ndarray, e: np.ndarray, norm: float) -> None:
        self.q, self.e, self.norm = q, e, norm
        self.history.append(q.copy())
        self.errors.append(norm)

    def result(self, status: str, message: str = "") -> IKResult:
        return IKResult(
            q=self.q.copy(),
            success=status == "converged",
            status=status,
            iterations=len(self.history) - 1,
            error=self.norm,
            history=np.array(self.history),
            error_history=np.array(self.errors),
            method=self.method,
            message=message,
        )


def _newton_step(J: np.ndarray, e: np.ndarray) -> np.ndarray:
    """``J⁻¹ e`` for a square invertible ``J``, else the least-norm least-squares ``J⁺ e``."""
    if J.shape[0] == J.shape[1]:
        try:
            return np.linalg.solve(J, e)
        except np.linalg.LinAlgError:
            pass  # exactly singular: fall through to the pseudo-inverse
    return np.linalg.pinv(J) @ e


def _armijo(run: _Run, g: np.ndarray, q_tol: float | None) -> IKResult | None:
    """One backtracking line search along ``g = Jᵀ e``; a result when the run must stop."""
    with np.errstate(over="ignore", invalid="ignore"):
        slope = float(g @ g)
    if not math.isfinite(slope):
        return run.result("diverged", f"‖Jᵀe‖² overflows at ‖e‖ = {run.norm:.3g}")
    F = 0.5 * run.norm**2
    alpha = 1.0
    for _ in range(ARMIJO_MAX_TRIALS):
        dq = alpha * g
        if q_tol is not None and float(np.linalg.norm(dq)) <= q_tol:
            return run.result("stalled", f"‖Δq‖ ≤ q_tol = {q_tol:g} with ‖e‖ = {run.norm:.3g}")
        trial = run.q + dq
        evaluated = run.evaluate(trial)
        if evaluated is not None and 0.5 * evaluated[1] ** 2 <= F - ARMIJO_SUFFICIENT_DECREASE * (
            alpha * slope
        ):
            run.accept(trial, *evaluated)
            return None
        alpha *= ARMIJO_SHRINK
    return run.result(
        "stalled", f"no Armijo step decreases ‖e‖ = {run.norm:.3g} (‖Jᵀe‖ = {slope**0.5:.3g})"
    )


def _finite_vector(x: np.ndarray, name: str) -> np.ndarray:
    x = np.atleast_1d(real_array(x, name))
    if x.ndim != 1:
        raise InvalidInput(f"{name} must be a vector, got shape {x.shape}")
    x = as_vector(x, x.size, name)
    if np.abs(x).max(initial=0.0) > _MAX_MAGNITUDE:
        raise InvalidInput(f"{name} must be within ±{_MAX_MAGNITUDE:g} (‖e‖² overflows): {x}")
    return x


def _check_options(step: float, tol: float, q_tol: float | None, max_iter: int) -> None:
    if isinstance(step, str) or not (isinstance(step, (int, float)) and step > 0):
        raise InvalidInput(f"step must be a positive number or 'armijo', got {step!r}")
    if not (isinstance(tol, (int, float)) and tol > 0):
        raise InvalidInput(f"tol must be a positive number, got {tol!r}")
    if q_tol is not None and not (isinstance(q_tol, (int, float)) and q_tol >= 0):
        raise InvalidInput(f"q_tol must be ≥ 0 or None, got {q_tol!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 0:
        raise InvalidInput(f"max_iter must be a non-negative integer, got {max_iter!r}")
