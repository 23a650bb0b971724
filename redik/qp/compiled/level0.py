r"""The box of a step and level 0's minimiser when no constraint binds it, compiled.

**The box.** A :class:`~redik.limits.ConfigurationLimit` bounds the step by
:math:`q_{min} - q \le Δq \le q_{max} - q` on the hinge and slide coordinates, a
:class:`~redik.limits.VelocityLimit` by :math:`|Δq_i| \le v_{max,i}\, dt`; their intersection
is the box every level is solved in (several limits of a kind are intersected when the plan is
built: :math:`\max(l_1 - q, l_2 - q) = \max(l_1, l_2) - q` exactly, rounding being
monotone).

**Level 0 without a binding constraint.** The unconstrained minimiser satisfies the KKT
conditions with zero multipliers whenever it lies in the box and meets the rows, and is then
*the* minimiser of the strictly convex level (Nocedal & Wright, *Numerical Optimization*,
§16.1): for a weighted level :math:`x = -H^{-1}c` (a Cholesky solve); for a least-squares
level, :math:`H = A^\top A + εI`, the push-through form
:math:`x = A^\top (AA^\top + εI)^{-1} b`, as well conditioned as :math:`AA^\top`
(:func:`redik.qp.hierarchy.least_squares_minimiser`). Only when a bound or row binds does the
step need a QP (:mod:`redik.qp.compiled.box_qp`, or daqp with rows).
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.compiled import COMPILE
from redik.qp.compiled.linalg import (
    cholesky,
    least_squares_point,
    rows_hold,
    substitute,
    within_box,
)

SOLVED = 0
""":func:`level0_point`: ``x`` is level 0's minimiser."""

BINDS = 1
""":func:`level0_point`: a bound or row binds; ``x`` is the unconstrained minimiser."""

EMPTY_BOX = 2
""":func:`level0_point`: a lower bound exceeds its upper one."""

NOT_DEFINITE = 3
""":func:`level0_point`: level 0's Hessian is not positive definite."""


@numba.njit(**COMPILE)
def box_bounds(
    q: NDArray[np.float64],
    scalar_q: NDArray[np.int64],
    box: NDArray[np.float64],
    position: bool,
    velocity: bool,
    dt: float,
    max_step: float,
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
) -> bool:
    """Write the step's box; return False when it is empty (a lower bound above its upper).

    Args:
        q: The configuration (nq,).
        scalar_q: Per tangent coordinate, its index in ``q`` (hinge, slide), −1 on ball and
            free joints (no position bound).
        box: ``(q_min, q_max, v_max)`` (3 × n).
        position: A configuration limit is present.
        velocity: A velocity limit is present.
        dt: The step's duration (s), with a velocity limit.
        max_step: A trust region ``|Δq_i| ≤ max_step`` (inf: none).
        lb: Written (n,).
        ub: Written (n,).
    """
    empty = False
    for i in range(lb.shape[0]):
        lower, upper = -np.inf, np.inf
        if position:
            value = q[scalar_q[i]] if scalar_q[i] >= 0 else 0.0
            lower = box[0, i] - value
            upper = box[1, i] - value
        if velocity:
            limit = box[2, i] * dt
            lower = max(lower, -limit)
            upper = min(upper, limit)
        lower = max(lower, -max_step)
        upper = min(upper, max_step)
        lb[i] = lower
        ub[i] = upper
        empty = empty or lower > upper
    return not empty


@numba.njit(**COMPILE)
def level0_point(
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    A: NDArray[np.float64],
    b: NDArray[np.float64],
    least_squares: bool,
    damping: float,
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
    C: NDArray[np.float64],
    u: NDArray[np.float64],
    m: int,
    x: NDArray[np.float64],
    L: NDArray[np.float64],
) -> int:
    """Write level 0's unconstrained minimiser into ``x`` and say whether it is the solution.

    Args:
        H: Level 0's Hessian (n × n), regularised.
        c: Its linear term (n,).
        A: Its rows (rows × n), for a least-squares level.
        b: Their right-hand side.
        least_squares: ``H = AᵀA + damping·I`` (module docstring); wide ``A`` only.
        damping: ``ε``.
        lb: Lower bounds of the step (n,).
        ub: Upper bounds (n,).
        C: Hard rows (≥ m × n).
        u: Their upper bounds.
        m: How many rows of ``C`` count.
        x: Written (n,).
        L: Written (n × n) on a weighted level: the Cholesky factor of ``H`` (``H = LLᵀ``).

    Returns:
        :data:`SOLVED`, :data:`BINDS` or :data:`NOT_DEFINITE`.
    """
    if least_squares:
        defined = least_squares_point(A, b, damping, x)
    else:
        defined = cholesky(H, np.arange(x.shape[0]), x.shape[0], L)
        if defined:
            x[:] = -c
            substitute(L, x.shape[0], x)
    if not defined:
        return NOT_DEFINITE
    if within_box(x, lb, ub) and rows_hold(C, u, m, x):
        return SOLVED
    return BINDS
