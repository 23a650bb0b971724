r"""Level 1 of a two-level step within level 0's optimal set, compiled.

The null-space parameterisation of :mod:`redik.qp.hierarchy`: with level 0 a least-squares
level of wide rows :math:`A_0` (m × n, m < n) solved at :math:`x_0`, level 1 is solved over
:math:`x = x_0 + Nz` where the columns of :math:`N` are an orthonormal basis of
:math:`\ker A_0`,

.. math::

    \min_z \tfrac12 z^\top N^\top H_1 N z + (N^\top (H_1 x_0 + c_1))^\top z
    \quad\text{s.t.}\quad x_0 + Nz \in \mathcal X \ \text{(relaxed so that } z = 0
    \text{ stays feasible)} .

**The null space** comes from the Householder QR :math:`A_0^\top = QR` in LAPACK's
convention (``dgeqrf``'s reflectors, ``dlarfg``; ``dormqr`` applied to the last
:math:`n - m` columns of the identity): :math:`N = Q_{:, m:}` (Golub & Van Loan, *Matrix
Computations*, 4th ed., §5.2.1–5.2.2), as :func:`redik.qp.hierarchy.row_null_space` computes
it through LAPACK. It is used when :math:`R`'s reciprocal 1-norm condition number exceeds
:math:`10\sqrt{\text{rank\_tol}}`; here that number is exact (:math:`R^{-1}` is formed), and
LAPACK's ``dtrcon`` estimate is never smaller, so whenever this test passes the general
path takes the QR too; otherwise the step goes to the general path (its eigendecomposition).

**One free direction** :math:`v` (a 7-joint arm under a 6-D pose): the closed form
:func:`redik.qp.hierarchy._solve_one_variable`, a row whose gain is below
:data:`~redik.qp.hierarchy.ROW_GAIN_TOL` not blocking. **More:** the reduced level's
unconstrained minimiser (a Cholesky solve) when it meets the relaxed rows, which makes it the
reduced QP's solution; else the reduced QP goes to a back-end.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.compiled import COMPILE
from redik.qp.compiled.linalg import clip_into, newton_point
from redik.qp.hierarchy import ROW_GAIN_TOL

DONE = 0
""":func:`lower_level`: ``x`` is the step."""

REDUCED_QP = 1
""":func:`lower_level`: the reduced QP (``Hz``, ``cz``, ``rows``, ``lower``, ``upper``) needs a
back-end; then ``x + N z``."""

UNSUPPORTED = 2
""":func:`lower_level`: rank-deficient rows or a level without curvature along the free
direction: the general path decides."""


@numba.njit(**COMPILE)
def _reflect(
    qr: NDArray[np.float64],
    tau: NDArray[np.float64],
    k: int,
    start: int,
    columns: int,
) -> None:
    """Apply ``I − τ_k v vᵀ`` (``v = [1; qr[k+1:, k]]``, from row ``k``) to columns of ``qr``."""
    n = qr.shape[0]
    for j in range(start, columns):
        total = qr[k, j]
        for i in range(k + 1, n):
            total += qr[i, k] * qr[i, j]
        total *= tau[k]
        qr[k, j] -= total
        for i in range(k + 1, n):
            qr[i, j] -= total * qr[i, k]


@numba.njit(**COMPILE)
def _householder(
    qr: NDArray[np.float64],
    tau: NDArray[np.float64],
    k: int,
) -> None:
    """LAPACK's ``dlarfg`` on ``qr[k:, k]``: ``β`` into ``qr[k, k]``, ``v`` below it, ``τ_k``."""
    n = qr.shape[0]
    alpha = qr[k, k]
    norm = 0.0
    for i in range(k + 1, n):
        norm += qr[i, k] * qr[i, k]
    norm = math.sqrt(norm)
    if norm == 0.0:
        tau[k] = 0.0
        return
    beta = -math.copysign(math.sqrt(alpha * alpha + norm * norm), alpha)
    tau[k] = (beta - alpha) / beta
    scale = 1.0 / (alpha - beta)
    for i in range(k + 1, n):
        qr[i, k] *= scale
    qr[k, k] = beta


@numba.njit(**COMPILE)
def _reciprocal_condition(
    qr: NDArray[np.float64],
    m: int,
) -> float:
    """``1 / (‖R‖₁ ‖R⁻¹‖₁)`` of the upper triangle ``R = qr[:m, :m]`` (0 when singular)."""
    inverse = np.zeros((m, m))
    norm, inverse_norm = 0.0, 0.0
    for j in range(m):
        if qr[j, j] == 0.0:
            return 0.0
        inverse[j, j] = 1.0 / qr[j, j]
        for i in range(j - 1, -1, -1):
            total = 0.0
            for k in range(i + 1, j + 1):
                total += qr[i, k] * inverse[k, j]
            inverse[i, j] = -total / qr[i, i]
        column, inverse_column = 0.0, 0.0
        for i in range(j + 1):
            column += abs(qr[i, j])
            inverse_column += abs(inverse[i, j])
        norm = max(norm, column)
        inverse_norm = max(inverse_norm, inverse_column)
    return 1.0 / (norm * inverse_norm)


@numba.njit(**COMPILE)
def null_space(
    A: NDArray[np.float64],
    N: NDArray[np.float64],
) -> float:
    """Write an orthonormal basis of ``ker A`` into ``N`` (n × (n − m)); ``A`` wide (m × n).

    Returns:
        The reciprocal 1-norm condition number of ``R`` (module docstring).
    """
    m, n = A.shape
    qr = np.empty((n, m))
    tau = np.empty(m)
    for i in range(n):
        for j in range(m):
            qr[i, j] = A[j, i]
    for k in range(m):
        _householder(qr, tau, k)
        _reflect(qr, tau, k, k + 1, m)
    # N = H_0 ⋯ H_{m−1} [0; I]: the reflectors applied in reverse order.
    for i in range(n):
        for j in range(n - m):
            N[i, j] = 1.0 if i == m + j else 0.0
    for k in range(m - 1, -1, -1):
        for j in range(n - m):
            total = N[k, j]
            for i in range(k + 1, n):
                total += qr[i, k] * N[i, j]
            total *= tau[k]
            N[k, j] -= total
            for i in range(k + 1, n):
                N[i, j] -= total * qr[i, k]
    return _reciprocal_condition(qr, m)


@numba.njit(**COMPILE)
def _gain_and_offset(
    C: NDArray[np.float64],
    r: int,
    N: NDArray[np.float64],
    x: NDArray[np.float64],
) -> tuple[float, float]:
    """``(C_r v, C_r x)`` of row ``r`` along the direction ``v = N[:, 0]``."""
    gain, offset = 0.0, 0.0
    for j in range(x.shape[0]):
        gain += C[r, j] * N[j, 0]
        offset += C[r, j] * x[j]
    return gain, offset


@numba.njit(**COMPILE)
def _pull_back(
    z: float,
    a: float,
    lower: float,
    upper: float,
) -> float:
    """``z`` pulled back to the relaxed row ``min(lower, 0) ≤ a z ≤ max(upper, 0)``."""
    if -ROW_GAIN_TOL <= a <= ROW_GAIN_TOL:
        return z  # moved by round-off only: it cannot block the direction
    if (a > 0.0) == (z > 0.0):
        if a * z > upper:
            return max(upper, 0.0) / a
    elif a * z < lower:
        return min(lower, 0.0) / a
    return z


@numba.njit(**COMPILE)
def one_direction(
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    x: NDArray[np.float64],
    N: NDArray[np.float64],
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
    C: NDArray[np.float64],
    u: NDArray[np.float64],
    m: int,
) -> bool:
    """Move ``x`` along ``v = N[:, 0]`` to level 1's minimiser on the relaxed constraints.

    :func:`redik.qp.hierarchy._solve_one_variable`: ``z = −g/h`` with ``h = vᵀHv``,
    ``g = xᵀHv + cᵀv``, pulled back to the first bound or row it crosses on its way from 0.

    Returns:
        False (``x`` unchanged) when ``h ≤ 0``.
    """
    n = x.shape[0]
    h, g = 0.0, 0.0
    for i in range(n):
        Hv = 0.0
        for k in range(n):
            Hv += H[i, k] * N[k, 0]
        h += N[i, 0] * Hv
        g += x[i] * Hv + c[i] * N[i, 0]
    if not h > 0.0:
        return False
    z = -g / h
    for i in range(n):
        z = _pull_back(z, N[i, 0], lb[i] - x[i], ub[i] - x[i])
    for r in range(m):
        gain, offset = _gain_and_offset(C, r, N, x)
        z = _pull_back(z, gain, -np.inf, u[r] - offset)
    for i in range(n):
        x[i] += z * N[i, 0]
    return True


@numba.njit(**COMPILE)
def reduced_level(
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    x: NDArray[np.float64],
    N: NDArray[np.float64],
    Hz: NDArray[np.float64],
    cz: NDArray[np.float64],
) -> None:
    """Write ``Hz = NᵀHN`` and ``cz = Nᵀ(Hx + c)``: level 1 in the coordinates ``z``."""
    n, r = N.shape
    HN = np.empty((n, r))
    for i in range(n):
        for j in range(r):
            total = 0.0
            for k in range(n):
                total += H[i, k] * N[k, j]
            HN[i, j] = total
    for a in range(r):
        total = 0.0
        for k in range(n):
            total += x[k] * HN[k, a] + c[k] * N[k, a]
        cz[a] = total
        for b in range(a + 1):
            total = 0.0
            for k in range(n):
                total += N[k, a] * HN[k, b]
            Hz[a, b] = total
            Hz[b, a] = total


@numba.njit(**COMPILE)
def _gain(
    a: float,
) -> float:
    """``a``, or 0 within ``ROW_GAIN_TOL`` (round-off cannot block a direction)."""
    return 0.0 if -ROW_GAIN_TOL <= a <= ROW_GAIN_TOL else a


@numba.njit(**COMPILE)
def reduced_rows(
    N: NDArray[np.float64],
    x: NDArray[np.float64],
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
    C: NDArray[np.float64],
    u: NDArray[np.float64],
    m: int,
    rows: NDArray[np.float64],
    lower: NDArray[np.float64],
    upper: NDArray[np.float64],
) -> None:
    """Write the rows ``[N; C N]`` on ``z`` and their bounds, relaxed so that ``z = 0`` holds.

    ``min(lb − x, 0) ≤ N z ≤ max(ub − x, 0)`` and ``C N z ≤ max(u − C x, 0)``, gains within
    ``ROW_GAIN_TOL`` zero (:meth:`redik.qp.hierarchy.Constraints.around`).
    """
    n, r = N.shape
    for i in range(n):
        for j in range(r):
            rows[i, j] = _gain(N[i, j])
        lower[i] = min(lb[i] - x[i], 0.0)
        upper[i] = max(ub[i] - x[i], 0.0)
    for k in range(m):
        Cx = 0.0
        for j in range(n):
            Cx += C[k, j] * x[j]
        for j in range(r):
            total = 0.0
            for i in range(n):
                total += C[k, i] * N[i, j]
            rows[n + k, j] = _gain(total)
        lower[n + k] = -np.inf
        upper[n + k] = max(u[k] - Cx, 0.0)


@numba.njit(**COMPILE)
def _rows_within(
    rows: NDArray[np.float64],
    count: int,
    z: NDArray[np.float64],
    lower: NDArray[np.float64],
    upper: NDArray[np.float64],
) -> bool:
    """Whether ``lower ≤ rows z ≤ upper`` holds exactly on the first ``count`` rows."""
    for i in range(count):
        total = 0.0
        for j in range(z.shape[0]):
            total += rows[i, j] * z[j]
        if not (total >= lower[i] and total <= upper[i]):
            return False
    return True


@numba.njit(**COMPILE)
def add_direction(
    x: NDArray[np.float64],
    N: NDArray[np.float64],
    z: NDArray[np.float64],
) -> None:
    """``x += N z`` in place."""
    for i in range(x.shape[0]):
        total = 0.0
        for j in range(z.shape[0]):
            total += N[i, j] * z[j]
        x[i] += total


@numba.njit(**COMPILE)
def lower_level(
    x: NDArray[np.float64],
    A0: NDArray[np.float64],
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    lb: NDArray[np.float64],
    ub: NDArray[np.float64],
    C: NDArray[np.float64],
    u: NDArray[np.float64],
    m: int,
    rank_tol: float,
    clip: bool,
    N: NDArray[np.float64],
    Hz: NDArray[np.float64],
    cz: NDArray[np.float64],
    rows: NDArray[np.float64],
    lower: NDArray[np.float64],
    upper: NDArray[np.float64],
) -> int:
    """Solve level 1 (``H``, ``c``) within level 0's optimal set at ``x`` (module docstring).

    Args:
        x: Level 0's solution (n,); written with the step.
        A0: Level 0's rows (m₀ × n, m₀ < n).
        H: Level 1's Hessian (n × n), regularised.
        c: Its linear term (n,).
        lb: Lower bounds of the step.
        ub: Upper bounds.
        C: Hard rows (≥ m × n).
        u: Their upper bounds.
        m: How many rows of ``C`` count.
        rank_tol: The null space's relative threshold (module docstring).
        clip: Clip the step into ``[lb, ub]`` when done.
        N: Written: the basis of level 0's null space (n × (n − m₀)).
        Hz: Written with :data:`REDUCED_QP`: the reduced Hessian.
        cz: Written with :data:`REDUCED_QP`: the reduced linear term.
        rows: Written with :data:`REDUCED_QP`: the reduced rows (≥ (n + m) × (n − m₀)).
        lower: Written with :data:`REDUCED_QP`: their lower bounds.
        upper: Written with :data:`REDUCED_QP`: their upper bounds.

    Returns:
        :data:`DONE`, :data:`REDUCED_QP` or :data:`UNSUPPORTED`.
    """
    if not null_space(A0, N) > 10.0 * math.sqrt(rank_tol):
        return UNSUPPORTED
    if N.shape[1] == 1:
        if not one_direction(H, c, x, N, lb, ub, C, u, m):
            return UNSUPPORTED
    else:
        reduced_level(H, c, x, N, Hz, cz)
        reduced_rows(N, x, lb, ub, C, u, m, rows, lower, upper)
        z = np.empty(N.shape[1])
        count = x.shape[0] + m
        if not (newton_point(Hz, cz, z) and _rows_within(rows, count, z, lower, upper)):
            return REDUCED_QP
        add_direction(x, N, z)
    if clip:
        clip_into(x, lb, ub)
    return DONE
