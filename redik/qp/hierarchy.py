r"""Strict priorities: the lexicographic (hierarchical) QP.

Given level objectives :math:`f_k(x) = \tfrac12 x^\top H_k x + c_k^\top x`,
:math:`k = 0, 1, \dots` (0 highest) and the hard constraints :math:`x \in \mathcal{X}`
(bounds and rows), level :math:`k` is solved within the optimal set of all the levels
above it (Kanoun, Lamiraux & Wieber, *Kinematic control of redundant manipulators:
generalizing the task-priority framework to inequality tasks*, IEEE T-RO 2011; Escande,
Mansard & Wieber, *Hierarchical quadratic programming*, IJRR 2014):

.. math::

    x_k^* \in \arg\min_{x \in S_{k}} f_k(x), \qquad
    S_{k+1} = \{x \in S_k : f_k(x) = f_k(x_k^*)\}, \quad S_0 = \mathcal{X}.

For a convex quadratic, two minimisers differ by a direction :math:`d` with
:math:`H_k d = 0` and :math:`c_k^\top d = 0`, so
:math:`S_{k+1} = S_k \cap (x_k^* + \ker [H_k; c_k^\top])`. redik uses the **null-space
parameterisation**: :math:`x = x_k^* + N_k z`, where the columns of :math:`N_k` are an
orthonormal basis of the directions still free after levels :math:`0..k` (eigenvectors of
:math:`N_{k-1}^\top H_k N_{k-1}` with eigenvalue :math:`\le` ``rank_tol`` ·
:math:`λ_{max}`, less the direction of the projected :math:`c_k`). Level :math:`k+1` is then
the smaller QP in :math:`z`

.. math::

    \min_z \tfrac12 z^\top N^\top \tilde H_{k+1} N z
    + (N^\top (\tilde H_{k+1} x_k^* + c_{k+1}))^\top z
    \quad\text{s.t.}\quad x_k^* + N z \in \mathcal{X},
    \qquad \tilde H = H + εI,

so a lower level can never change a higher level's objective. Each level's Hessian
arrives regularised, :math:`\tilde H_k = H_k + εI` (``damping``: it picks the smallest step
among equals and keeps the Hessian definite for active-set solvers); as :math:`εI` shifts
every eigenvalue alike, the null space is that of the undamped :math:`H_k` with the
eigenvalues read as :math:`λ - ε`. The constraints of level :math:`k+1` are relaxed by the previous
solution's own violation (at most the back-end tolerance) so that :math:`z = 0` stays
feasible — so a lower level can always be solved; should its back-end still fail (a
degenerate face confuses some), the level and those below it are skipped and counted.
Levels after the freedom is used up are skipped.

This is the priority API other drivers build on: any objective :math:`(H, c)` given as a
level below the task levels (e.g. a null-space motion) is optimised without disturbing
them.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..exceptions import BackendError, InfeasibleProblem
from .backends import Backend
from .problem_data import QP


def free_directions(H: np.ndarray, c: np.ndarray, rank_tol: float, shift: float = 0.0):
    """Orthonormal basis (n × r) of ``ker [H − shift·I; cᵀ]`` for symmetric ``H``, by eigh.

    ``shift`` is the regularisation already added to ``H``: eigenvectors are shared, and an
    eigenvalue ``λ`` counts as zero when ``λ − shift ≤ rank_tol · (λ_max − shift)``.
    """
    eigenvalues, eigenvectors = np.linalg.eigh(H)
    eigenvalues = eigenvalues - shift
    scale = max(float(eigenvalues[-1]), 0.0)
    N = eigenvectors[:, eigenvalues <= rank_tol * scale] if scale > 0.0 else eigenvectors
    if N.shape[1] == 0:
        return N
    g = N.T @ c
    norm = float(np.linalg.norm(g))
    if norm > rank_tol * max(float(np.linalg.norm(c)), 1.0):
        # Remove the direction along which the linear term still changes the objective.
        _, _, Vt = np.linalg.svd(g[None, :])
        N = N @ Vt[1:].T
    return N


def solve_lexicographic(
    objectives: Sequence[tuple[np.ndarray, np.ndarray]],
    backends: Sequence[Backend],
    lb: np.ndarray | None = None,
    ub: np.ndarray | None = None,
    C: np.ndarray | None = None,
    l: np.ndarray | None = None,
    u: np.ndarray | None = None,
    damping: float | Sequence[float] = 0.0,
    rank_tol: float = 1e-10,
    stats: dict | None = None,
) -> np.ndarray:
    """Solve the levels ``objectives`` (highest first) lexicographically; returns ``x``.

    Args:
        objectives: ``(H_k + εI, c_k)`` per level, already regularised; not modified.
        backends: One back-end per level (they may keep per-level state).
        lb, ub: Bounds on ``x`` (or None).
        C, l, u: Rows ``l ≤ C x ≤ u`` (or None).
        damping: The ``ε`` the Hessians carry (discounted when finding null spaces): one
            value for every level, or one per level (e.g. a Levenberg–Marquardt term on
            level 0 only).
        rank_tol: Relative eigenvalue threshold of the null space.
        stats: If given, ``stats["skipped_levels"]`` counts lower levels whose back-end
            failed; their step is then zero (``z = 0`` is always feasible for them).

    Raises:
        InfeasibleProblem, BackendError: from the back-end of level 0.
    """
    shifts = [damping] * len(objectives) if np.isscalar(damping) else list(damping)
    H0, c0 = objectives[0]
    x = backends[0].solve(QP(H0, c0, lb, ub, C, l, u))
    if len(objectives) == 1:
        return x
    N = free_directions(H0, c0, rank_tol, shifts[0])
    last = len(objectives) - 1
    for level, ((H_k, c_k), backend, shift) in enumerate(
        zip(objectives[1:], backends[1:], shifts[1:], strict=True), start=1
    ):
        if N.shape[1] == 0:
            break
        Hz = N.T @ H_k @ N
        cz = N.T @ (H_k @ x + c_k)
        rows, lower, upper = [], [], []
        if lb is not None:
            rows.append(N)
            lower.append(lb - x)
            upper.append(ub - x)
        if C is not None:
            rows.append(C @ N)
            Cx = C @ x
            lower.append(l - Cx)
            upper.append(u - Cx)
        qp = QP(Hz, cz)
        if rows:
            qp.C = np.vstack(rows)
            # Keep z = 0 feasible despite the previous level's tolerance-sized violation.
            qp.l = np.minimum(np.concatenate(lower), 0.0)
            qp.u = np.maximum(np.concatenate(upper), 0.0)
        try:
            z = backend.solve(qp)
        except (BackendError, InfeasibleProblem):
            # z = 0 is feasible by construction, so a failure here is the back-end's (a
            # degenerate face confuses some); keep the higher levels' step.
            if stats is not None:
                stats["skipped_levels"] = stats.get("skipped_levels", 0) + 1
            break
        x = x + N @ z
        if level == last:
            break  # no level below: its free directions would go unused
        N = N @ free_directions(Hz, cz, rank_tol, shift)
    return x
