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
eigenvalues read as :math:`λ - ε`. The constraints of level :math:`k+1` are relaxed by the
previous solution's own violation (at most the back-end tolerance) so that :math:`z = 0`
stays feasible — so a lower level can always be solved; should its back-end still fail (a
degenerate face confuses some), the level and those below it are skipped and counted.
Levels after the freedom is used up are skipped.

**Ranked inequalities.** A group of rows :math:`Gx \le h` may also be given a place in the
order (``ranked``: a limit with ``priority=``, :mod:`redik.limits.limit`). Just before level
:math:`k` it is the slack level

.. math::

    \min_{z,\,w}\ \tfrac12\|w\|^2 + \tfrac{ρ}{2}\|z\|^2
    \quad\text{s.t.}\quad G(x + Nz) - w \le h,\ \ x + Nz \in \mathcal{X},

(:math:`ρ` = :data:`SLACK_DAMPING`: the least violation, damped as Levenberg–Marquardt
damps a least-squares step where the rows lose rank). Its :math:`w^* = \max(G x^+ - h, 0)`
at the new point :math:`x^+ = x + Nz^*` is the least violation within :math:`S_k`; from
there on :math:`G x \le h + w^*` joins the constraints of every lower level, and the free
directions :math:`N` are unchanged (an inequality fixes a polyhedron, not a subspace). The
levels above never saw the rows. Kanoun et al.'s inequality tasks, one QP each (rather
than Escande et al.'s active-set HQP).

**Special structure.** When level 0 is a pure least-squares level
(:math:`H_0 = A_0^\top A_0 + εI`, e.g. a pose task), its null space comes from one
Householder QR of :math:`A_0^\top` (:func:`row_null_space`) instead of an
eigendecomposition; on a back-end that is not active-set its minimiser, when no bound or
row binds it, is the damped least-squares solution (:func:`least_squares_minimiser`), exact
where such a back-end stops at its tolerance along the near-null directions of
:math:`H_0`. A lower level left with a single free direction (a 7-joint arm under a 6-D
pose) is a one-variable QP, solved in closed form (:func:`_solve_one_variable`).

:func:`solve_lexicographic` runs the levels in these named steps: the ranked groups before
level 0 (:func:`_rank_before_level0`), level 0 (:func:`_solve_level0`), its free
directions (:func:`_level0_free_directions`), then per lower level the ranked groups just
above it (:func:`_apply_ranked`) and the level itself (:func:`_solve_lower_level`). Any
objective :math:`(H, c)` given as a level below the task levels (a null-space motion) is
optimised this way without disturbing them.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.linalg.lapack import dgeqrf as _dgeqrf
from scipy.linalg.lapack import dormqr as _dormqr
from scipy.linalg.lapack import dposv as _dposv
from scipy.linalg.lapack import dsyev as _dsyev
from scipy.linalg.lapack import dtrcon as _dtrcon

from redik.core.exceptions import BackendError, InfeasibleProblem
from redik.qp.backends import Backend
from redik.qp.problem_data import QP

CURVATURE_MARGIN = 0.01
"""A second-order term is used only while the reduced model keeps this fraction of level 1's
own reduced Hessian (a step at most 1/0.01 = 100 times level 1's own Newton step)."""

SLACK_DAMPING = 1e-2
"""``ρ`` of a ranked inequality's slack level, ``½‖w‖² + ½ρ‖z‖²`` (row units² per unit² of
``Δq``: a radian of motion weighs as 0.1 m of violation): Levenberg–Marquardt damping of the
least-violation step. Where the free directions barely move the rows (gain ``σ``: a link
pivoting about a hand held inside an obstacle) the undamped step ``v/σ`` is huge and trusts
the linearisation far beyond its reach; damped, it is at most ``v/(2√ρ) = 5v``, and where
the rows have gain it keeps ``σ²/(σ² + ρ)`` of the reduction (96 % at σ = 0.5 m/rad). As in
Levenberg–Marquardt the damping shapes the step, not the stationary points: a point from
which the slack level does not move (``z* = 0``) satisfies ``(GN)ᵀw = 0``, the first-order
condition of the least violation itself."""

ROW_GAIN_TOL = 1e-12
"""A constraint row whose gain ``|a_i|`` along a free direction is at most this does not
block that direction (:func:`_solve_one_variable`, :meth:`Constraints.around`): it moves the
row by round-off only (a self-motion direction has exact zeros on some joints, computed as
±1e-16), while a joint sitting on its bound would otherwise stop the whole motion at
``z = 0`` — or not, by the sign of that round-off."""

Curvature = Callable[[NDArray[np.float64]], NDArray[np.float64]]
"""``N ↦ NᵀMN``: a second-order term of level 1 in the coordinates of a basis ``N``."""

Ranked = tuple[int, NDArray[np.float64], NDArray[np.float64], Backend]
"""A ranked inequality group ``(k, G, h, backend)``: the rows ``G x ≤ h`` just before level
``k``, solved by ``backend``."""


@dataclasses.dataclass(slots=True)
class Constraints:
    """The hard constraints every level is solved under.

    Bounds ``lb ≤ x ≤ ub`` and rows ``l ≤ C x ≤ u``, each pair None when absent.
    """

    lb: NDArray[np.float64] | None = None
    ub: NDArray[np.float64] | None = None
    C: NDArray[np.float64] | None = None
    l: NDArray[np.float64] | None = None
    u: NDArray[np.float64] | None = None

    def with_rows(self, G: NDArray[np.float64], bound: NDArray[np.float64]) -> Constraints:
        """These constraints and the rows ``G x ≤ bound``."""
        free = np.full(G.shape[0], -np.inf)
        if self.C is None:
            return dataclasses.replace(self, C=G, l=free, u=bound)
        return dataclasses.replace(
            self,
            C=np.vstack([self.C, G]),
            l=np.concatenate([self.l, free]),
            u=np.concatenate([self.u, bound]),
        )

    def around(
        self, x: NDArray[np.float64], N: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """The constraints ``x + N z ∈ 𝒳`` as rows on ``z``: ``(rows, lower, upper)``.

        They are relaxed by ``x``'s own violation so that ``z = 0`` stays feasible; gains
        within :data:`ROW_GAIN_TOL` are zero; ``rows`` is empty without constraints.
        """
        rows: list[NDArray[np.float64]] = []
        lower: list[NDArray[np.float64]] = []
        upper: list[NDArray[np.float64]] = []
        if self.lb is not None and self.ub is not None:
            rows.append(N)
            lower.append(self.lb - x)
            upper.append(self.ub - x)
        if self.C is not None and self.l is not None and self.u is not None:
            Cx = self.C @ x
            rows.append(self.C @ N)
            lower.append(self.l - Cx)
            upper.append(self.u - Cx)
        if not rows:
            return np.empty((0, N.shape[1])), np.empty(0), np.empty(0)
        lower_all = np.minimum(np.concatenate(lower), 0.0)
        upper_all = np.maximum(np.concatenate(upper), 0.0)
        stacked = np.vstack(rows)
        stacked[np.abs(stacked) <= ROW_GAIN_TOL] = 0.0
        return stacked, lower_all, upper_all


def free_directions(
    H: NDArray[np.float64], c: NDArray[np.float64], rank_tol: float, shift: float = 0.0
) -> NDArray[np.float64]:
    """Orthonormal basis (n × r) of ``ker [H − shift·I; cᵀ]`` for symmetric ``H``.

    :func:`kernel_directions` less the direction of ``c`` (:func:`without_gradient`).
    """
    return without_gradient(kernel_directions(H, rank_tol, shift), c, rank_tol)


def kernel_directions(
    H: NDArray[np.float64], rank_tol: float, shift: float = 0.0
) -> NDArray[np.float64]:
    """Orthonormal basis (n × r) of ``ker (H − shift·I)`` for symmetric ``H``.

    ``shift`` is the regularisation already added to ``H``: eigenvectors are shared, and an
    eigenvalue ``λ`` counts as zero when ``λ − shift ≤ rank_tol · (λ_max − shift)``. One
    LAPACK ``dsyev`` call (numpy's ``eigh`` wrapper costs twice the decomposition at these
    sizes).
    """
    eigenvalues, eigenvectors, info = _dsyev(H, compute_v=1, lower=1)
    if info != 0:  # LAPACK did not converge: the general routine decides
        eigenvalues, eigenvectors = np.linalg.eigh(H)
    eigenvalues -= shift
    scale = eigenvalues[-1]
    kernel: NDArray[np.float64] = (
        eigenvectors[:, eigenvalues <= rank_tol * scale] if scale > 0.0 else eigenvectors
    )
    return kernel


def without_gradient(
    N: NDArray[np.float64], c: NDArray[np.float64], rank_tol: float
) -> NDArray[np.float64]:
    """A basis of ``{N z : cᵀ N z = 0}``: the columns of ``N`` less the direction of ``c``.

    ``N`` is orthonormal; the direction removed is the one along which the linear term ``c``
    still changes the objective. The reflection ``P = I − 2vvᵀ/vᵀv``, ``v = u − e₁``
    (``u = Nᵀc/‖Nᵀc‖``) maps ``e₁`` to ``u``, so its other columns span ``u⊥`` (Golub &
    Van Loan §5.1.2). ``N`` is returned as it is when ``‖Nᵀc‖ ≤ rank_tol · max(‖c‖, 1)``.
    """
    if N.shape[1] == 0:
        return N
    g = c @ N
    norm = math.sqrt(g @ g)
    if norm <= rank_tol * max(math.sqrt(c @ c), 1.0):
        return N
    v = g / norm
    v[0] -= 1.0
    vv = v @ v
    rest: NDArray[np.float64] = N[:, 1:]
    if vv > 0.0:
        rest = rest - np.outer(N @ v, v[1:]) * (2.0 / vv)
    return rest


def row_null_space(A: NDArray[np.float64], rank_tol: float) -> NDArray[np.float64] | None:
    """Orthonormal basis (n × (n − m)) of ``ker A`` for a wide ``A`` of full row rank.

    One Householder QR of ``Aᵀ`` — cheaper than the eigendecomposition of ``AᵀA``.
    ``Aᵀ = Q R``: the last ``n − m`` columns of ``Q`` span ``range(Aᵀ)⊥ = ker A``
    (Golub & Van Loan §5.2). Returns None (use :func:`free_directions`) when ``A`` is not
    wide or LAPACK's estimate of ``R``'s reciprocal condition number is within a factor 10
    of ``√rank_tol`` — the QR is not rank-revealing there, the eigendecomposition is; the
    two thresholds agree, as ``AᵀA`` squares the singular values.
    """
    m, n = A.shape
    if m == 0 or m >= n:
        return None
    qr, tau, _, info = _dgeqrf(A.T)
    if info != 0:
        return None
    rcond, info = _dtrcon(qr[:m])  # reads the upper triangle only
    if info != 0 or not rcond > 10.0 * math.sqrt(rank_tol):
        return None
    N, _, info = _dormqr(b"L", b"N", qr, tau, _identity_tail(n, m), 64 * n)
    return N if info == 0 else None


_IDENTITY_TAILS: dict[tuple[int, int], NDArray[np.float64]] = {}


def _identity_tail(n: int, m: int) -> NDArray[np.float64]:
    """The last ``n − m`` columns of the n × n identity, Fortran-ordered (LAPACK's)."""
    tail = _IDENTITY_TAILS.get((n, m))
    if tail is None:
        tail = _IDENTITY_TAILS[n, m] = np.asfortranarray(np.eye(n)[:, m:])
    return tail


def least_squares_minimiser(
    A: NDArray[np.float64],
    b: NDArray[np.float64],
    shift: float,
    lb: NDArray[np.float64] | None,
    ub: NDArray[np.float64] | None,
    C: NDArray[np.float64] | None,
    l: NDArray[np.float64] | None,
    u: NDArray[np.float64] | None,
) -> NDArray[np.float64] | None:
    r"""The minimiser of a damped least-squares level when no bound or row binds it, else None.

    The level is :math:`\tfrac12\|Ax - b\|^2 + \tfrac{s}{2}\|x\|^2` with ``A`` wide, subject
    to the bounds ``lb ≤ x ≤ ub`` and the rows ``l ≤ C x ≤ u`` (None when absent).

    The unconstrained minimiser :math:`A^\top (AA^\top + sI)^{-1} b` (the push-through
    identity: an m × m Cholesky solve whose condition is that of :math:`AA^\top`, not the
    :math:`σ_{max}^2/s` of :math:`H = A^\top A + sI` along :math:`\ker A`) satisfies the
    KKT conditions with zero multipliers whenever it is feasible, and is then *the*
    minimiser (Nocedal & Wright §16.1): exact, without a back-end call. Feasible means
    within the bounds and rows exactly. Used for back-ends that are not active-set
    (:attr:`redik.qp.backends.Backend.active_set`).
    """
    m, n = A.shape
    if m >= n:
        return None
    gram = A @ A.T
    gram.flat[:: m + 1] += shift
    _, y, info = _dposv(gram, b)
    if info != 0:  # not positive definite (or a NaN): the back-end decides
        return None
    x = A.T @ y
    if lb is not None and not ((x >= lb).all() and (x <= ub).all()):
        return None  # (a NaN fails the comparisons too)
    if C is not None:
        Cx = C @ x
        if not ((Cx >= l).all() and (Cx <= u).all()):
            return None
    return x if np.isfinite(x).all() else None


def _solve_one_variable(
    h: float,
    g: float,
    a: list[float],
    lower: list[float],
    upper: list[float],
    offset: list[float] | None = None,
) -> float:
    """The one-variable QP ``argmin ½ h z² + g z`` subject to relaxed rows, in closed form.

    The rows are ``min(l, 0) ≤ a z ≤ max(u, 0)`` with ``l = lower − offset``,
    ``u = upper − offset`` (``offset`` default 0; h > 0; the relaxation keeps ``z = 0``
    feasible): the unconstrained minimiser ``−g/h``, pulled back to the first row it crosses
    on its way from 0 — exact, no back-end needed. A row with ``|a_i| ≤`` :data:`ROW_GAIN_TOL`
    holds for every ``z`` (it moves by round-off only). A plain loop over Python floats: at
    a handful of rows it is several times faster than numpy's per-call overhead.
    """
    z = -g / h
    if offset is None:
        offset = [0.0] * len(a)
    for a_i, lower_i, upper_i, offset_i in zip(a, lower, upper, offset, strict=True):
        if -ROW_GAIN_TOL <= a_i <= ROW_GAIN_TOL:
            continue
        # The side of row i that z moves towards: a_i z grows when a_i and z share a sign.
        if (a_i > 0.0) == (z > 0.0):
            if a_i * z > upper_i - offset_i:
                z = max(upper_i - offset_i, 0.0) / a_i
        elif a_i * z < lower_i - offset_i:
            z = min(lower_i - offset_i, 0.0) / a_i
    return z


def _least_violation(
    x: NDArray[np.float64],
    N: NDArray[np.float64] | None,
    G: NDArray[np.float64],
    h: NDArray[np.float64],
    constraints: Constraints,
    backend: Backend,
    shift: float,
) -> NDArray[np.float64]:
    """The point ``x + Nz`` of the slack level of the rows ``Gx ≤ h`` (module docstring).

    ``N`` None: the full space from ``x = 0`` with the constraints as given (before level
    0); else they are relaxed by ``x``'s own violation so that ``z = 0`` stays feasible, as
    for a lower level.
    """
    n = x.shape[0]
    r = n if N is None else N.shape[1]
    m = G.shape[0]
    H = np.zeros((r + m, r + m))
    H.flat[: r * (r + m) : r + m + 1] = max(shift, SLACK_DAMPING)
    H.flat[r * (r + m) + r :: r + m + 1] = 1.0  # ½‖w‖²
    basis = np.eye(n) if N is None else N
    rows, lower, upper = constraints.around(x, basis)
    if N is None and rows.shape[0]:
        # Before level 0 the constraints hold as given: no relaxation around x = 0.
        lower, upper = _unrelaxed(constraints)
    stacked = np.vstack(
        [np.hstack([G @ basis, -np.eye(m)]), np.hstack([rows, np.zeros((rows.shape[0], m))])]
    )
    low = np.concatenate([np.full(m, -np.inf), lower])
    up = np.concatenate([h - G @ x, upper])
    qp = QP(H, np.zeros(r + m), C=stacked, l=low, u=up)
    z = backend.solve(qp)[:r]
    step: NDArray[np.float64] = x + basis @ z
    return step


def _unrelaxed(constraints: Constraints) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The bounds of :meth:`Constraints.around` at ``x = 0`` without the relaxation."""
    lower: list[NDArray[np.float64]] = []
    upper: list[NDArray[np.float64]] = []
    if constraints.lb is not None and constraints.ub is not None:
        lower.append(constraints.lb)
        upper.append(constraints.ub)
    if constraints.C is not None and constraints.l is not None and constraints.u is not None:
        lower.append(constraints.l)
        upper.append(constraints.u)
    return np.concatenate(lower), np.concatenate(upper)


def _skipped(stats: dict[str, int] | None) -> None:
    """Count a lower level whose back-end failed (its step is then zero)."""
    if stats is not None:
        stats["skipped_levels"] = stats.get("skipped_levels", 0) + 1


def _rank_before_level0(
    ranked: list[Ranked], constraints: Constraints, n: int, shift: float
) -> Constraints:
    """The constraints with the ranked groups placed before level 0 (popped from ``ranked``).

    Each group is solved from ``x = 0`` and appended to the hard constraints, relaxed by its
    least violation.
    """
    while ranked and ranked[0][0] == 0:
        _, G, h, backend = ranked.pop(0)
        point = _least_violation(np.zeros(n), None, G, h, constraints, backend, shift)
        constraints = constraints.with_rows(G, np.maximum(G @ point, h))
    return constraints


def _solve_level0(
    objective: tuple[NDArray[np.float64], NDArray[np.float64]],
    backend: Backend,
    constraints: Constraints,
    rows0: NDArray[np.float64] | None,
    rhs0: NDArray[np.float64] | None,
    shift: float,
) -> NDArray[np.float64]:
    """Level 0's minimiser.

    The damped least-squares solution when no constraint binds it and the back-end is not
    active-set (module docstring), else the back-end's.
    """
    x = None
    c = constraints
    if rows0 is not None and rhs0 is not None and not backend.active_set:
        x = least_squares_minimiser(rows0, rhs0, shift, c.lb, c.ub, c.C, c.l, c.u)
    if x is None:
        H0, c0 = objective
        x = backend.solve(QP(H0, c0, c.lb, c.ub, c.C, c.l, c.u))
    return x


def _level0_free_directions(
    objective: tuple[NDArray[np.float64], NDArray[np.float64]],
    rows0: NDArray[np.float64] | None,
    kernel0: NDArray[np.float64] | None,
    rank_tol: float,
    shift: float,
) -> NDArray[np.float64]:
    """Orthonormal basis of the directions level 0 leaves free.

    ``kernel0`` (given), the QR of its rows (a least-squares level), or its Hessian's
    eigendecomposition; less the direction of its gradient.
    """
    H0, c0 = objective
    if kernel0 is not None:
        return without_gradient(kernel0, c0, rank_tol)
    N = None if rows0 is None else row_null_space(rows0, rank_tol)
    return free_directions(H0, c0, rank_tol, shift) if N is None else N


def _apply_ranked(
    ranked: list[Ranked],
    level: int,
    x: NDArray[np.float64],
    N: NDArray[np.float64],
    constraints: Constraints,
    shift: float,
    stats: dict[str, int] | None,
) -> tuple[NDArray[np.float64], Constraints, bool]:
    """The ranked groups placed just before ``level`` (popped from ``ranked``).

    Returns ``(x, the constraints with their rows, whether the hierarchy goes on)``; a group
    whose back-end fails ends it there, counted as a skipped level.
    """
    while ranked and ranked[0][0] == level:
        _, G, h, backend = ranked.pop(0)
        try:
            x = _least_violation(x, N, G, h, constraints, backend, shift)
        except (BackendError, InfeasibleProblem):
            _skipped(stats)
            return x, constraints, False
        constraints = constraints.with_rows(G, np.maximum(G @ x, h))
    return x, constraints, True


def _curved_model(
    Hz: NDArray[np.float64],
    cz: NDArray[np.float64],
    M: NDArray[np.float64],
    Nx: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The reduced model with the second-order term ``M``, when it stays convex enough.

    ``Hz + M`` is used when it keeps :data:`CURVATURE_MARGIN` of ``Hz`` (positive definite),
    else ``Hz`` alone; the model's gradient is taken at ``x`` (``Nx = Nᵀx``).
    """
    try:
        np.linalg.cholesky(Hz + M - CURVATURE_MARGIN * Hz)
    except np.linalg.LinAlgError:
        return Hz, cz  # not convex enough in the free directions: level 1's own Hessian
    return Hz + M, cz + M @ Nx


def _one_direction_level(
    H_k: NDArray[np.float64],
    c_k: NDArray[np.float64],
    x: NDArray[np.float64],
    v: NDArray[np.float64],
    constraints: Constraints,
    curvature: Curvature | None,
) -> tuple[float, float, float] | None:
    """Level ``k`` along its one free direction ``v``, in closed form.

    Returns ``(z, h, g)`` with ``x + z v`` its minimiser (:func:`_solve_one_variable`),
    ``h = vᵀH_k v`` and ``g`` the model's slope at ``x``; None when ``h ≤ 0`` (the general
    path decides).
    """
    Hv = H_k @ v
    h = float(v @ Hv)
    if h <= 0.0:
        return None
    h_model, m = h, 0.0
    if curvature is not None:
        m = float(curvature(v[:, None])[0, 0])
        if h * (1.0 - CURVATURE_MARGIN) + m > 0.0:
            h_model = h + m
        else:
            m = 0.0
    # The model's gradient at x: level 0's x may carry a component along v (a
    # tolerance-based back-end's, along its near-null directions).
    g = float(x @ Hv) + float(c_k @ v) + m * float(v @ x)
    a: list[float] = []
    lower: list[float] = []
    upper: list[float] = []
    offset: list[float] = []
    if constraints.lb is not None and constraints.ub is not None:
        a += v.tolist()
        lower += constraints.lb.tolist()
        upper += constraints.ub.tolist()
        offset += x.tolist()
    if constraints.C is not None and constraints.l is not None and constraints.u is not None:
        a += (constraints.C @ v).tolist()
        lower += constraints.l.tolist()
        upper += constraints.u.tolist()
        offset += (constraints.C @ x).tolist()
    return _solve_one_variable(h_model, g, a, lower, upper, offset), h, g


def _reduced_level(
    H_k: NDArray[np.float64],
    c_k: NDArray[np.float64],
    x: NDArray[np.float64],
    N: NDArray[np.float64],
    constraints: Constraints,
    curvature: Curvature | None,
    backend: Backend,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Level ``k`` in the coordinates ``z`` of ``x + N z``.

    Returns ``(z, Hz, cz)``: ``Hz``, ``cz`` are the reduced level without the second-order
    term, for the next free directions.

    Raises:
        BackendError, InfeasibleProblem: from the back-end.
    """
    HN = H_k @ N
    Hz = N.T @ HN
    cz = (x @ HN) + (c_k @ N)
    qp = QP(Hz, cz)
    if curvature is not None:
        qp.H, qp.c = _curved_model(Hz, cz, curvature(N), N.T @ x)
    rows, lower, upper = constraints.around(x, N)
    if rows.shape[0]:
        qp.C, qp.l, qp.u = rows, lower, upper
    return backend.solve(qp), Hz, cz


def _solve_lower_level(
    objective: tuple[NDArray[np.float64], NDArray[np.float64]],
    backend: Backend,
    x: NDArray[np.float64],
    N: NDArray[np.float64],
    constraints: Constraints,
    curvature: Curvature | None,
    rank_tol: float,
    shift: float,
    last: bool,
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None] | None:
    """One lower level within ``x + range(N)``.

    Returns ``(x, N)`` after it (the point and the directions it leaves free; None for the
    ``last`` level, whose are not needed), or None when its back-end failed (``z = 0`` is
    feasible by construction, so the failure is the back-end's: a degenerate face confuses
    some).
    """
    H_k, c_k = objective
    if N.shape[1] == 1:
        solved = _one_direction_level(H_k, c_k, x, N[:, 0], constraints, curvature)
        if solved is not None:
            z, h, g = solved
            x = x + z * N[:, 0]
            if last:
                return x, None
            return x, N @ free_directions(np.array([[h]]), np.array([g]), rank_tol, shift)
    try:
        reduced_step, Hz, cz = _reduced_level(H_k, c_k, x, N, constraints, curvature, backend)
    except (BackendError, InfeasibleProblem):
        return None
    x = x + N @ reduced_step
    return x, None if last else N @ free_directions(Hz, cz, rank_tol, shift)


def solve_lexicographic(
    objectives: Sequence[tuple[NDArray[np.float64], NDArray[np.float64]]],
    backends: Sequence[Backend],
    lb: NDArray[np.float64] | None = None,
    ub: NDArray[np.float64] | None = None,
    C: NDArray[np.float64] | None = None,
    l: NDArray[np.float64] | None = None,
    u: NDArray[np.float64] | None = None,
    damping: float | Sequence[float] = 0.0,
    rank_tol: float = 1e-10,
    stats: dict[str, int] | None = None,
    rows0: NDArray[np.float64] | None = None,
    kernel0: NDArray[np.float64] | None = None,
    curvature1: Curvature | None = None,
    rhs0: NDArray[np.float64] | None = None,
    ranked: Sequence[Ranked] = (),
) -> NDArray[np.float64]:
    """Solve the levels ``objectives`` (highest first) lexicographically; returns ``x``.

    Args:
        objectives: ``(H_k + εI, c_k)`` per level, already regularised; not modified.
        backends: One back-end per level (they may keep per-level state).
        lb: Lower bounds on ``x`` (or None).
        ub: Upper bounds on ``x`` (or None with ``lb``).
        C: Rows ``l ≤ C x ≤ u`` (or None).
        l: Lower bounds of the rows.
        u: Upper bounds of the rows.
        damping: The ``ε`` the Hessians carry (discounted when finding null spaces): one
            value for every level, or one per level (e.g. a Levenberg–Marquardt term on
            level 0 only).
        rank_tol: Relative eigenvalue threshold of the null space.
        stats: If given, ``stats["skipped_levels"]`` counts lower levels whose back-end
            failed; their step is then zero (``z = 0`` is always feasible for them).
        rows0: The stacked rows ``A₀`` when level 0 is a pure least-squares level,
            ``H₀ = A₀ᵀA₀ + εI``: its null space then comes from a QR of ``A₀ᵀ``
            (:func:`row_null_space`) rather than an eigendecomposition.
        kernel0: An orthonormal basis of ``ker A₀`` (or of ``ker (H₀ − εI)``) the caller
            already has; ``c₀``'s direction is still removed here.
        curvature1: ``N ↦ NᵀMN``, the second-order term of level 1 in the coordinates of
            the basis ``N`` of level 0's optimal set: added to level 1's reduced Hessian
            when ``NᵀH₁N + NᵀMN − ρ NᵀH₁N`` (``ρ`` = :data:`CURVATURE_MARGIN`) is positive
            definite, else ignored (the curvature of level 0's constraint weighted by level
            1's multipliers: the Hessian of the Lagrangian of sequential quadratic
            programming, :mod:`redik.qp.curvature`).
        rhs0: With ``rows0``, the right-hand side ``b₀`` of level 0 (``c₀ = −A₀ᵀb₀``): its
            minimiser, when no constraint binds it, is then the damped least-squares
            solution (:func:`least_squares_minimiser`) on a back-end that is not
            active-set.
        ranked: Ranked inequality groups ``(k, G, h, backend)``, in order: the rows
            ``G x ≤ h`` as a slack level just before level ``k`` (``k = len(objectives)``:
            after the last), solved by ``backend`` (module docstring). A group at 0 that the
            hard constraints leave no point for raises as level 0 does; a later group whose
            back-end fails ends the hierarchy there, counted as a skipped level.

    Returns:
        The step ``x``.

    Raises:
        InfeasibleProblem, BackendError: from the back-end of level 0.
    """
    shifts = (
        [float(damping)] * len(objectives)
        if isinstance(damping, int | float | np.integer | np.floating)
        else [float(shift) for shift in damping]
    )
    ranked = list(ranked)
    n = objectives[0][1].shape[0]
    constraints = _rank_before_level0(ranked, Constraints(lb, ub, C, l, u), n, shifts[0])
    x = _solve_level0(objectives[0], backends[0], constraints, rows0, rhs0, shifts[0])
    if len(objectives) == 1 and not ranked:
        return x
    N = _level0_free_directions(objectives[0], rows0, kernel0, rank_tol, shifts[0])
    # The last level whose free directions are needed: the last objective, or the one before
    # trailing ranked groups.
    last = len(objectives) - (0 if ranked and ranked[-1][0] == len(objectives) else 1)
    for level in range(1, len(objectives) + 1):
        shift = shifts[min(level, len(shifts) - 1)]
        if N.shape[1] == 0:
            break
        x, constraints, going_on = _apply_ranked(ranked, level, x, N, constraints, shift, stats)
        if not going_on or level == len(objectives):
            break
        curvature = curvature1 if level == 1 else None
        solved = _solve_lower_level(
            objectives[level], backends[level], x, N, constraints, curvature, rank_tol, shift,
            last=level == last,
        )  # fmt: skip
        if solved is None:
            _skipped(stats)
            break
        x, directions = solved
        if directions is None:
            break
        N = directions
    return x
