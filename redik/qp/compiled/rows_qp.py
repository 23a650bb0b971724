r"""A compiled dual active-set method for level 0's QP with hard rows and an inactive box.

.. math::

    \min_x \tfrac12 x^\top H x + c^\top x \quad\text{s.t.}\quad C x \le u ,
    \qquad H \succ 0 ,

solved by the dual method of Goldfarb & Idnani (*A numerically stable dual method for
solving strictly convex quadratic programs*, Math. Programming 27, 1983), which DAQP
implements too (Arnström, Bemporad & Axehill, IEEE TAC 2022): start from the unconstrained
minimiser :math:`x = -H^{-1}c` with an empty active set :math:`\mathcal A`; while a row
:math:`j` is violated by more than the primal tolerance, move along

.. math::

    z = H^{-1}C_j^\top - H^{-1}C_{\mathcal A}^\top r, \qquad
    r = (C_{\mathcal A} H^{-1} C_{\mathcal A}^\top)^{-1} C_{\mathcal A} H^{-1} C_j^\top ,

(the primal direction that keeps the active rows and moves row :math:`j`; the multipliers
move by :math:`-r`), as far as the full step :math:`t_f = (C_j x - u_j) / C_j z` that makes
row :math:`j` active, or less, :math:`t_p = \min_{r_i > 0} λ_i / r_i`, when an active row's
multiplier reaches zero first: that row leaves :math:`\mathcal A` and the step repeats for
:math:`j`. Each step keeps every multiplier non-negative and raises the dual objective, so the
method ends, after finitely many steps, at the KKT point of the rows — *the* minimiser, ``H``
being positive definite (Goldfarb & Idnani, Theorem 1). The active rows are few (the collision
rows of a step), so :math:`C_{\mathcal A} H^{-1} C_{\mathcal A}^\top` is factored afresh at
each step instead of updated.

The box is not among the constraints: the answer is the step's only when it lies in the box
(then the box's multipliers are zero and the KKT conditions of the whole QP hold); else the
caller hands the QP to DAQP.
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.compiled import COMPILE
from redik.qp.compiled.linalg import cholesky, substitute, within_box

_DEPENDENT_TOL = 1e-12
"""Row ``j`` counts as a combination of the active rows when ``C_j z`` (what of
``C_j H⁻¹ C_jᵀ`` the active rows leave) is below this fraction of it: it cannot be made active
without them, and an active row must leave instead."""


@numba.njit(**COMPILE)
def _most_violated(
    C: NDArray[np.float64],
    u: NDArray[np.float64],
    m: int,
    x: NDArray[np.float64],
    active: NDArray[np.bool_],
    tolerance: float,
) -> int:
    """The inactive row most violated by more than ``tolerance``, or −1 (a NaN: row 0)."""
    worst, row = tolerance, -1
    for i in range(m):
        if active[i]:
            continue
        violation = C[i] @ x - u[i]
        if violation > worst or violation != violation:
            worst, row = violation, i
    return row


@numba.njit(**COMPILE)
def _direction(
    C: NDArray[np.float64],
    Y: NDArray[np.float64],
    rows: NDArray[np.int64],
    k: int,
    j: int,
    S: NDArray[np.float64],
    r: NDArray[np.float64],
    z: NDArray[np.float64],
) -> bool:
    """Write ``r`` and ``z`` (module docstring) for adding row ``j`` to the ``k`` active ``rows``.

    Returns:
        False when the active rows' ``C H⁻¹ Cᵀ`` is not positive definite.
    """
    for a in range(k):
        for b in range(a + 1):
            S[a, b] = C[rows[a]] @ Y[rows[b]]
        r[a] = C[rows[a]] @ Y[j]
    if k and not cholesky(S, np.arange(k), k, S):
        return False
    substitute(S, k, r)
    z[:] = Y[j]
    for a in range(k):
        z -= r[a] * Y[rows[a]]
    return True


@numba.njit(**COMPILE)
def _partial_step(
    multipliers: NDArray[np.float64], rows: NDArray[np.int64], k: int, r: NDArray[np.float64]
) -> tuple[float, int]:
    """``(t_p, a)``: the step at which active row ``rows[a]``'s multiplier reaches zero first."""
    step, leaving = np.inf, -1
    for a in range(k):
        if r[a] > 0.0 and multipliers[rows[a]] / r[a] < step:
            step, leaving = multipliers[rows[a]] / r[a], a
    return step, leaving


@numba.njit(**COMPILE)
def _add_row(
    C: NDArray[np.float64],
    u: NDArray[np.float64],
    Y: NDArray[np.float64],
    j: int,
    x: NDArray[np.float64],
    multipliers: NDArray[np.float64],
    active: NDArray[np.bool_],
    rows: NDArray[np.int64],
    k: int,
    max_steps: int,
    S: NDArray[np.float64],
    r: NDArray[np.float64],
    z: NDArray[np.float64],
) -> int:
    """Make row ``j`` active (module docstring); return the new number of active rows, or −1.

    ``S`` (≥ m × m), ``r`` (≥ m) and ``z`` (n) are the caller's scratch.
    """
    for _ in range(max_steps):
        if not _direction(C, Y, rows, k, j, S, r, z):
            return -1
        curvature = C[j] @ z  # the Schur complement of the active rows in C H⁻¹ Cᵀ
        full = np.inf
        if curvature > _DEPENDENT_TOL * (C[j] @ Y[j]) and k < x.shape[0]:
            full = (C[j] @ x - u[j]) / curvature
        partial, leaving = _partial_step(multipliers, rows, k, r)
        step = min(full, partial)
        if step == np.inf:
            return -1  # the rows cannot all hold
        x -= step * z
        for a in range(k):
            multipliers[rows[a]] -= step * r[a]
        multipliers[j] += step
        if full <= partial:
            active[j], rows[k] = True, j
            return k + 1
        multipliers[rows[leaving]], active[rows[leaving]] = 0.0, False
        rows[leaving : k - 1] = rows[leaving + 1 : k].copy()
        k -= 1
    return -1


@numba.njit(**COMPILE)
def rows_qp(
    L: NDArray[np.float64],
    c: NDArray[np.float64],
    C: NDArray[np.float64],
    u: NDArray[np.float64],
    m: int,
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
    tolerance: float,
    x: NDArray[np.float64],
) -> int:
    """Solve the QP of the rows by the dual method (module docstring), the box checked after.

    Args:
        L: The Cholesky factor of the Hessian, ``H = LLᵀ`` (n × n, lower triangle read).
        c: The linear term (n,).
        C: The rows (≥ m × n).
        u: Their upper bounds.
        m: How many rows count.
        lb: The box's lower bounds (n,), checked at the answer.
        ub: Its upper bounds (n,).
        tolerance: A row counts as violated above ``u_i + tolerance`` (DAQP's ``primal_tol``).
        x: Written: the minimiser.

    Returns:
        The number of active rows at the minimiser, or −1 when the method cannot answer: the
        active rows' ``C H⁻¹ Cᵀ`` not positive definite, rows that cannot all hold, a box bound
        broken (``x`` is then undefined).
    """
    n = x.shape[0]
    x[:] = -c
    substitute(L, n, x)
    Y = np.empty((m, n))
    for i in range(m):
        Y[i] = C[i]
        substitute(L, n, Y[i])
    active, rows = np.zeros(m, dtype=np.bool_), np.empty(m, dtype=np.int64)
    multipliers = np.zeros(m)
    S, r, z = np.empty((m, m)), np.empty(m), np.empty(n)
    k = 0
    for _ in range(2 * m + 2):
        j = _most_violated(C, u, m, x, active, tolerance)
        if j < 0:
            held = _most_violated(C, u, m, x, np.zeros(m, dtype=np.bool_), tolerance) < 0
            return k if held and within_box(x, lb, ub) else -1
        k = _add_row(C[:m], u, Y, j, x, multipliers, active, rows, k, 2 * m + 2, S, r, z)
        if k < 0:
            return -1
    return -1
