r"""A compiled primal active-set method for the box-constrained QP of a step.

.. math::

    \min_x \tfrac12 x^\top H x + c^\top x \quad\text{s.t.}\quad l \le x \le u,
    \qquad H \succ 0 .

The primal active-set method of Nocedal & Wright, *Numerical Optimization*, 2nd ed.,
Algorithm 16.3, specialised to bounds (the working set :math:`\mathcal W` is a set of
coordinates held at one of their bounds; Bertsekas, *Projected Newton methods for
optimization problems with simple constraints*, SIAM J. Control Optim. 1982, is the same
idea with projections):

1. Start from the unconstrained minimiser clipped into the box; the clipped coordinates form
   :math:`\mathcal W` (a feasible start, N&W §16.5 "finding an initial feasible point").
2. Minimise over the free coordinates :math:`F` with :math:`\mathcal W` held:
   :math:`H_{FF}\, x^*_F = -(c_F + H_{F\mathcal W} x_{\mathcal W})` (a Cholesky solve).
3. Step from :math:`x` towards :math:`x^*` as far as the box allows (N&W eq. 16.41); a free
   coordinate that reaches a bound joins :math:`\mathcal W` and the iteration repeats.
4. At :math:`x^*` (a full step) the multiplier of a held coordinate is its gradient
   :math:`g_i = (Hx + c)_i`, of the right sign when :math:`g_i \ge 0` at a lower bound and
   :math:`g_i \le 0` at an upper one. If all are, :math:`x` satisfies the KKT conditions
   and, :math:`H` being positive definite, is *the* minimiser (N&W Theorem 16.4); else the
   most violated coordinate is released (N&W Theorem 16.5: the next step moves it into
   the box) and the iteration repeats.

**Termination and exactness.** Each step lowers the objective or grows :math:`\mathcal W`,
so in exact arithmetic the method ends after finitely many iterations (N&W §16.5); the
result is exact up to the round-off of the Cholesky solves, as any active-set method's.
Round-off is guarded twice: a released coordinate whose next minimiser lies on the wrong
side of its bound had a multiplier below round-off, so it is held again and the method
stops (Theorem 16.5 rules that step out in exact arithmetic); and past
``max_iterations`` the method gives up (the caller's QP back-end decides).
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.compiled import COMPILE
from redik.qp.compiled.linalg import cholesky, rows_hold, substitute

FAILED = -1
""":func:`box_qp`: the free block was not positive definite, or the iterations ran out."""

ROWS_VIOLATED = -2
""":func:`box_qp`: the box's minimiser breaks one of the extra rows ``C x ≤ u``."""


@numba.njit(**COMPILE)
def _start(
    x: NDArray[np.float64],
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
    held: NDArray[np.int64],
) -> None:
    """Clip ``x`` into the box; the clipped coordinates are held (−1 lower, +1 upper)."""
    for i in range(x.shape[0]):
        held[i] = 0
        if x[i] <= lb[i]:
            x[i] = lb[i]
            held[i] = -1
        elif x[i] >= ub[i]:
            x[i] = ub[i]
            held[i] = 1


@numba.njit(**COMPILE)
def _free_minimiser(
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    x: NDArray[np.float64],
    held: NDArray[np.int64],
    free: NDArray[np.int64],
    L: NDArray[np.float64],
    rhs: NDArray[np.float64],
    target: NDArray[np.float64],
) -> bool:
    """Write ``target``: ``x`` with its free coordinates minimising, the held ones kept.

    ``free``, ``L`` and ``rhs`` are scratch (n, n × n, n). Returns False when the free block
    ``H_FF`` is not positive definite.
    """
    n = x.shape[0]
    k = 0
    for i in range(n):
        target[i] = x[i]
        if held[i] == 0:
            free[k] = i
            k += 1
    if not cholesky(H, free, k, L):
        return False
    for a in range(k):
        i = free[a]
        total = c[i]
        for j in range(n):
            if held[j] != 0:
                total += H[i, j] * x[j]
        rhs[a] = -total
    substitute(L, k, rhs)
    for a in range(k):
        target[free[a]] = rhs[a]
    return True


@numba.njit(**COMPILE)
def _step(
    x: NDArray[np.float64],
    target: NDArray[np.float64],
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
    held: NDArray[np.int64],
) -> int:
    """Move the free coordinates from ``x`` towards ``target`` as far as the box allows.

    Returns the coordinate that stopped the step (now on its bound and held), or −1 after a
    full step.
    """
    alpha, blocking, side = 1.0, -1, 0
    for i in range(x.shape[0]):
        if held[i] != 0:
            continue
        if target[i] < lb[i]:
            t = (lb[i] - x[i]) / (target[i] - x[i])
            if t < alpha:
                alpha, blocking, side = t, i, -1
        elif target[i] > ub[i]:
            t = (ub[i] - x[i]) / (target[i] - x[i])
            if t < alpha:
                alpha, blocking, side = t, i, 1
    for i in range(x.shape[0]):
        if held[i] == 0:
            x[i] += alpha * (target[i] - x[i])
    if blocking >= 0:
        x[blocking] = lb[blocking] if side < 0 else ub[blocking]
        held[blocking] = side
    return blocking


@numba.njit(**COMPILE)
def _most_violated(
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    x: NDArray[np.float64],
    held: NDArray[np.int64],
) -> int:
    """The held coordinate whose multiplier has the wrong sign by the most, or −1 (optimal)."""
    worst, index = 0.0, -1
    for i in range(x.shape[0]):
        if held[i] == 0:
            continue
        g = c[i]
        for j in range(x.shape[0]):
            g += H[i, j] * x[j]
        violation = g if held[i] < 0 else -g  # a multiplier's sign, at a lower/upper bound
        if violation < worst:
            worst, index = violation, i
    return index


@numba.njit(**COMPILE)
def _wrong_side(
    target: NDArray[np.float64],
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
    released: int,
    side: int,
) -> bool:
    """Whether the minimiser after releasing a coordinate would take it out of its bound."""
    if side < 0:
        return bool(target[released] <= lb[released])
    return bool(target[released] >= ub[released])


@numba.njit(**COMPILE)
def box_qp(
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
    C: NDArray[np.float64],
    u: NDArray[np.float64],
    m: int,
    x: NDArray[np.float64],
    max_iterations: int,
) -> int:
    """Solve the box QP of the module docstring in place, from ``x``.

    Args:
        H: The Hessian (n × n), symmetric positive definite.
        c: The linear term (n,).
        lb: Lower bounds (n,), ``lb ≤ ub``; −inf where there is none.
        ub: Upper bounds (n,); +inf where there is none.
        C: Extra rows (≥ m × n), checked (not imposed) at the end.
        u: Their upper bounds.
        m: How many rows of ``C`` count.
        x: The start, usually the unconstrained minimiser; written with the minimiser.
        max_iterations: The iteration budget.

    Returns:
        The iterations used (≥ 1); :data:`FAILED`; or :data:`ROWS_VIOLATED` when the box's
        minimiser (then in ``x``) breaks a row: the QP with the rows needs a general solver.
    """
    n = x.shape[0]
    held = np.empty(n, dtype=np.int64)
    free = np.empty(n, dtype=np.int64)
    target = np.empty(n)
    rhs = np.empty(n)
    L = np.empty((n, n))
    _start(x, lb, ub, held)
    released, side, iterations = -1, 0, 0
    while True:
        if iterations == max_iterations:
            return FAILED
        iterations += 1
        if not _free_minimiser(H, c, x, held, free, L, rhs, target):
            return FAILED
        if released >= 0 and _wrong_side(target, lb, ub, released, side):
            held[released] = side  # its multiplier was round-off: x is the minimiser
            break
        if _step(x, target, lb, ub, held) >= 0:
            released = -1
            continue
        released = _most_violated(H, c, x, held)
        if released < 0:
            break
        side = held[released]
        held[released] = 0
    for i in range(n):
        x[i] = min(max(x[i], lb[i]), ub[i])  # round-off of the last step
    if not rows_hold(C, u, m, x):
        return ROWS_VIOLATED
    return iterations
