r"""Small dense linear algebra of the compiled step: Cholesky solves and feasibility tests.

IK-sized systems (n ≤ a few dozen) are solved by the textbook algorithms in plain loops,
which at these sizes beat a LAPACK call through its Python wrapper many times over: the
Cholesky factorisation :math:`H = LL^\top` column by column, then two triangular solves
(Golub & Van Loan, *Matrix Computations*, 4th ed., Algorithm 4.2.1 and §3.1).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.compiled import COMPILE


@numba.njit(**COMPILE)
def cholesky(
    H: NDArray[np.float64],
    index: NDArray[np.int64],
    k: int,
    L: NDArray[np.float64],
) -> bool:
    """Factor the principal block ``H[index[:k]][:, index[:k]] = L Lᵀ`` into ``L[:k, :k]``.

    Args:
        H: A symmetric matrix (its lower triangle is read).
        index: The rows and columns of the block.
        k: The block's size.
        L: Written (at least k × k): the lower-triangular factor.

    Returns:
        False when the block is not numerically positive definite (a pivot ``≤ 0`` or NaN).
    """
    for a in range(k):
        i = index[a]
        pivot = H[i, i]
        for t in range(a):
            pivot -= L[a, t] * L[a, t]
        if not pivot > 0.0:
            return False
        d = math.sqrt(pivot)
        L[a, a] = d
        for b in range(a + 1, k):
            total = H[index[b], i]
            for t in range(a):
                total -= L[b, t] * L[a, t]
            L[b, a] = total / d
    return True


@numba.njit(**COMPILE)
def substitute(
    L: NDArray[np.float64],
    k: int,
    y: NDArray[np.float64],
) -> None:
    """Solve ``L Lᵀ y = y`` in place on the first ``k`` entries (forward, then backward)."""
    for i in range(k):
        total = y[i]
        for t in range(i):
            total -= L[i, t] * y[t]
        y[i] = total / L[i, i]
    for i in range(k - 1, -1, -1):
        total = y[i]
        for t in range(i + 1, k):
            total -= L[t, i] * y[t]
        y[i] = total / L[i, i]


@numba.njit(**COMPILE)
def cholesky_solve(
    H: NDArray[np.float64],
    rhs: NDArray[np.float64],
    x: NDArray[np.float64],
) -> bool:
    """Write ``x = H⁻¹ rhs`` for a symmetric positive definite ``H``.

    Args:
        H: The matrix (n × n; its lower triangle is read).
        rhs: The right-hand side (n,); may be ``x`` itself.
        x: Written (n,).

    Returns:
        False (``x`` undefined) when ``H`` is not numerically positive definite.
    """
    n = x.shape[0]
    L = np.empty((n, n))
    if not cholesky(H, np.arange(n), n, L):
        return False
    for i in range(n):
        x[i] = rhs[i]
    substitute(L, n, x)
    return True


@numba.njit(**COMPILE)
def newton_point(
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    x: NDArray[np.float64],
) -> bool:
    """Write the unconstrained minimiser ``x = −H⁻¹c`` of ``½xᵀHx + cᵀx``.

    Args:
        H: The Hessian (n × n), symmetric positive definite.
        c: The linear term (n,).
        x: Written (n,).

    Returns:
        False when ``H`` is not positive definite.
    """
    for i in range(c.shape[0]):
        x[i] = -c[i]
    return cholesky_solve(H, x, x)


@numba.njit(**COMPILE)
def least_squares_point(
    A: NDArray[np.float64],
    b: NDArray[np.float64],
    shift: float,
    x: NDArray[np.float64],
) -> bool:
    r"""Write the minimiser of :math:`\tfrac12\|Ax - b\|^2 + \tfrac{s}{2}\|x\|^2` for a wide ``A``.

    The push-through identity :math:`x = A^\top (AA^\top + sI)^{-1} b`: an m × m system whose
    condition is that of :math:`AA^\top`, not the :math:`σ_{max}^2 / s` of
    :math:`A^\top A + sI` (:func:`redik.qp.hierarchy.least_squares_minimiser`).

    Args:
        A: The rows (m × n, m < n).
        b: The right-hand side (m,).
        shift: ``s > 0``.
        x: Written (n,).

    Returns:
        False when ``AAᵀ + sI`` is not positive definite.
    """
    m, n = A.shape
    gram = np.empty((m, m))
    for i in range(m):
        for j in range(i + 1):
            total = 0.0
            for k in range(n):
                total += A[i, k] * A[j, k]
            gram[i, j] = total
            gram[j, i] = total
        gram[i, i] += shift
    y = np.empty(m)
    if not cholesky_solve(gram, b, y):
        return False
    for k in range(n):
        total = 0.0
        for i in range(m):
            total += A[i, k] * y[i]
        x[k] = total
    return True


@numba.njit(**COMPILE)
def within_box(
    x: NDArray[np.float64],
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
) -> bool:
    """Whether ``lb ≤ x ≤ ub`` holds exactly (a NaN fails)."""
    for i in range(x.shape[0]):
        if not (x[i] >= lb[i] and x[i] <= ub[i]):
            return False
    return True


@numba.njit(**COMPILE)
def rows_hold(
    C: NDArray[np.float64],
    u: NDArray[np.float64],
    m: int,
    x: NDArray[np.float64],
) -> bool:
    """Whether the first ``m`` rows ``C x ≤ u`` hold exactly (a NaN fails)."""
    for r in range(m):
        total = 0.0
        for j in range(x.shape[0]):
            total += C[r, j] * x[j]
        if not total <= u[r]:
            return False
    return True


@numba.njit(**COMPILE)
def clip_into(
    x: NDArray[np.float64],
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
) -> None:
    """Clip ``x`` into ``[lb, ub]`` in place."""
    for i in range(x.shape[0]):
        x[i] = min(max(x[i], lb[i]), ub[i])
