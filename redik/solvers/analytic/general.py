r"""Every solution of a general 6R arm: Raghavan–Roth elimination solved as an eigenproblem.

An arm with no three axes meeting or parallel (no closed form, :mod:`.decomposed`) still has
finitely many solutions, at most 16 (Primrose 1986; Lee & Liang 1988): the real roots of a
univariate polynomial of degree 16 in :math:`x_3 = \tan(θ_3/2)`. This module finds all of
them by the elimination of Raghavan & Roth ("Inverse kinematics of the general 6R manipulator and
related linkages", ASME J. Mech. Des. 115, 1993) solved as a generalised eigenproblem as
Manocha & Canny do ("Efficient inverse kinematics for general 6R manipulators", IEEE Trans.
Robot. Autom. 10(5), 1994):

1. The arm is written in standard Denavit–Hartenberg form,
   :math:`A_i = R_z(θ_i) T_z(d_i) T_x(a_i) R_x(α_i)`, from its screw axes (common normals at
   q = 0, :func:`dh_of_chain`), and the loop is split as
   :math:`A_3 A_4 A_5 = A_2^{-1} A_1^{-1} T A_6^{-1}`. The third and fourth columns of
   :math:`A_6^{-1}` do not depend on θ6, so the axis ``l`` and position ``p`` of both sides
   give six equations free of θ6.
2. With them, ``p·p``, ``p·l``, ``p × l`` and ``(p·p) l − 2 (p·l) p``: fourteen equations
   :math:`P(θ_3)\,R = Q\,S`, ``R`` the nine products of ``{1, c4, s4}`` and ``{1, c5, s5}``,
   ``S`` the eight non-constant products of ``{1, c1, s1}`` and ``{1, c2, s2}``, ``P``
   linear in ``c3, s3`` and ``Q`` fixed by the target (Raghavan & Roth's theorem: the
   products add no higher power). The coefficients are read off exactly by the three-point
   Fourier transform of each side in each angle (a function linear in ``{1, cos θ, sin θ}``
   is fixed by its values at θ = 0, 2π/3, 4π/3).
3. ``Q`` (14 × 8) has a 6-dimensional left null space ``N``: ``N P(θ3) R = 0`` are six
   equations in θ3, θ4, θ5 alone. With half-angle tangents (each angle shifted by a fixed
   offset so that no solution of a generic target sits at the tangent's pole) and cleared
   denominators they are biquadratic in ``x4, x5`` and quadratic in ``x3``; with their
   multiples by ``x4`` they form :math:`M(x_3) m = 0`, ``M`` 12 × 12 quadratic in ``x3``,
   ``m`` the monomials :math:`x_4^i x_5^j` (i ≤ 3, j ≤ 2). ``det M(x3) = 0`` is the degree-16
   polynomial (times the spurious :math:`(1 + x_3^2)^4`), solved without forming it: the
   24 × 24 companion pencil's eigenvalues (QZ, homogeneous, so a root at the pole is an
   eigenvalue at infinity). This is what makes the method exact and robust where a search is
   not: no sampling density, no root left between samples, no double root to detect.
4. Each real root (imaginary part within :data:`IMAGINARY_TOL`, so that a double root split
   by rounding is kept) gives ``m`` from the null space of :math:`M(x_3)` — for a root of
   multiplicity k the k-dimensional null space is split by the shift ``x4`` (a k × k
   eigenproblem) — and θ4, θ5 from ratios of its entries; θ1, θ2 from ``Q S = P R`` (least
   squares, by ``Q``'s pseudo-inverse), θ6 from :math:`A_6 = (A_1 ⋯ A_5)^{-1} T`.
5. Every candidate is polished by Gauss–Newton on the screw chain's FK and kept only if that
   FK reaches the target within :data:`~redik.solvers.analytic.decomposed.VERIFY_TOL`;
   duplicates are merged. Where the Jacobian's condition is below :data:`SINGULAR_TOL` two
   roots meet (a double root): the solution carries a ``singular`` text.

The alternative, IK-Geo's 2-D search (Elias & Wen 2022, arXiv 2211.05737, §IV-C: sample two
joint angles, reduce the rest to subproblems, find the zeros of a 2-D error function), can
miss a pair of roots closer than its grid and needs a tolerance to decide a tangency; the
eigenproblem has no such parameter, which is why it is used here.

The elimination is degenerate for some special geometries (``Q`` rank-deficient or the
pencil singular, e.g. the PUMA); :func:`general_solver` checks both on a probe pose and tries
the chain run backwards before refusing with :class:`~redik.core.exceptions.ModelError`;
a split is used only if it also finds the generating configuration of :data:`PROBES` seeded
targets (a regular pencil is not always enough: see :func:`_misses`).
Arms with one pair of intersecting or parallel axes anywhere (no decomposition class fits
them) are not degenerate, forwards or backwards (``tests/test_analytic_general.py``), so this
module is also the "1-D search" class of IK-Geo, without a search. Labels are ``"root1"``…
by increasing θ3 of the chain the elimination ran on.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.linalg

from redik.core.exceptions import InvalidInput, ModelError
from redik.lie import se3_exp, wrap_angle
from redik.solvers.analytic import _checks
from redik.solvers.analytic.chain import hadamard_ratio, newton
from redik.solvers.analytic.geometry import Chain, pack, perpendicular, screws_of
from redik.solvers.analytic.results import (
    DEFAULT_TOL,
    DUPLICATE_TOL,
    Candidate,
    IKSolutions,
    finalize,
    unreachable,
)

#: A solution's FK must match the target to this (m, and rotation-matrix entries).
VERIFY_TOL = 1e-9

REVOLUTE = np.ones(6, bool)

if TYPE_CHECKING:
    from redik.kinematics.robot import Robot

#: Most solutions a 6R arm can have (Lee & Liang 1988; Raghavan & Roth 1993).
MAX_SOLUTIONS = 16

#: An eigenvalue is taken as a real root when the imaginary part of its angle
#: ``2 atan(x3)`` is below this (rad). A double root splits into a complex pair of about
#: √ε·cond; a spurious candidate is rejected by the FK check anyway.
IMAGINARY_TOL = 1e-3

#: Eigenvalues closer than this (rad, in θ3) are one root of multiplicity k (step 4).
CLUSTER_TOL = 1e-6

#: Gauss–Newton steps polishing a candidate, and the FK error at which they stop early.
NEWTON_STEPS = 8
NEWTON_STOP = 1e-14

#: A solution whose Jacobian has ``σ_min/σ_max`` below this is reported as singular.
SINGULAR_TOL = 1e-6

#: Two polished solutions closer than this per joint (rad) are the same one.
MERGE_TOL = 1e-7

#: Smallest singular-value ratio of ``Q`` and of the pencil at a probe point for the
#: elimination to count as non-degenerate (step 3).
RANK_TOL = 1e-9

#: Targets (FK of seeded random q) whose generating configuration the solver must find on an
#: arm before it is used there (:func:`general_solver`).
PROBES = 4

#: Half-angle offsets of θ3, θ4, θ5: ``x = tan((θ − offset)/2)`` (any fixed values that no
#: special geometry singles out).
OFFSETS = (0.6180339887, 1.4142135624 - 1.0, 2.7182818285 - 2.0)

_GRID = np.array([0.0, 2.0 * np.pi / 3.0, 4.0 * np.pi / 3.0])
#: ``_BASIS[g, b]``: the basis ``(1, cos, sin)`` at the grid angle ``g``; its inverse maps
#: three samples to coefficients.
_BASIS = np.stack([np.ones(3), np.cos(_GRID), np.sin(_GRID)], axis=1)
_FROM_SAMPLES = np.linalg.inv(_BASIS)
#: ``(1, cos ψ, sin ψ)·(1 + x²)`` as coefficients of ``(1, x, x²)``, ``x = tan(ψ/2)``.
_HALF_ANGLE = np.array([[1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [0.0, 2.0, 0.0]])
#: Where c1, s1, c2, s2 sit in ``S`` (products ``{1, c1, s1} ⊗ {1, c2, s2}`` minus the 1).
_C1, _S1, _C2, _S2 = 2, 5, 0, 1


@dataclass(frozen=True)
class DH:
    """A standard DH table (``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``) equal to a screw chain:
    ``T(q) = base · A_1(q_1 + offset_1) ⋯ A_6(q_6 + offset_6) · tool``."""

    d: np.ndarray
    a: np.ndarray
    alpha: np.ndarray
    offset: np.ndarray
    base: np.ndarray
    tool: np.ndarray


def _link(theta: np.ndarray, d: float, a: float, alpha: float) -> np.ndarray:
    """``A(θ)`` for an array of θ: shape (..., 4, 4) — :func:`redik.models.dh.row_transform`
    (standard convention) written out, so that a grid of angles takes one call."""
    theta = np.asarray(theta, dtype=float)
    c, s = np.cos(theta), np.sin(theta)
    ca, sa = np.cos(alpha), np.sin(alpha)
    A = np.zeros((*theta.shape, 4, 4))
    A[..., 0, 0], A[..., 0, 1], A[..., 0, 2], A[..., 0, 3] = c, -s * ca, s * sa, a * c
    A[..., 1, 0], A[..., 1, 1], A[..., 1, 2], A[..., 1, 3] = s, c * ca, -c * sa, a * s
    A[..., 2, 1], A[..., 2, 2], A[..., 2, 3] = sa, ca, d
    A[..., 3, 3] = 1.0
    return A


def _inverse(T: np.ndarray) -> np.ndarray:
    """Inverse of rigid transforms (..., 4, 4): :func:`redik.lie.inverse` on a stack."""
    inverse = np.zeros_like(T)
    R = np.swapaxes(T[..., :3, :3], -1, -2)
    inverse[..., :3, :3] = R
    inverse[..., :3, 3] = -np.einsum("...ij,...j->...i", R, T[..., :3, 3])
    inverse[..., 3, 3] = 1.0
    return inverse


def _frame(x: np.ndarray, z: np.ndarray, origin: np.ndarray) -> np.ndarray:
    F = np.eye(4)
    F[:3, 0], F[:3, 1], F[:3, 2], F[:3, 3] = x, np.cross(z, x), z, origin
    return F


def dh_of_chain(chain: Chain) -> DH:
    r"""The standard DH table of a 6R chain by the common normals of consecutive axes at
    q = 0 (Spong, Hutchinson & Vidyasagar 2006, §3.2): frame ``i`` has ``z_i`` on axis
    ``i + 1``, its origin where the common normal of axes ``i`` and ``i + 1`` meets axis
    ``i + 1`` and ``x_i`` along that normal (``z_{i−1} × z_i`` when they meet; from axis
    ``i`` to axis ``i + 1`` when parallel). Frame 6 is frame 5 turned by θ6 (a6 = d6 = α6 =
    0), so the last link is a pure rotation; the rest of the flange is ``tool``."""
    h, a = chain.h, chain.a
    z = [h[0]]
    # Frame 0: on axis 1 at the foot of its common normal with axis 2, x0 any perpendicular.
    origin = _closest_on_first(a[0], h[0], a[1], h[1])
    x = [perpendicular(h[0])]
    origins = [origin]
    d, lengths, alpha, offset = np.zeros(6), np.zeros(6), np.zeros(6), np.zeros(6)
    for i in range(1, 6):
        previous_z, previous_origin = z[-1], origins[-1]
        foot_previous = _closest_on_first(a[i - 1], h[i - 1], a[i], h[i])
        foot = _closest_on_first(a[i], h[i], a[i - 1], h[i - 1])
        normal = np.cross(previous_z, h[i])
        if np.linalg.norm(normal) > 1e-12:
            gap = foot - foot_previous
            x_i = gap / np.linalg.norm(gap) if np.linalg.norm(gap) > 1e-12 else normal
            x_i = x_i / np.linalg.norm(x_i)
        else:  # parallel: the normal through the previous origin
            foot_previous = previous_origin
            foot = a[i] + h[i] * ((previous_origin - a[i]) @ h[i])
            gap = foot - foot_previous
            x_i = gap / np.linalg.norm(gap)
        d[i - 1] = (foot_previous - previous_origin) @ previous_z
        lengths[i - 1] = (foot - foot_previous) @ x_i
        alpha[i - 1] = np.arctan2(np.cross(previous_z, h[i]) @ x_i, previous_z @ h[i])
        offset[i - 1] = np.arctan2(np.cross(x[-1], x_i) @ previous_z, x[-1] @ x_i)
        z.append(h[i])
        x.append(x_i)
        origins.append(foot)
    base = _frame(x[0], z[0], origins[0])
    last = _frame(x[-1], z[-1], origins[-1])
    return DH(d, lengths, alpha, offset, base, _inverse(last) @ chain.M)


def _closest_on_first(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray):
    """The point of line ``(p1, u1)`` closest to line ``(p2, u2)`` (p1 if parallel)."""
    w = p1 - p2
    b = u1 @ u2
    denominator = 1.0 - b * b
    if denominator < 1e-24:
        return p1.copy()
    s = (b * (u2 @ w) - (u1 @ w)) / denominator
    return p1 + s * u1


def _fourteen(p: np.ndarray, l: np.ndarray) -> np.ndarray:
    """The 14 quantities of step 2 from positions and axes (..., 3): shape (..., 14)."""
    pp = np.einsum("...i,...i->...", p, p)[..., None]
    pl = np.einsum("...i,...i->...", p, l)[..., None]
    return np.concatenate([p, l, pp, pl, np.cross(p, l), pp * l - 2.0 * pl * p], axis=-1)


def _offset_basis(offset: float) -> np.ndarray:
    """``K`` with ``(1, cos θ, sin θ) = K (1, cos ψ, sin ψ)`` for ``θ = offset + ψ``."""
    c, s = np.cos(offset), np.sin(offset)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


@dataclass(frozen=True)
class Elimination:
    """The target-independent part of steps 1–3 for one (scaled) chain: the DH table and
    the coefficients of the left side, ``left[b3, b4, b5, k]`` over the bases
    ``(1, cos, sin)`` of θ3, θ4, θ5, ``k`` the 14 quantities."""

    dh: DH
    left: np.ndarray
    #: ``(1, cos θ, sin θ)(1 + x²)`` as powers of the shifted half-angle tangent, per angle.
    powers: tuple[np.ndarray, np.ndarray, np.ndarray]

    @classmethod
    def of(cls, dh: DH) -> Elimination:
        g3, g4, g5 = np.meshgrid(_GRID, _GRID, _GRID, indexing="ij")
        chain = (
            _link(g3, dh.d[2], dh.a[2], dh.alpha[2])
            @ _link(g4, dh.d[3], dh.a[3], dh.alpha[3])
            @ _link(g5, dh.d[4], dh.a[4], dh.alpha[4])
        )
        samples = _fourteen(chain[..., :3, 3], chain[..., :3, 2])
        left = np.einsum("ag,bh,ci,ghik->abck", *(_FROM_SAMPLES,) * 3, samples)
        powers = tuple(_offset_basis(offset) @ _HALF_ANGLE for offset in OFFSETS)
        return cls(dh, left, powers)  # type: ignore[arg-type]

    def right(self, T: np.ndarray) -> np.ndarray:
        """``right[b1, b2, k]``: the coefficients of :math:`A_2^{-1} A_1^{-1} T A_6^{-1}`'s 14
        quantities over the bases of θ1, θ2 (``A_6^{-1}`` keeps ``z`` and the origin)."""
        dh = self.dh
        g1, g2 = np.meshgrid(_GRID, _GRID, indexing="ij")
        back = _inverse(
            _link(g1, dh.d[0], dh.a[0], dh.alpha[0]) @ _link(g2, dh.d[1], dh.a[1], dh.alpha[1])
        )
        p = np.einsum("...ij,j->...i", back[..., :3, :3], T[:3, 3]) + back[..., :3, 3]
        l = np.einsum("...ij,j->...i", back[..., :3, :3], T[:3, 2])
        return np.einsum("ag,bh,ghk->abk", _FROM_SAMPLES, _FROM_SAMPLES, _fourteen(p, l))

    def pencil(self, T: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        """Step 3 for the DH-frame target ``T``: ``(Q, constant, (M0, M1, M2), rank)``,
        ``rank`` the smallest singular value of ``Q`` over its largest."""
        right = self.right(T)
        Q = right.reshape(9, 14)[1:].T
        left = self.left.copy()
        left[0, 0, 0] -= right[0, 0]
        U, sigma, _ = np.linalg.svd(Q)
        N = U[:, 8:].T
        reduced = np.einsum("ek,abck->eabc", N, left)
        w3, w4, w5 = self.powers
        poly = np.einsum("eabc,ax,by,cz->exyz", reduced, w3, w4, w5)
        M = np.zeros((3, 12, 12))
        for shift in range(2):
            for i in range(3):
                for j in range(3):
                    M[:, shift * 6 : shift * 6 + 6, 3 * (i + shift) + j] = poly[:, :, i, j].T
        M /= np.abs(M).max(axis=(0, 2))[None, :, None]  # row balance
        return Q, right[0, 0], M, float(sigma[-1] / sigma[0])

    def left_at(self, theta3: float, theta4: float, theta5: float) -> np.ndarray:
        """The 14 left-side quantities at θ3, θ4, θ5 (from the coefficients)."""
        b3, b4, b5 = (np.array([1.0, np.cos(t), np.sin(t)]) for t in (theta3, theta4, theta5))
        partial = (b3 @ self.left.reshape(3, 126)).reshape(3, 42)
        return b5 @ (b4 @ partial).reshape(3, 14)


def _angles(alpha: np.ndarray, beta: np.ndarray) -> np.ndarray:
    """``2 atan(α/β)`` of homogeneous eigenvalues, complex, finite at β = 0."""
    angles = np.empty(alpha.shape, complex)
    small = np.abs(alpha) <= np.abs(beta)
    # The spurious roots x = ±i of (1 + x²) are arctan's poles: non-finite, then dropped.
    with np.errstate(divide="ignore", invalid="ignore"):
        angles[small] = 2.0 * np.arctan(alpha[small] / beta[small])
        ratio = beta[~small] / alpha[~small]
        sign = np.where(ratio.real >= 0.0, 1.0, -1.0)
        angles[~small] = sign * np.pi - 2.0 * np.arctan(ratio)
    return angles


def _ratio_angle(high: np.ndarray, low: np.ndarray) -> float:
    """``2 atan(x)`` for ``high ≈ x · low`` (least squares, finite at x = ∞)."""
    return 2.0 * float(np.arctan2(high.ravel() @ low.ravel(), low.ravel() @ low.ravel()))


def _monomials(M: np.ndarray, x: float, k: int) -> list[np.ndarray]:
    """The monomial vectors ``m`` (12,) of the k-fold root ``x`` (step 4)."""
    matrix = M[0] + x * M[1] + x * x * M[2] if abs(x) <= 1.0 else M[2] + M[1] / x + M[0] / x**2
    _, _, Vt = np.linalg.svd(matrix)
    V = Vt[-k:].T
    if k == 1:
        return [V[:, 0]]
    grid = V.reshape(4, 3, k)
    low, high = grid[:3].reshape(9, k), grid[1:].reshape(9, k)
    shift = np.linalg.lstsq(low, high, rcond=None)[0]
    _, vectors = np.linalg.eig(shift)
    return [(V @ vectors[:, c]).real for c in range(k)]


@dataclass(frozen=True)
class GeneralSolver:
    """Every solution of a general 6R arm (module docstring); make one with
    :func:`general_solver` or :func:`redik.solvers.analytic.solver_for`.

    Attributes:
        chain: The screw chain solved (the robot's, or run backwards if ``reversed``).
        reversed: Whether the elimination runs on the chain backwards (for ``T⁻¹``).
        scale: The length (m) the chain is divided by before the elimination.
        elimination: Steps 1–3's target-independent part, on the scaled chain.
        lower, upper: The joint limits applied by default.
        kind: ``"general"`` (no closed-form class); ``method``: ``"elimination"``.
    """

    chain: Chain
    reversed: bool
    scale: float
    elimination: Elimination
    geometry: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    kind: str = "general"
    method: str = "elimination"

    def __call__(
        self, target: Any, *, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> IKSolutions:
        """Every solution of a world-frame target pose, labelled ``"root1"``… (``limits``:
        ``"robot"``, None or ``(lower, upper)``; ``tol`` is unused: every solution is exact
        to :data:`~redik.solvers.analytic.decomposed.VERIFY_TOL`, and kept for the common
        signature)."""
        T = _checks.pose(target, "target", strict=strict)
        _checks.length(tol, "tol", allow_zero=True)
        lower, upper = self._limits(limits)
        q, conditions = self._solve(T)
        if len(q) == 0:
            return unreachable(
                6, "no real root of the degree-16 elimination reaches the target (out of reach)"
            )
        candidates = [
            Candidate(row, f"root{i + 1}", _singular_text(conditions[i])) for i, row in enumerate(q)
        ]
        bounded = np.isfinite(lower).any() or np.isfinite(upper).any()
        return finalize(candidates, 6, REVOLUTE, (lower, upper) if bounded else None)

    def raw(
        self, T: np.ndarray, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> np.ndarray:
        """Every solution as a (k, 6) array (the solutions of :meth:`__call__`, no labels)."""
        return self(T, limits=limits, tol=tol, strict=strict).as_array()

    def solve(self, T: np.ndarray) -> np.ndarray:
        """Every solution of the validated pose ``T`` (4 × 4), no limits: (k, 6), wrapped to
        (−π, π], in increasing θ3 of the eliminated chain, each verified by FK."""
        return self._solve(T)[0]

    def _solve(self, T: np.ndarray) -> tuple[np.ndarray, list[float]]:
        """:meth:`solve` and each solution's Jacobian condition ``σ_min/σ_max``."""
        target = np.linalg.inv(T) if self.reversed else T
        scaled = target.copy()
        scaled[:3, 3] /= self.scale
        dh = self.elimination.dh
        local = _inverse(dh.base) @ scaled @ _inverse(dh.tool)
        Q, constant, M, _ = self.elimination.pencil(local)
        candidates = self._candidates(local, np.linalg.pinv(Q), constant, M)
        found: list[np.ndarray] = []
        conditions: list[float] = []
        for theta in candidates:
            row = np.zeros(18)
            row[:6] = theta - dh.offset
            row[6:12], row[12:] = np.cos(row[:6]), np.sin(row[:6])
            error = newton(self.geometry, row, target, -1, NEWTON_STEPS, NEWTON_STOP)
            if error > VERIFY_TOL:
                continue
            q = np.arctan2(row[12:], row[6:12])
            if all(np.abs(wrap_angle(q - other)).max() > MERGE_TOL for other in found):
                found.append(q)
                conditions.append(hadamard_ratio(self.geometry, row, self.scale))
        q = np.array(found).reshape(-1, 6)
        return (q[:, ::-1].copy() if self.reversed else q), conditions

    def _candidates(
        self, T: np.ndarray, Q_pinv: np.ndarray, constant: np.ndarray, M: np.ndarray
    ) -> list[np.ndarray]:
        """DH joint angles (θ1…θ6) of every real root of the pencil (steps 3–4); ``Q_pinv``
        the pseudo-inverse of ``Q`` (the least squares of step 4, once per target)."""
        zeros = np.zeros((12, 12))
        identity = np.eye(12)
        A = np.block([[zeros, identity], [-M[0], -M[1]]])
        B = np.block([[identity, zeros], [zeros, M[2]]])
        alpha, beta = scipy.linalg.eig(A, B, right=False, homogeneous_eigvals=True)
        finite = (np.abs(alpha) > 1e-300) | (np.abs(beta) > 1e-300)
        psi = _angles(alpha[finite], beta[finite])
        real = np.sort(psi[np.isfinite(psi) & (np.abs(psi.imag) <= IMAGINARY_TOL)].real)
        dh = self.elimination.dh
        w3_offset, w4_offset, w5_offset = OFFSETS
        candidates = []
        start = 0
        while start < len(real):
            stop = start + 1
            while stop < len(real) and real[stop] - real[start] <= CLUSTER_TOL:
                stop += 1
            psi3 = float(real[start:stop].mean())
            for m in _monomials(M, float(np.tan(psi3 / 2.0)), stop - start):
                grid = m.reshape(4, 3)
                theta3 = w3_offset + psi3
                theta4 = w4_offset + _ratio_angle(grid[1:], grid[:3])
                theta5 = w5_offset + _ratio_angle(grid[:, 1:], grid[:, :2])
                rhs = self.elimination.left_at(theta3, theta4, theta5) - constant
                S = Q_pinv @ rhs
                theta1 = np.arctan2(S[_S1], S[_C1])
                theta2 = np.arctan2(S[_S2], S[_C2])
                theta = np.array([theta1, theta2, theta3, theta4, theta5, 0.0])
                first_five = _link(theta[0], dh.d[0], dh.a[0], dh.alpha[0])
                for i in range(1, 5):
                    first_five = first_five @ _link(theta[i], dh.d[i], dh.a[i], dh.alpha[i])
                last = _inverse(first_five) @ T
                theta[5] = np.arctan2(last[1, 0], last[0, 0])
                candidates.append(theta)
            start = stop
        return candidates

    def _limits(self, limits: Any) -> tuple[np.ndarray, np.ndarray]:
        if isinstance(limits, str):
            if limits != "robot":
                raise InvalidInput(
                    f"limits must be 'robot', None or (lower, upper), got {limits!r}"
                )
            return self.lower, self.upper
        if limits is None:
            return np.full(6, -np.inf), np.full(6, np.inf)
        checked = _checks.limits(limits, 6)
        assert checked is not None
        return checked


def _singular_text(condition: float) -> str:
    """The ``singular`` text of a solution whose Jacobian has ``σ_min/σ_max = condition``
    ('' above :data:`SINGULAR_TOL`): there two roots of the elimination meet (a double root)
    and the arm can move without moving the tool, to first order."""
    if condition >= SINGULAR_TOL:
        return ""
    return (
        f"at a singularity (σ_min/σ_max of the Jacobian {condition:.1e}): two of the "
        "elimination's roots meet here"
    )


def _scale(chain: Chain) -> float:
    """A length of the arm (m): the largest distance of an axis point or the flange from the
    first axis point, so that the scaled chain has lengths of order 1."""
    points = np.vstack([chain.a, chain.M[:3, 3]])
    return max(float(np.abs(points - chain.a[0]).max()), 1e-6)


def _scaled(chain: Chain, scale: float) -> Chain:
    M = chain.M.copy()
    M[:3, 3] /= scale
    return Chain(chain.h, chain.a / scale, M)


def _degeneracy(elimination: Elimination, chain: Chain) -> str:
    """Why the elimination is degenerate for this (scaled) chain on a probe pose ('' if not):
    ``Q`` rank-deficient or the pencil singular."""
    rng = np.random.default_rng(0)
    dh = elimination.dh
    for _ in range(2):
        theta = rng.uniform(-np.pi, np.pi, 6)
        T = _link(theta[0], dh.d[0], dh.a[0], dh.alpha[0])
        for i in range(1, 6):
            T = T @ _link(theta[i], dh.d[i], dh.a[i], dh.alpha[i])
        _, _, M, rank = elimination.pencil(T)
        if rank < RANK_TOL:
            return "the target's 14 × 8 matrix Q is rank-deficient"
        x = rng.uniform(-1.0, 1.0)
        sigma = np.linalg.svd(M[0] + x * M[1] + x * x * M[2], compute_uv=False)
        if sigma[-1] < RANK_TOL * sigma[0]:
            return "the 12 × 12 pencil is singular for every x3"
    return ""


def _misses(solver: GeneralSolver, S: np.ndarray, M: np.ndarray) -> str:
    """Why the solver cannot be trusted on this arm ('' if it can): it must find the
    configuration that generated each of :data:`PROBES` seeded targets. A regular pencil is
    not enough on every geometry (three consecutive parallel axes can keep it regular yet
    lose roots), and this costs a few ms once per arm."""
    rng = np.random.default_rng(1)
    for _ in range(PROBES):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = M
        for i in reversed(range(6)):
            T = se3_exp(np.concatenate([S[3:, i], S[:3, i]]) * q[i]) @ T
        found = solver.solve(T)
        if not len(found) or np.abs(wrap_angle(found - q)).max(axis=1).min() > 1e-6:
            return "it misses the configuration that generated a probe target"
    return ""


def general_solver(
    S: np.ndarray,
    M: np.ndarray,
    lower: np.ndarray | None = None,
    upper: np.ndarray | None = None,
) -> GeneralSolver:
    """The all-solutions solver of the 6R chain with space screws ``S`` (6 × 6, (ω, v)
    columns) and home pose ``M``.

    Raises:
        ModelError: A joint is prismatic, or the elimination is degenerate for this geometry
            both forwards and backwards, or misses a probe target's configuration (module
            docstring).
    """
    S = _checks.finite_array(S, "S", (6, 6))
    M = _checks.pose(M, "M")
    prismatic = np.flatnonzero(np.linalg.norm(S[:3], axis=0) < 0.5)
    if prismatic.size:
        raise ModelError(
            f"joint(s) {(prismatic + 1).tolist()} are prismatic; the general 6R solver takes "
            "revolute joints only"
        )
    chain = Chain.from_screws(S, M)
    reasons = []
    for reverse, candidate in ((False, chain), (True, chain.reversed())):
        scale = _scale(candidate)
        elimination = Elimination.of(dh_of_chain(_scaled(candidate, scale)))
        reason = _degeneracy(elimination, candidate)
        if not reason:
            lower = np.full(6, -np.inf) if lower is None else np.asarray(lower, float).copy()
            upper = np.full(6, np.inf) if upper is None else np.asarray(upper, float).copy()
            geometry = pack(candidate, candidate.a, candidate.h[5])
            solver = GeneralSolver(candidate, reverse, scale, elimination, geometry, lower, upper)
            reason = _misses(solver, S, M)
            if not reason:
                return solver
        reasons.append(reason)
    raise ModelError(
        "the Raghavan–Roth elimination is degenerate for this 6R arm "
        f"(forwards: {reasons[0]}; backwards: {reasons[1]}); arms with intersecting or "
        "parallel axes have closed forms in redik.solvers.analytic.decomposed"
    )


def solver_from_robot(robot: Robot) -> GeneralSolver:
    """:func:`general_solver` for a 6R :class:`redik.Robot` and its joint limits."""
    if robot.dof != 6 or not robot.revolute.all():
        raise ModelError(f"{robot.name!r}: the general solver takes 6 revolute joints")
    S, M = screws_of(robot)
    return general_solver(S, M, robot.lower, robot.upper)


__all__ = ["DUPLICATE_TOL", "GeneralSolver", "general_solver", "solver_from_robot"]
