r"""The damped least-squares step, compiled for one target and batched in numpy.

.. math::

    Δq = J_f^\top (J_f J_f^\top + λ I_6)^{-1} e \quad (n ≥ 6), \qquad
    Δq = (J_f^\top J_f + λ I_n)^{-1} J_f^\top e \quad (n < 6),

the two forms of the same minimiser of ``‖J_f Δq − e‖² + λ‖Δq‖²`` (Wampler 1986; Nakamura &
Hanafusa 1986), each solving the smaller of the two symmetric positive-definite systems.
``J_f`` is ``J`` with the columns that are not ``free`` zeroed, so those joints do not move
(the clamping loop of :mod:`redik.solvers.dls.kernel`). The system is factored by Cholesky
``A = L Lᵀ`` in place and solved by forward and back substitution (Golub & Van Loan,
*Matrix Computations*, §4.2).

:func:`damped_solve` is the compiled one-target form the kernel runs; :func:`damped_step`
the same formula over a batch (the batch last), for callers that iterate a whole batch in
numpy; ``tests/test_batch_kernel.py`` holds them equal.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from redik.kinematics.compiled import COMPILE


@numba.njit(**COMPILE)
def gram(J, G):
    """The lower triangle of ``G = J Jᵀ`` (6 × 6) when ``n ≥ 6``, else of ``JᵀJ`` (n × n).

    It changes only when ``J`` does: an iteration whose trial is rejected, and each pass of
    the clamping loop, solve with the same ``G`` (:func:`damped_solve_gram`).
    """
    n = J.shape[1]
    if n >= 6:
        for i in range(6):
            for j in range(i + 1):
                total = 0.0
                for k in range(n):
                    total += J[i, k] * J[j, k]
                G[i, j] = total
    else:
        for i in range(n):
            for j in range(i + 1):
                total = 0.0
                for k in range(6):
                    total += J[k, i] * J[k, j]
                G[i, j] = total


@numba.njit(inline="always", **COMPILE)
def _row_system(J, G, free, e, A, y):
    """``A = J_f J_fᵀ = G − Σ_k j_k j_kᵀ`` over the columns ``k`` not free, ``y = e``."""
    for i in range(6):
        for j in range(i + 1):
            A[i, j] = G[i, j]
        y[i] = e[i]
    for k in range(J.shape[1]):
        if not free[k]:
            for i in range(6):
                for j in range(i + 1):
                    A[i, j] -= J[i, k] * J[j, k]


@numba.njit(inline="always", **COMPILE)
def _column_system(J, G, free, e, A, y):
    """``A = J_fᵀ J_f`` (the rows and columns of ``G = JᵀJ`` not free zeroed), ``y = J_fᵀ e``."""
    n = J.shape[1]
    for i in range(n):
        for j in range(i + 1):
            A[i, j] = G[i, j] if free[i] and free[j] else 0.0
        total = 0.0
        if free[i]:
            for k in range(6):
                total += J[k, i] * e[k]
        y[i] = total


@numba.njit(inline="always", **COMPILE)
def _cholesky(A, damping):
    """``A + λI = L Lᵀ`` in place: ``L`` in the lower triangle, ``1 / L_jj`` on the diagonal."""
    m = A.shape[0]
    for j in range(m):
        diagonal = A[j, j] + damping
        for k in range(j):
            diagonal -= A[j, k] * A[j, k]
        inverse = 1.0 / math.sqrt(diagonal)
        A[j, j] = inverse
        for i in range(j + 1, m):
            entry = A[i, j]
            for k in range(j):
                entry -= A[i, k] * A[j, k]
            A[i, j] = entry * inverse


@numba.njit(inline="always", **COMPILE)
def _substitute(A, y):
    """``y ← (L Lᵀ)⁻¹ y`` from the factor of :func:`_cholesky`: ``L z = y``, then ``Lᵀ x = z``."""
    m = A.shape[0]
    for i in range(m):
        value = y[i]
        for k in range(i):
            value -= A[i, k] * y[k]
        y[i] = value * A[i, i]
    for i in range(m - 1, -1, -1):
        value = y[i]
        for k in range(i + 1, m):
            value -= A[k, i] * y[k]
        y[i] = value * A[i, i]


@numba.njit(inline="always", **COMPILE)
def _row_step(J, free, y, dq):
    """``dq = J_fᵀ y``: the step of the ``n ≥ 6`` form from its solved system."""
    for k in range(J.shape[1]):
        total = 0.0
        if free[k]:
            for i in range(6):
                total += J[i, k] * y[i]
        dq[k] = total


@numba.njit(**COMPILE)
def damped_solve_gram(J, G, free, e, damping, A, y, dq):
    r"""The damped step of :func:`damped_solve` from the Gram matrix ``G`` of ``J`` (:func:`gram`).

    ``A`` (m × m) and ``y`` (m) are work buffers, ``m = min(n, 6)``; ``dq`` receives the step.
    """
    if J.shape[1] >= 6:
        _row_system(J, G, free, e, A, y)
    else:
        _column_system(J, G, free, e, A, y)
    _cholesky(A, damping)
    _substitute(A, y)
    if J.shape[1] >= 6:
        _row_step(J, free, y, dq)
    else:
        dq[:] = y


@numba.njit(**COMPILE)
def damped_solve(J, free, e, damping, A, y, dq):
    r"""``dq = J_fᵀ (J_f J_fᵀ + λI)⁻¹ e`` (``n ≥ 6``) or ``(J_fᵀJ_f + λI)⁻¹ J_fᵀ e``.

    ``J_f`` is ``J`` with the columns not ``free`` zeroed (their ``dq`` is 0).
    """
    G = np.empty_like(A)
    gram(J, G)
    damped_solve_gram(J, G, free, e, damping, A, y, dq)


_SMALL_BATCH = 256
"""Below this many columns, one LAPACK solve per system beats the vectorised substitution."""


def damped_step(J: np.ndarray, e: np.ndarray, damping: np.ndarray) -> np.ndarray:
    r"""``Δq = Jᵀ (J Jᵀ + λ I)⁻¹ e`` for every column: ``J`` is ``m × n × B``, ``e`` ``m × B``.

    The symmetric positive-definite ``m × m`` systems are factored by Cholesky ``L Lᵀ`` and
    solved by forward and back substitution, each entry one vector operation over the batch
    (below ``_SMALL_BATCH`` columns by LAPACK, one system after another, where numpy's call
    overhead would dominate).

    Args:
        J: The Jacobians, the batch last (``m × n × B``).
        e: The errors (``m × B``).
        damping: ``λ ≥ 0`` per column (``B``); with ``λ = 0`` the least-norm step ``J⁺e`` of
            a ``J`` of full row rank.

    Returns:
        ``Δq`` (``n × B``).
    """
    m, _, size = J.shape
    if size < _SMALL_BATCH:
        Jb = J.transpose(2, 0, 1)
        A = Jb @ Jb.transpose(0, 2, 1)
        A[:, range(m), range(m)] += damping[:, None]
        return np.einsum("bik,bi->kb", Jb, np.linalg.solve(A, e.T[..., None])[..., 0])
    L = _batched_cholesky(J, damping)
    y: list[np.ndarray] = []
    for i in range(m):  # L y = e
        value = e[i].copy()
        for k in range(i):
            value -= L[i][k] * y[k]
        y.append(value / L[i][i])
    x: list[np.ndarray] = [y[0]] * m
    for i in reversed(range(m)):  # Lᵀ x = y
        value = y[i].copy()
        for k in range(i + 1, m):
            value -= L[k][i] * x[k]
        x[i] = value / L[i][i]
    return np.einsum("ikb,ib->kb", J, np.array(x))


def _batched_cholesky(J: np.ndarray, damping: np.ndarray) -> list[list[np.ndarray]]:
    """The Cholesky factor ``L`` of ``J Jᵀ + λI`` over the batch.

    ``L[i][k]`` (``k ≤ i``) is the batch of entries ``(i, k)``.
    """
    m = J.shape[0]
    L: list[list[np.ndarray]] = [[] for _ in range(m)]
    for j in range(m):
        diagonal = np.einsum("kb,kb->b", J[j], J[j]) + damping
        for k in range(j):
            diagonal -= L[j][k] * L[j][k]
        np.sqrt(diagonal, out=diagonal)
        inverse = 1.0 / diagonal
        for i in range(j + 1, m):
            entry = np.einsum("kb,kb->b", J[i], J[j])  # (J Jᵀ)[i, j]
            for k in range(j):
                entry -= L[i][k] * L[j][k]
            entry *= inverse
            L[i].append(entry)
        L[j].append(diagonal)
    return L
