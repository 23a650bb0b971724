r"""The classic iterative root finders on a user's own task function ``x = f(q)``:
:func:`solve_equations` (``redik.solve_equations``) and the three methods it runs.

``f`` maps ``n`` minimal coordinates to an ``r``-dimensional task; the error is
``e(q) = x_d − f(q)`` and every solver drives ``‖e‖`` to zero (Lynch & Park, *Modern
Robotics* §6.2; the numbered options below are the textbook's, so a course's worked example
can be reproduced line by line — ``tests/test_course.py``). They take any function, where
:func:`redik.solve_pose` takes a robot and a pose; their names say which algorithm runs.

:func:`newton_raphson`
    Newton–Raphson (*Modern Robotics* §6.2.1):

    .. math:: q_{k+1} = q_k + λ^k\, J^{+}(q_k)\, e(q_k),

    with ``J⁺ = J⁻¹`` when ``J`` is square and invertible and the Moore–Penrose
    pseudo-inverse otherwise (fat ``J``: the least-norm step; tall ``J``: the least-squares
    step). Quadratic convergence near a regular root. ``λ^k`` is a constant ``step`` or,
    with ``step="armijo"``, adaptive (below).
:func:`gradient_descent`
    Gradient descent on :math:`F(q) = ½\, e^T K e`, the *Jacobian-transpose* method
    (Buss 2004, "Introduction to Inverse Kinematics with Jacobian Transpose, Pseudoinverse
    and Damped Least Squares methods", §4; Siciliano et al., *Robotics: Modelling,
    Planning and Control* §3.7.2, ``q̇ = Jᵀ K e``):

    .. math:: q_{k+1} = q_k + α\, J^{T}(q_k)\, K\, e(q_k),

    since :math:`∇F = −J^{T} K e`. ``K`` (``gain``) is a symmetric positive-definite
    ``r × r`` gain, the identity by default; it weighs the task components against each
    other (metres against radians in a pose error).
:func:`gradient_then_newton`
    Gradient steps while ``‖e‖ > switch_error`` — robust far from the root, where Newton's
    linearisation is poor or ``J`` near-singular — then Newton steps for the quadratic
    terminal convergence (the "hybrid" method of the course notes; Nocedal & Wright
    §11.2 motivate the same globalisation).

Adaptive step (``step="armijo"``)
    Backtracking from ``λ = 1`` (halving, at most :data:`ARMIJO_MAX_TRIALS` times) until
    the Armijo condition on the merit ``F = ½ eᵀKe`` holds along the direction ``d``:

    .. math:: F(q + λ d) ≤ F(q) + c\, λ\, ∇F^T d, \qquad ∇F^T d = −e^T K J d,

    ``c = 10⁻⁴`` (Nocedal & Wright, *Numerical Optimization* Alg. 3.1). For Newton
    ``∇Fᵀd = −eᵀJJ⁺e`` (``−‖e‖²`` for a square regular ``J``), so the full step is taken
    near the root and quadratic convergence is kept; far away ``‖e‖`` never increases.

Jacobian
    ``jac(q)`` when given, else finite differences (:func:`finite_difference_jacobian`):
    ``fd_scheme="central"`` (default, step ``ε^{1/3}``) or ``"forward"``, with the step
    ``fd_step = δ`` when the course fixes one.

Stopping rules, each with its own ``status``
    - ``tol``: ``‖e‖ ≤ tol`` → ``"converged"``. A pair ``tol = (ε_p, ε_R)`` for a pose
      residual ``e = (e_p, e_R)`` of length 6, ordered (position, orientation) as twists are
      in :mod:`redik.core.conventions`: converged when ``‖e_p‖ ≤ ε_p`` and ``‖e_R‖ ≤ ε_R``
      (metres and radians are not comparable, so one norm would mix units). ``tol = 0``
      never stops on the error: all ``max_iterations`` iterations run (to reproduce an iterate
      table); the status is then ``"max_iterations"``, or ``"converged"`` when ``e`` ended
      exactly 0.
    - ``rel_tol``: the relative change :math:`‖f(q_{k+1}) − f(q_k)‖ / ‖e(q_k)‖ ≤ ε`
      (equivalently ``‖e_{k+1} − e_k‖ / ‖e_k‖``) ends the iteration; the status is
      ``"converged"`` when ``tol`` is met too (or ``e`` is exactly 0), else ``"stalled"``
      (a small change does not certify a root: it happens at a local minimum of ``‖e‖`` as
      well).
    - ``q_tol``: ``‖Δq‖ ≤ q_tol`` with ``‖e‖ > tol`` → ``"stalled"`` (without moving).
    - ``singular_tol``: ``σ_min(J) ≤ singular_tol`` → ``"singular"`` (without moving),
      checked before each step (the Newton phase only for :func:`gradient_then_newton`).
    - A NaN or inf in ``f``, ``J`` or the step, or a finite blow-up — an iterate with
      ``‖q‖_∞ > max_growth · max(1, ‖q_0‖_∞)`` or an error with
      ``‖e‖ > max_growth · max(1, ‖e_0‖)`` (``max_growth = 10⁸`` by default: beyond it a
      float64 angle has lost half its digits) → ``"diverged"``, with the last sane iterate.
      This is what a Newton step from a numerically singular start (``q ≈ 10¹⁶``) ends as.
    - The budget spent → ``"max_iterations"``.

Every solver returns an :class:`~redik.core.result.IKResult` whose ``history[0] = q0`` and
``history[k]`` is ``q`` after iteration ``k``, with ``error_history[k] = ‖e(history[k])‖``;
with a pair ``tol`` its ``position_error``/``rotation_error`` are ``‖e_p‖``/``‖e_R‖``.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import IKResult, Status
from redik.core.validate import as_vector, integer, non_negative, positive, real_array

TaskFunction = Callable[[np.ndarray], np.ndarray]
"""A task function ``x = f(q)``: a length-``n`` vector to a length-``r`` vector."""

JacobianFunction = Callable[[np.ndarray], np.ndarray]
"""``J(q) = ∂f/∂q``, an ``r × n`` matrix."""

Tolerance = float | tuple[float, float]
"""``tol``: one bound on ``‖e‖``, or ``(ε_p, ε_R)`` on the two halves of a pose residual."""

ARMIJO_SUFFICIENT_DECREASE = 1e-4
"""Armijo constant ``c``: accept ``λ`` when ``F`` drops by at least ``c λ |∇Fᵀd|``."""

ARMIJO_SHRINK = 0.5
"""Backtracking factor applied to ``λ`` after each rejected trial."""

ARMIJO_MAX_TRIALS = 60
"""Halvings tried before a line search of the root finders here gives up: ``λ`` then is
``2⁻⁶⁰ ≈ 8.7·10⁻¹⁹`` of the first trial, below the double-precision spacing (``2⁻⁵² ≈
2.2·10⁻¹⁶``) relative to a unit step, so a longer search would only re-evaluate ``q`` itself.
These runs have no restart to fall back on and often a ``q_tol`` (``min_alpha``) that ends
the search earlier, so the budget is "until the step cannot move ``q``"."""

ARMIJO_ATTEMPT_TRIALS = 30
"""Halvings tried by a line search inside one attempt of a restarting solver (the
``"transpose"``/``"hybrid"`` methods of :func:`redik.solve_pose`): ``λ`` then is ``2⁻³⁰ ≈
9.3·10⁻¹⁰`` of Buss's step ``α₀``, itself the minimiser along ``Jᵀe`` of the linearised
error. No decrease at a billionth of that step is a stalled attempt (a stationary point of
``‖e‖²`` or a limit-blocked direction), and a random restart is a better use of the 30
more forward-kinematics-and-Jacobian evaluations that :data:`ARMIJO_MAX_TRIALS` would spend
on steps of ``10⁻⁹``–``10⁻¹⁸`` ``α₀`` (moves far below the pose tolerances)."""

MAX_GROWTH = 1e8
"""Default ``max_growth``: an iterate or error this many times its starting scale diverged."""

FD_SCHEMES = ("central", "forward")
"""The finite-difference schemes of :func:`finite_difference_jacobian`."""

_MAX_MAGNITUDE = 1e150
"""Largest ``|x_d|``, ``|q0|`` entry and ``‖e‖`` taken: ``‖e‖²`` (Armijo's test) stays finite.
A larger error at an iterate counts as non-finite (the step is refused)."""


def finite_difference_jacobian(
    f: TaskFunction,
    q: np.ndarray,
    step: float | None = None,
    scheme: str = "central",
    f_q: np.ndarray | None = None,
) -> np.ndarray:
    r"""Finite-difference Jacobian of ``f`` at ``q``, column by column.

    ``scheme="central"``: ``J[:, i] = (f(q + h_i e_i) − f(q − h_i e_i)) / 2h_i``, error
    O(h²); ``scheme="forward"``: ``J[:, i] = (f(q + h_i e_i) − f(q)) / h_i``, error O(h)
    (the course's formula, one evaluation per column).

    With ``step=None`` the step balances truncation against rounding (Nocedal & Wright
    §8.1): ``h_i = ε^{1/3} max(1, |q_i|)`` for central differences (accurate to about
    ``ε^{2/3} ≈ 4·10⁻¹¹``), ``h_i = ε^{1/2} max(1, |q_i|)`` for forward ones (about
    ``ε^{1/2} ≈ 10⁻⁸``). A number ``step = δ`` uses ``h_i = δ`` for every column, as a
    textbook exercise does (with ``δ = 0.1`` the forward Jacobian of ``x²`` at 1 is 2.1).

    Args:
        f: The task function.
        q: Where to differentiate (length ``n``).
        step: The step ``δ > 0``, or None for the automatic one.
        scheme: One of :data:`FD_SCHEMES`.
        f_q: ``f(q)`` when already known (saves one evaluation for ``"forward"``).
    """
    if scheme not in FD_SCHEMES:
        raise InvalidInput(f"scheme must be one of {FD_SCHEMES}, got {scheme!r}")
    if not callable(f):
        raise InvalidInput(f"f must be callable, got {f!r}")
    if step is not None:
        step = positive(step, "the finite-difference step")
    return _difference_jacobian(f, _finite_vector(q, "q"), step, scheme, f_q)


def _difference_jacobian(
    f: TaskFunction, q: np.ndarray, step: float | None, scheme: str, f_q: np.ndarray | None
) -> np.ndarray:
    """:func:`finite_difference_jacobian` on checked arguments: the solvers call it every
    iteration, after :class:`_Run` checked ``f``, ``fd_step`` and ``fd_scheme`` once."""
    q = q.copy()
    if step is None:
        exponent = 1.0 / 3.0 if scheme == "central" else 0.5
        h = np.finfo(float).eps ** exponent * np.maximum(1.0, np.abs(q))
    else:
        h = np.full(q.size, step)
    forward = scheme == "forward"
    if forward and f_q is None:
        f_q = np.asarray(f(q.copy()), dtype=float)
    columns = []
    for i in range(q.size):
        saved = q[i]
        q[i] = saved + h[i]
        f_plus = np.asarray(f(q.copy()), dtype=float)
        if forward:
            columns.append((f_plus - f_q) / h[i])
        else:
            q[i] = saved - h[i]
            f_minus = np.asarray(f(q.copy()), dtype=float)
            columns.append((f_plus - f_minus) / (2.0 * h[i]))
        q[i] = saved
    return np.stack(columns, axis=-1) if columns else np.empty((0, 0))


def newton_raphson(
    f: TaskFunction,
    x_d: np.ndarray,
    q0: np.ndarray,
    jac: JacobianFunction | None = None,
    step: float | str = 1.0,
    tol: Tolerance = 1e-6,
    q_tol: float | None = None,
    max_iterations: int = 100,
    singular_tol: float | None = None,
    *,
    rel_tol: float | None = None,
    fd_step: float | None = None,
    fd_scheme: str = "central",
    max_growth: float = MAX_GROWTH,
) -> IKResult:
    r"""Newton–Raphson on ``x_d − f(q) = 0``: ``q ← q + λ^k J⁺(q) (x_d − f(q))``.

    Args:
        f: The task function ``x = f(q)``.
        x_d: The desired task value (length ``r``).
        q0: The initial guess (length ``n``).
        jac: ``J(q)`` (``r × n``); ``None`` uses :func:`finite_difference_jacobian`.
        step: The step scale ``λ`` (1 is the full Newton step), or ``"armijo"`` for the
            adaptive ``λ^k`` of the module docstring.
        tol: ``‖e‖ ≤ tol`` → ``"converged"``; ``(ε_p, ε_R)`` for a 6-vector pose residual;
            0 runs all ``max_iterations`` iterations (module docstring).
        q_tol: Stop with ``"stalled"`` when ``‖Δq‖ ≤ q_tol`` and ``‖e‖ > tol``.
        max_iterations: Iteration budget.
        singular_tol: Stop with ``"singular"`` when ``σ_min(J) ≤ singular_tol`` (the smallest
            of the ``min(r, n)`` singular values), before taking the step.
        rel_tol: Stop when ``‖e_{k+1} − e_k‖ / ‖e_k‖ ≤ rel_tol`` (module docstring).
        fd_step, fd_scheme: The finite-difference step ``δ`` and scheme when ``jac`` is None.
        max_growth: The blow-up bound of the ``"diverged"`` status (module docstring).

    Returns:
        An :class:`~redik.core.result.IKResult` (method ``"newton"``); see the module docstring.

    Raises:
        InvalidInput: a shape mismatch, a non-finite ``x_d``/``q0``, or a bad option.
    """
    step = _step_option(step, "step")
    options = _Options.checked(tol, q_tol, max_iterations, singular_tol, rel_tol, max_growth)
    run = _Run(f, x_d, q0, jac, "newton", options, fd_step, fd_scheme, None)
    return _iterate(run, options, lambda J, e: (_newton_step(J, e), step))


def gradient_descent(
    f: TaskFunction,
    x_d: np.ndarray,
    q0: np.ndarray,
    jac: JacobianFunction | None = None,
    step: float | str = 0.5,
    tol: Tolerance = 1e-6,
    q_tol: float | None = None,
    max_iterations: int = 100,
    singular_tol: float | None = None,
    *,
    gain: np.ndarray | float | None = None,
    rel_tol: float | None = None,
    fd_step: float | None = None,
    fd_scheme: str = "central",
    max_growth: float = MAX_GROWTH,
) -> IKResult:
    r"""Jacobian transpose / gradient descent on ``½ eᵀKe``: ``q ← q + α Jᵀ K e``.

    Args:
        f, x_d, q0, jac, tol, q_tol, max_iterations, rel_tol, fd_step, fd_scheme, max_growth:
            As for :func:`newton_raphson`.
        step: A constant ``α > 0``, or ``"armijo"`` for a backtracking line search that never
            lets ``eᵀKe`` increase (when no trial decreases it, the search stops with
            ``"stalled"``: ``q`` is then a stationary point to working precision).
        singular_tol: Stop with ``"singular"`` when ``σ_min(J) ≤ singular_tol``: near a
            singularity ``Jᵀe`` loses the components of ``e`` along the lost directions and
            the method crawls (or stops at ``Jᵀe = 0`` with ``e ≠ 0``).
        gain: The gain ``K``: a symmetric positive-definite ``r × r`` matrix, a length-``r``
            vector (its diagonal) or a positive number (``k I``); default the identity.

    Returns:
        An :class:`~redik.core.result.IKResult` (method ``"gradient"``).
    """
    step = _step_option(step, "step")
    options = _Options.checked(tol, q_tol, max_iterations, singular_tol, rel_tol, max_growth)
    run = _Run(f, x_d, q0, jac, "gradient", options, fd_step, fd_scheme, gain)
    return _iterate(run, options, lambda J, e: (J.T @ (run.K @ e), step))


def gradient_then_newton(
    f: TaskFunction,
    x_d: np.ndarray,
    q0: np.ndarray,
    jac: JacobianFunction | None = None,
    switch_error: float = 0.1,
    gradient_step: float | str = "armijo",
    newton_step: float | str = 1.0,
    tol: Tolerance = 1e-6,
    q_tol: float | None = None,
    max_iterations: int = 100,
    singular_tol: float | None = None,
    *,
    gain: np.ndarray | float | None = None,
    rel_tol: float | None = None,
    fd_step: float | None = None,
    fd_scheme: str = "central",
    max_growth: float = MAX_GROWTH,
) -> IKResult:
    r"""Gradient steps ``α JᵀKe`` while ``‖e‖ > switch_error``, then Newton steps ``λ J⁺e``.

    The phase is chosen afresh at every iteration from the current ``‖e‖``, so a Newton
    step that lands outside the switch radius hands back to the gradient.

    Args:
        switch_error: The error norm below which Newton takes over (> 0).
        gradient_step: ``α`` of the gradient phase, as ``step`` of :func:`gradient_descent`.
        newton_step: ``λ`` of the Newton phase, as ``step`` of :func:`newton_raphson`.
        singular_tol: Checked before each Newton step (the gradient phase is exactly what
            is used where ``J`` is ill-conditioned).
        f, x_d, q0, jac, tol, q_tol, max_iterations, gain, rel_tol, fd_step, fd_scheme,
        max_growth: As for :func:`gradient_descent`.

    Returns:
        An :class:`~redik.core.result.IKResult` (method ``"hybrid"``).
    """
    switch_error = positive(switch_error, "switch_error")
    gradient_step = _step_option(gradient_step, "gradient_step")
    newton_step = _step_option(newton_step, "newton_step")
    if singular_tol is not None:  # checked by the Newton phase only, not by _iterate
        singular_tol = non_negative(singular_tol, "singular_tol")
    options = _Options.checked(tol, q_tol, max_iterations, None, rel_tol, max_growth)
    run = _Run(f, x_d, q0, jac, "hybrid", options, fd_step, fd_scheme, gain)

    def direction(J: np.ndarray, e: np.ndarray) -> tuple[np.ndarray, float | str] | IKResult:
        if run.norm > switch_error:
            return J.T @ (run.K @ e), gradient_step
        if singular_tol is not None:
            stop = _singular(run, J, singular_tol)
            if stop is not None:
                return stop
        return _newton_step(J, e), newton_step

    return _iterate(run, options, direction)


METHODS = {
    "newton": newton_raphson,
    "gradient": gradient_descent,
    "hybrid": gradient_then_newton,
}
"""The methods of :func:`solve_equations`, by name (the ``method`` of the result)."""


def solve_equations(
    f: TaskFunction,
    x_d: np.ndarray,
    q0: np.ndarray,
    method: str = "newton",
    jac: JacobianFunction | None = None,
    **options: object,
) -> IKResult:
    r"""Solve ``f(q) = x_d`` for ``q`` from ``q0`` with one of the root finders above.

    The one entry point for a user's own task function, as :func:`redik.solve_pose` is for
    a robot's pose: ``method`` picks :func:`newton_raphson` (``"newton"``),
    :func:`gradient_descent` (``"gradient"``) or :func:`gradient_then_newton`
    (``"hybrid"``), and ``options`` are that function's keywords (``step``, ``tol``,
    ``max_iterations``, ``gain``, ``switch_error``…).

    Returns:
        The method's :class:`~redik.core.result.IKResult`.

    Raises:
        InvalidInput: an unknown method or an option the method does not take, and what the
            method itself refuses.
    """
    if not isinstance(method, str) or method not in METHODS:
        raise InvalidInput(f"method must be one of {list(METHODS)}, got {method!r}")
    solver = METHODS[method]
    known = list(inspect.signature(solver).parameters)[4:]  # after f, x_d, q0, jac
    unknown = sorted(set(options) - set(known))
    if unknown:
        raise InvalidInput(f"unknown option(s) {unknown} for method={method!r}; it takes {known}")
    return solver(f, x_d, q0, jac, **options)


# --------------------------------------------------------------------------------------
# Internals


@dataclass(frozen=True)
class _Options:
    """The validated stopping options of one solve."""

    tol: float
    pose_tol: tuple[float, float] | None
    q_tol: float | None
    max_iterations: int
    singular_tol: float | None
    rel_tol: float | None
    max_growth: float

    @classmethod
    def checked(
        cls,
        tol: object,
        q_tol: object,
        max_iterations: object,
        singular_tol: object,
        rel_tol: object,
        max_growth: object,
    ) -> _Options:
        pose_tol = None
        if isinstance(tol, (tuple, list, np.ndarray)):
            pair = [non_negative(value, "tol") for value in tol]
            if len(pair) != 2:
                raise InvalidInput(f"tol must be a number or a pair (ε_p, ε_R), got {tol!r}")
            pose_tol = (pair[0], pair[1])
            tol = 0.0
        tol = non_negative(tol, "tol")
        return cls(
            tol=tol,
            pose_tol=pose_tol,
            q_tol=None if q_tol is None else non_negative(q_tol, "q_tol"),
            max_iterations=integer(max_iterations, "max_iterations"),
            singular_tol=None
            if singular_tol is None
            else non_negative(singular_tol, "singular_tol"),
            rel_tol=None if rel_tol is None else non_negative(rel_tol, "rel_tol"),
            max_growth=positive(max_growth, "max_growth", allow_inf=True),
        )


class _Run:
    """The state of one solve: the current ``q``, ``e`` and the history so far."""

    def __init__(
        self,
        f: TaskFunction,
        x_d: np.ndarray,
        q0: np.ndarray,
        jac: JacobianFunction | None,
        method: str,
        options: _Options,
        fd_step: float | None,
        fd_scheme: str,
        gain: np.ndarray | float | None,
    ) -> None:
        if not callable(f):
            raise InvalidInput(f"f must be callable, got {f!r}")
        if jac is not None and not callable(jac):
            raise InvalidInput(f"jac must be callable or None, got {jac!r}")
        if fd_scheme not in FD_SCHEMES:
            raise InvalidInput(f"fd_scheme must be one of {FD_SCHEMES}, got {fd_scheme!r}")
        if fd_step is not None:
            fd_step = positive(fd_step, "fd_step")
        self.x_d = _finite_vector(x_d, "x_d")
        self.q = _finite_vector(q0, "q0").copy()
        if self.q.size == 0:
            raise InvalidInput("q0 must hold at least one joint value, got an empty vector")
        self.f = f
        self.jac = jac
        self.fd_step, self.fd_scheme = fd_step, fd_scheme
        self.method = method
        self.options = options
        r = self.x_d.size
        if options.pose_tol is not None and r != 6:
            raise InvalidInput(
                f"tol = (ε_p, ε_R) needs a pose residual of length 6 (position, orientation), "
                f"but x_d has length {r}"
            )
        self.K = _gain(gain, r)
        x = real_array(f(self.q.copy()), "f(q0)")
        if x.shape != self.x_d.shape:
            raise InvalidInput(
                f"f(q0) has shape {x.shape} but x_d has shape {self.x_d.shape}; "
                "f must return a vector of the task's length"
            )
        self.x = x
        self._J0 = None  # jac(q0), checked here and used by the first iteration
        if jac is not None:
            J = real_array(jac(self.q.copy()), "jac(q0)")
            expected = (r, self.q.size)
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
        self.q_bound = options.max_growth * max(1.0, float(np.max(np.abs(self.q), initial=0.0)))
        self.e_bound = options.max_growth * max(1.0, self.norm)

    def done(self) -> bool:
        """The tolerance is met (never, for ``tol = 0``: every iteration runs)."""
        pose_tol = self.options.pose_tol
        if pose_tol is not None:
            position, rotation = self.pose_errors()
            return position <= pose_tol[0] and rotation <= pose_tol[1]
        return self.options.tol > 0.0 and self.norm <= self.options.tol

    def pose_errors(self) -> tuple[float, float]:
        return float(np.linalg.norm(self.e[:3])), float(np.linalg.norm(self.e[3:]))

    def merit(self, e: np.ndarray) -> float:
        """``F = ½ eᵀKe`` (inf where it overflows: such a trial is never accepted)."""
        with np.errstate(over="ignore", invalid="ignore"):
            return 0.5 * float(e @ (self.K @ e))

    def jacobian(self) -> np.ndarray | None:
        if self._J0 is not None:
            J, self._J0 = self._J0, None
        elif self.jac is None:
            J = _difference_jacobian(self.f, self.q, self.fd_step, self.fd_scheme, self.x)
        else:
            J = np.asarray(self.jac(self.q.copy()), dtype=float)
        return J if np.all(np.isfinite(J)) else None

    def evaluate(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float] | None:
        """``(x, e, ‖e‖)`` at ``q``, or None when ``q`` or ``f(q)`` is not finite (or so
        large that ``‖e‖²`` overflows)."""
        if not np.all(np.isfinite(q)):
            return None
        x = np.asarray(self.f(q.copy()), dtype=float)
        e = self.x_d - x
        with np.errstate(over="ignore", invalid="ignore"):
            norm = float(np.linalg.norm(e))
        return (x, e, norm) if norm <= _MAX_MAGNITUDE else None

    def blown_up(self, q: np.ndarray, norm: float) -> bool:
        return float(np.max(np.abs(q), initial=0.0)) > self.q_bound or norm > self.e_bound

    def accept(self, q: np.ndarray, x: np.ndarray, e: np.ndarray, norm: float) -> None:
        self.q, self.x, self.e, self.norm = q, x, e, norm
        self.history.append(q.copy())
        self.errors.append(norm)

    def result(self, status: Status, message: str = "") -> IKResult:
        position = rotation = None
        if self.options.pose_tol is not None:
            position, rotation = self.pose_errors()
        return IKResult(
            q=self.q.copy(),
            success=status == Status.CONVERGED,
            status=status,
            iterations=len(self.history) - 1,
            error=self.norm,
            position_error=position,
            rotation_error=rotation,
            history=np.array(self.history),
            error_history=np.array(self.errors),
            method=self.method,
            message=message,
        )


Direction = Callable[[np.ndarray, np.ndarray], "tuple[np.ndarray, float | str] | IKResult"]


def _iterate(run: _Run, options: _Options, direction: Direction) -> IKResult:
    """The loop shared by every method: Jacobian, checks, one (line-searched) step, stops."""
    if run.done():
        return run.result(Status.CONVERGED)
    for _ in range(options.max_iterations):
        J = run.jacobian()
        if J is None:
            return run.result(Status.DIVERGED, "the Jacobian holds NaN or inf")
        if options.singular_tol is not None:
            stop = _singular(run, J, options.singular_tol)
            if stop is not None:
                return stop
        chosen = direction(J, run.e)
        if isinstance(chosen, IKResult):
            return chosen
        d, step = chosen
        e_before = run.e
        stop = _step(run, J, d, step)
        if stop is not None:
            return stop
        if run.done():
            return run.result(Status.CONVERGED)
        if options.rel_tol is not None:
            stop = _relative_change_stop(run, e_before, options.rel_tol)
            if stop is not None:
                return stop
    if run.norm == 0.0:
        return run.result(Status.CONVERGED)
    return run.result(Status.MAX_ITERATIONS)


def _relative_change_stop(run: _Run, e_before: np.ndarray, rel_tol: float) -> IKResult | None:
    """Stop when ``‖e_{k+1} − e_k‖ ≤ rel_tol ‖e_k‖`` (multiplied out: at an exact root both
    sides are 0, and the run ends ``"converged"``, as at the end of a ``tol = 0`` run)."""
    previous = run.errors[-2]
    change = float(np.linalg.norm(run.e - e_before))
    if change > rel_tol * previous:
        return None
    if run.norm == 0.0:
        return run.result(Status.CONVERGED)
    return run.result(
        Status.STALLED,
        f"relative change ‖e_k+1 − e_k‖/‖e_k‖ = {change / previous:.3g} ≤ rel_tol = "
        f"{rel_tol:g} with ‖e‖ = {run.norm:.3g} above tol",
    )


def _singular(run: _Run, J: np.ndarray, singular_tol: float) -> IKResult | None:
    sigma_min = float(np.linalg.svd(J, compute_uv=False)[-1]) if J.size else 0.0
    if sigma_min <= singular_tol:
        return run.result(
            Status.SINGULAR, f"σ_min(J) = {sigma_min:.3g} ≤ singular_tol = {singular_tol:g}"
        )
    return None


def _step(run: _Run, J: np.ndarray, d: np.ndarray, step: float | str) -> IKResult | None:
    """Move along ``d`` by ``step`` (a number or ``"armijo"``); a result when the run stops."""
    q_tol = run.options.q_tol
    if step != "armijo":
        dq = step * d
        if q_tol is not None and float(np.linalg.norm(dq)) <= q_tol:
            return run.result(Status.STALLED, f"‖Δq‖ ≤ q_tol = {q_tol:g} with ‖e‖ = {run.norm:.3g}")
        return _move(run, run.q + dq)
    with np.errstate(over="ignore", invalid="ignore"):
        slope = -float(run.e @ (run.K @ (J @ d)))  # ∇Fᵀd
    if not math.isfinite(slope):
        return run.result(Status.DIVERGED, f"the slope ∇Fᵀd overflows at ‖e‖ = {run.norm:.3g}")
    if not slope < 0.0:
        return run.result(
            Status.STALLED, f"the direction does not decrease ½eᵀKe (slope {slope:.3g}); ‖e‖ = "
            f"{run.norm:.3g}"
        )  # fmt: skip
    F = run.merit(run.e)
    accepted = []

    def merit_at(alpha: float) -> float:
        trial = run.q + alpha * d
        evaluated = run.evaluate(trial)
        if evaluated is None or run.blown_up(trial, evaluated[2]):
            return math.inf
        accepted[:] = [trial, evaluated]
        return run.merit(evaluated[1])

    norm_d = float(np.linalg.norm(d))  # ‖λd‖ ≤ q_tol ⟺ λ ≤ q_tol / ‖d‖
    if q_tol is None:
        min_alpha = 0.0
    else:
        min_alpha = math.inf if norm_d <= q_tol else q_tol / norm_d
    alpha, outcome = armijo_backtrack(merit_at, F, slope, min_alpha=min_alpha)
    if alpha is not None:
        run.accept(accepted[0], *accepted[1])
        return None
    if outcome == "too_small":
        return run.result(Status.STALLED, f"‖Δq‖ ≤ q_tol = {q_tol:g} with ‖e‖ = {run.norm:.3g}")
    return run.result(
        Status.STALLED, f"no Armijo step decreases ‖e‖ = {run.norm:.3g} (slope {slope:.3g})"
    )


def armijo_backtrack(
    merit_at: Callable[[float], float],
    F: float,
    slope: float,
    alpha: float = 1.0,
    *,
    trials: int = ARMIJO_MAX_TRIALS,
    min_alpha: float = 0.0,
) -> tuple[float | None, str]:
    r"""Backtracking line search: the first ``λ = α₀ ρᵏ`` (``k < trials``) with
    ``F(λ) ≤ F + c λ ∇Fᵀd`` (Nocedal & Wright Alg. 3.1; ``c`` =
    :data:`ARMIJO_SUFFICIENT_DECREASE`, ``ρ`` = :data:`ARMIJO_SHRINK`).

    ``merit_at(λ)`` is the merit at ``q + λ d`` (NaN or inf for a trial that cannot be
    used: it is rejected); ``slope`` is ``∇Fᵀd < 0``. Returns ``(λ, "accepted")``,
    ``(None, "too_small")`` when ``λ`` fell to ``min_alpha`` or below before a trial was
    accepted (the step is negligible), or ``(None, "exhausted")`` after ``trials``
    rejections. The one Armijo search of redik: the root finders here and the
    ``"transpose"``/``"hybrid"`` methods of :func:`redik.solve_pose` use it.
    """
    for _ in range(trials):
        if alpha <= min_alpha:
            return None, "too_small"
        if merit_at(alpha) <= F + ARMIJO_SUFFICIENT_DECREASE * alpha * slope:
            return alpha, "accepted"
        alpha *= ARMIJO_SHRINK
    return None, "exhausted"


def _move(run: _Run, q: np.ndarray) -> IKResult | None:
    """Accept ``q`` as the next iterate, or stop with ``"diverged"`` (and no move)."""
    evaluated = run.evaluate(q)
    if evaluated is None:
        return run.result(Status.DIVERGED, f"the {run.method} step produced NaN or inf")
    if run.blown_up(q, evaluated[2]):
        return run.result(
            Status.DIVERGED,
            f"the {run.method} step blew up (‖q‖_∞ = {np.max(np.abs(q)):.3g}, ‖e‖ = "
            f"{evaluated[2]:.3g}; max_growth = {run.options.max_growth:g} × the start)",
        )
    run.accept(q, *evaluated)
    return None


def _newton_step(J: np.ndarray, e: np.ndarray) -> np.ndarray:
    """``J⁻¹ e`` for a square invertible ``J``, else the least-norm least-squares ``J⁺ e``."""
    if J.shape[0] == J.shape[1]:
        try:
            return np.linalg.solve(J, e)
        except np.linalg.LinAlgError:
            pass  # exactly singular: fall through to the pseudo-inverse
    return np.linalg.pinv(J) @ e


def _gain(gain: np.ndarray | float | None, r: int) -> np.ndarray:
    """``K`` as an ``r × r`` symmetric positive-definite matrix."""
    if gain is None:
        return np.eye(r)
    K = real_array(gain, "gain")
    if K.ndim == 0:
        K = K * np.eye(r)
    elif K.ndim == 1 and K.shape == (r,):
        K = np.diag(K)
    if K.shape != (r, r) or not np.all(np.isfinite(K)):
        raise InvalidInput(
            f"gain must be a positive number, a length-{r} vector or an {r} × {r} matrix, "
            f"got shape {K.shape}"
        )
    if not np.allclose(K, K.T, rtol=1e-12, atol=1e-12 * max(1.0, float(np.abs(K).max()))):
        raise InvalidInput("gain K must be symmetric (it weighs ½ eᵀKe)")
    eigenvalues = np.linalg.eigvalsh(K)
    if not eigenvalues[0] > 0.0:
        raise InvalidInput(
            f"gain K must be positive definite, its smallest eigenvalue is {eigenvalues[0]:.3g}"
        )
    return K


def _finite_vector(x: np.ndarray, name: str) -> np.ndarray:
    x = np.atleast_1d(real_array(x, name))
    if x.ndim != 1:
        raise InvalidInput(f"{name} must be a vector, got shape {x.shape}")
    x = as_vector(x, x.size, name)
    if np.abs(x).max(initial=0.0) > _MAX_MAGNITUDE:
        raise InvalidInput(f"{name} must be within ±{_MAX_MAGNITUDE:g} (‖e‖² overflows): {x}")
    return x


def _step_option(step: object, name: str) -> float | str:
    """A step: ``"armijo"`` or a finite ``λ > 0``."""
    if isinstance(step, str) and step == "armijo":
        return step
    if isinstance(step, str):
        raise InvalidInput(f"{name} must be a positive number or 'armijo', got {step!r}")
    return positive(step, name)
