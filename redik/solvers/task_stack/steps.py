r"""The three steps of an attempt: reach, polish and optimise (and the restoration they share).

Each takes the current :class:`Point` and returns the next one, or None when no fraction of
its step is acceptable. The problem answers the steps (:class:`redik.Problem`); these
functions decide which fraction of a step to take.

- :func:`reach_step`: the lexicographic QP step with Levenberg–Marquardt damping on level 0,
  backtracked until ``‖W e‖²`` falls below a reference merit: the point's own in a monotone
  descent, the largest of the recent ones in a non-monotone escape (Grippo, Lampariello &
  Lucidi, SIAM J. Numer. Anal. 1986). Simple decrease, as Levenberg–Marquardt accepts a step
  (Nocedal & Wright §10.3): a failed search raises the damping, which shortens and turns the
  next step towards steepest descent.
- :func:`polish_step`: the undamped Gauss–Newton step of level 0's targets by the truncated
  pseudo-inverse, joints clamped at their bounds (:func:`clamped_least_squares`), backtracked
  on ``‖W e‖``. Damping shrinks a step along a weak singular direction :math:`σ` by
  :math:`σ^2/(σ^2 + λ)`; backtracking keeps the direction and only shortens the step.
- :func:`optimise_step`: from a point on level 0, the QP step with level 1's curvature term,
  each fraction brought back onto level 0 (:func:`restore`, the second-order correction of
  sequential quadratic programming, Nocedal & Wright §18.3: a merit that insists on
  feasibility rejects tangent steps, the Maratos effect) and accepted when the lower levels
  decrease lexicographically (:func:`compare_lower`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from redik.qp.problem import Problem
from redik.solvers.task_stack.options import SolveOptions

FRACTIONS = tuple(0.5**k for k in range(7))
"""Step fractions a line search tries, 1 down to 1/64."""

RCOND = 1e-12
"""Relative singular-value cut-off of the polish step's pseudo-inverse."""

ROUND_OFF = 1e-14
"""Relative change of a lower level's value that :func:`compare_lower` calls a tie."""

RESTORE_STEPS = 4
"""Polish steps :func:`restore` takes at most to bring a point back onto level 0."""

RESTORED = 1e-14
"""Level-0 error ``‖W e‖`` at which :func:`restore` stops: a lower level's value then moves by
its multipliers times this, about the round-off :data:`ROUND_OFF` of the value."""


@dataclasses.dataclass
class Point:
    """An iterate and what is known at it.

    Attributes:
        q: The configuration.
        converged: Level 0's targets are met (:class:`redik.qp.problem.Measurement`).
        error: ``‖W e‖`` of level 0's targets.
        position_error: The worst frame position error (m), or None.
        rotation_error: The worst frame rotation error (rad), or None.
        admitted: The limits linearised elsewhere hold here.
        values: Each optimised level's value, once needed.
        stationarity: Each optimised level's projected gradient, once needed.
    """

    q: np.ndarray
    converged: bool
    error: float
    position_error: float | None
    rotation_error: float | None
    admitted: bool
    values: list[float] | None = None
    stationarity: list[float] | None = None

    @property
    def merit(self) -> float:
        """``‖W e‖²``, what the reach and polish steps lower."""
        return self.error * self.error


def measure(problem: Problem, q: np.ndarray, options: SolveOptions) -> Point:
    """The :class:`Point` at ``q`` (forward kinematics and level 0's errors)."""
    m = problem.measure(q, options.pos_tol, options.rot_tol)
    return Point(q, m.converged, m.error, m.position_error, m.rotation_error, m.admitted)


def values(problem: Problem, point: Point) -> list[float]:
    """The optimised levels' values at ``point`` (cached on it)."""
    if point.values is None:
        point.values = problem.objective_values(point.q)
    return point.values


def reach_step(
    problem: Problem, point: Point, mu: float, reference: float, options: SolveOptions
) -> tuple[Point | None, float]:
    """The damped QP step from ``point``, at the largest fraction that lowers the merit.

    Args:
        problem: The problem.
        point: The current point (level 0 not met).
        mu: The Levenberg–Marquardt scale: level 0's Hessian gets ``μ‖W e‖²``.
        reference: The merit to pass: the point's own (a monotone descent) or the largest
            recent one (an escape).
        options: The solve's options.

    Returns:
        ``(trial, fraction)``, or ``(None, 0)`` when no fraction passes.
    """
    q = point.q
    dq = problem.static_step(q, options.dt, lm_damping=mu * point.merit, max_step=options.max_step)
    for alpha in FRACTIONS:
        trial = measure(problem, problem.integrate(q, alpha * dq), options)
        if trial.admitted and (trial.converged or trial.merit < reference):
            return trial, alpha
    return None, 0.0


def polish_step(problem: Problem, point: Point, options: SolveOptions) -> Point | None:
    """The undamped Gauss–Newton step of level 0's targets, at the largest fraction that helps.

    The fraction must lower ``‖W e‖`` (or meet level 0).

    Args:
        problem: The problem.
        point: The current point.
        options: The solve's options.

    Returns:
        The trial point, or None (no targets, or no fraction lowers the error).
    """
    q = point.q
    A, b = problem.target_rows(q)
    if A.shape[0] == 0:
        return None
    dq = clamped_least_squares(A, b, *problem.step_bounds(q, options.dt))
    for alpha in FRACTIONS:
        trial = measure(problem, problem.integrate(q, alpha * dq), options)
        if trial.admitted and (trial.converged or trial.error < point.error):
            return trial
    return None


def restore(problem: Problem, point: Point, options: SolveOptions) -> Point:
    """``point`` brought onto level 0 by polish steps, as closely as they can.

    At most :data:`RESTORE_STEPS`, each taken only when it lowers ``‖W e‖``, until
    :data:`RESTORED`. The lower levels' values are then compared on level 0 itself, not at
    level-0 errors that differ by a tolerance: each such difference shifts a lower level's
    value by its multipliers times it, which can exceed the decrease being judged.
    """
    for _ in range(RESTORE_STEPS):
        if point.error <= RESTORED:
            break
        trial = polish_step(problem, point, options)
        if trial is None:
            break
        point = trial
    return point


def optimise_step(
    problem: Problem, point: Point, stationarity: list[float], options: SolveOptions
) -> Point | None:
    """From ``point`` on level 0, the restored step that lowers the lower levels.

    First the QP step (with level 1's curvature term); when no fraction of it is accepted —
    near a stationary point the QP's own round-off on the levels above can outweigh the
    decrease left to find — the projected steepest-descent step of the first level that is
    not stationary (:meth:`redik.Problem.descent_steps`).

    Args:
        problem: The problem.
        point: The current point (level 0 met).
        stationarity: The optimised levels' projected gradients at ``point``.
        options: The solve's options.

    Returns:
        The accepted point, or None.
    """
    dq = problem.static_step(point.q, options.dt, second_order=True, max_step=options.max_step)
    trial = _lower_along(problem, point, dq, stationarity, options)
    if trial is not None:
        return trial
    tol = options.stationarity_tol or 0.0
    level = next(k for k, value in enumerate(stationarity) if value > tol)
    cauchy = problem.descent_steps(point.q, options.dt)[level]
    return _lower_along(problem, point, cauchy, stationarity, options)


def _lower_along(
    problem: Problem, point: Point, dq: np.ndarray, stationarity: list[float], options
) -> Point | None:
    """The largest fraction of ``dq`` that lowers the optimised levels, restored.

    The largest fraction of ``dq`` whose restored point lowers the optimised levels
    lexicographically (:func:`compare_lower`); on a tie within round-off, the largest that lowers
    the projected gradient.
    """
    before = values(problem, point)
    for alpha in FRACTIONS:
        trial = measure(problem, problem.integrate(point.q, alpha * dq), options)
        trial = restore(problem, trial, options)
        if not (trial.converged and trial.admitted):
            continue
        verdict = compare_lower(values(problem, trial), before, stationarity, options)
        if verdict < 0:
            return trial
        if verdict == 0:
            trial.stationarity = problem.stationarity(trial.q, options.dt)
            if max(trial.stationarity) < max(stationarity):
                return trial
    return None


def compare_lower(
    new: list[float], old: list[float], stationarity: list[float], options: SolveOptions
) -> int:
    """−1 when ``new`` is lexicographically lower than ``old``, 0 for a tie, 1 otherwise.

    The levels are compared in order; the first that is not stationary (its projected
    gradient above ``stationarity_tol``) decides, and must fall. A stationary level above it
    may rise, by no more than that level falls: at a stationary point both changes are of
    second order — the rise is the curvature of the stationary level's optimal set, which
    the restoration (onto level 0 only) does not correct — so the iterates still converge
    to the lexicographic optimum. Changes within :data:`ROUND_OFF` of a value are ties: near
    the optimum a Newton step lowers the value by the square of a gradient that
    ``stationarity_tol`` may put below the value's precision, and the projected gradient
    then decides (:func:`optimise_step`).
    """
    tol = options.stationarity_tol or 0.0
    rise = 0.0
    for level, (a, b) in enumerate(zip(new, old, strict=True)):
        slack = ROUND_OFF * max(1.0, abs(b))
        if stationarity[level] > tol:
            if a < b - slack:
                return -1 if rise <= b - a else 1
            return 0 if a <= b + slack and rise == 0.0 else 1
        rise = max(rise, a - b - slack)
    return 0 if rise == 0.0 else 1


def clamped_least_squares(
    A: np.ndarray, b: np.ndarray, lb: np.ndarray, ub: np.ndarray
) -> np.ndarray:
    r"""The minimum-norm :math:`x` of :math:`\min ‖Ax − b‖` with :math:`lb ≤ x ≤ ub`, by clamping.

    Solve on the free columns by the pseudo-inverse (singular values below
    :data:`RCOND` · σ_max dropped), fix every column that leaves its bound at the bound, and
    solve again for the rest of ``b`` (Chan & Dubey, *A weighted least-norm solution based
    scheme for avoiding joint limits for redundant joint manipulators*, IEEE T-RA 1995).
    ``lb ≤ 0 ≤ ub`` is assumed (``x = 0`` is feasible), so it ends within ``n`` passes.

    Args:
        A: The rows (m × n).
        b: The right-hand side (m,).
        lb: Lower bounds (n,), ``≤ 0``.
        ub: Upper bounds (n,), ``≥ 0``.

    Returns:
        ``x`` (n,).
    """
    n = A.shape[1]
    free = np.ones(n, dtype=bool)
    x = np.zeros(n)
    for _ in range(n):
        residual = b - A[:, ~free] @ x[~free]
        x[free] = pseudo_inverse_solve(A[:, free], residual)
        low, high = free & (x < lb), free & (x > ub)
        if not (low.any() or high.any()):
            return x
        x[low], x[high] = lb[low], ub[high]
        free &= ~(low | high)
        if not free.any():
            return x
    return np.clip(x, lb, ub)


def pseudo_inverse_solve(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``A⁺ b`` by the SVD, singular values below :data:`RCOND` · σ_max dropped."""
    if A.size == 0:
        return np.zeros(A.shape[1])
    U, s, Vt = np.linalg.svd(A, full_matrices=False)
    keep = s > RCOND * s[0] if s.size and s[0] > 0.0 else np.zeros_like(s, dtype=bool)
    return Vt[keep].T @ ((U[:, keep].T @ b) / s[keep])


def error_gradient(problem: Problem, q: np.ndarray, options: SolveOptions) -> float:
    """``‖P(Aᵀb)‖`` at ``q``: the descent direction of ``½‖W e‖²`` on the face of the box.

    Components that push a joint into an ε-active bound (:data:`redik.qp.problem.ACTIVE_TOL`)
    are removed; ``inf`` without targets.
    """
    from redik.qp.problem import ACTIVE_TOL

    A, b = problem.target_rows(q)
    if A.shape[0] == 0:
        return np.inf
    d = A.T @ b
    lb, ub = problem.step_bounds(q, options.dt)
    d[(lb >= -ACTIVE_TOL) & (d < 0.0)] = 0.0
    d[(ub <= ACTIVE_TOL) & (d > 0.0)] = 0.0
    return float(np.linalg.norm(d))
