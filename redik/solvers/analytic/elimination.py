r"""Every solution of a 6R arm by the Raghavan–Roth elimination, compiled up to one eigenproblem.

A 6R arm with no closed form still has finitely many solutions, at most 16 (Primrose 1986;
Lee & Liang 1988): the real roots of a degree-16 polynomial in a half-angle tangent.
Raghavan & Roth ("Inverse kinematics of the general 6R manipulator and related linkages",
ASME J. Mech. Des. 115, 1993) find them by a dialytic elimination, solved here as an
eigenproblem as Manocha & Canny do ("Efficient inverse kinematics for general 6R
manipulators", IEEE Trans. Robot. Autom. 10(5), 1994):

1. The chain is written in standard Denavit–Hartenberg form,
   :math:`A_i = R_z(θ_i) T_z(d_i) T_x(a_i) R_x(α_i)`, from its screw axes (common normals at
   q = 0, :func:`dh_of_chain`), and the loop :math:`A_1 ⋯ A_6 = T` is split into a *left*
   triple of links and a *right* side with two links on each side of the target:

   - the standard split :math:`A_3 A_4 A_5 = A_2^{-1} A_1^{-1}\, T\, A_6^{-1}`;
   - the split re-based through the target link,
     :math:`A_2 A_3 A_4 = A_1^{-1}\, T\, A_6^{-1} A_5^{-1}` (the loop read from another
     link: :math:`A_6 T^{-1} A_1 ⋯ A_5 = I`), for arms whose every standard split is
     degenerate (special pairs at both ends: the Jaco).

   The z axis and origin of the last inverted link do not depend on its angle, so the axis
   ``l`` and position ``p`` of both sides give six equations free of that angle.
2. With them, ``p·p``, ``p·l``, ``p × l`` and ``(p·p) l − 2 (p·l) p``: fourteen equations
   :math:`P(θ_a)\,R = Q\,S`, ``R`` the nine products of the other two left angles' ``{1, c, s}``,
   ``S`` the eight non-constant products of the two right angles' ``{1, c, s}``, ``P``
   linear in the first left angle and ``Q`` fixed by the target. The coefficients are read
   off exactly by the three-point Fourier transform of each side in each angle (a function
   linear in ``{1, cos θ, sin θ}`` is fixed by its values at θ = 0, 2π/3, 4π/3).
3. ``Q`` (14 × 8) has a 6-dimensional left null space ``N`` (Householder QR): ``N P R = 0``
   are six equations in the three left angles alone, of degree 2 in each half-angle tangent
   (each shifted by a fixed offset so that no solution of a generic target sits at the
   tangent's pole). Any of the three may be the hidden variable (Manocha & Canny, §3): with
   the six equations multiplied by the second tangent they form :math:`M(x) m = 0`, ``M``
   12 × 12 quadratic in the hidden ``x``, ``m`` the monomials :math:`y^i z^j` (i ≤ 3, j ≤ 2).
   ``det M(x) = 0`` is the degree-16 polynomial (times :math:`(1 + x^2)^4`), solved without
   forming it: after the Möbius change :math:`x = x_0 + 1/y` (``M(x0)`` regular) the
   quadratic pencil is a 24 × 24 companion matrix, whose eigenvalues are one
   ``numpy.linalg.eigvals`` call — the one step not compiled.
4. Each real root (imaginary part of its angle within :data:`IMAGINARY_TOL`, so that a
   double root split by rounding is kept) gives ``m`` from the null vector of :math:`M(x)`
   (inverse iteration) and the other two left angles from ratios of its entries; the two
   right angles from ``Q S = P R`` (by the QR of ``Q``) and the last angle from the
   remaining link. Roots closer than :data:`CLUSTER_TOL` are one root of multiplicity k: its
   k-dimensional null space is split by the shift of the second tangent (a k × k
   eigenproblem, :func:`monomials_of`).
5. Every candidate is polished by damped Gauss–Newton on the screw chain's FK
   (:func:`redik.solvers.analytic.chain.newton`) and kept only if it reaches the target
   within :data:`VERIFY_TOL`; duplicates are merged. Each solution carries the Hadamard
   ratio of its Jacobian (:func:`redik.solvers.analytic.chain.hadamard_ratio`): 0 where two
   roots meet.

The elimination has no sampling density and no tolerance for a tangency: every real root
of the degree-16 problem is an eigenvalue. IK-Geo's searches (Elias & Wen 2022, §IV-C: sample
one or two joint angles, reduce the rest to subproblems, find the zeros of an error
function) can miss a pair of roots closer than their grid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from redik.kinematics.compiled import COMPILE
from redik.solvers.analytic.chain import hadamard_ratio, inverse, newton, wrap
from redik.solvers.analytic.geometry import Chain, pack, perpendicular
from redik.solvers.analytic.vectors import cross, dot

#: A solution's FK must match the target to this (m, and rotation-matrix entries).
VERIFY_TOL = 1e-9

#: Most solutions a 6R arm can have (Lee & Liang 1988; Raghavan & Roth 1993).
MAX_SOLUTIONS = 16

#: An eigenvalue is taken as a real root when the imaginary part of its angle is below this
#: (rad): a double root splits into a complex pair of about √ε·cond.
IMAGINARY_TOL = 1e-3

#: Real roots closer than this (rad) are one root of multiplicity k (step 4).
CLUSTER_TOL = 1e-6

#: Damped Gauss–Newton steps polishing a candidate, and the FK error at which they stop.
POLISH_STEPS = 8
POLISH_STOP = 1e-14

#: Two polished solutions closer than this per joint (rad) are the same one.
MERGE_TOL = 1e-7

#: Half-angle offsets of the three left angles: ``x = tan((θ − offset)/2)`` (fixed values no
#: special geometry singles out).
OFFSETS = (0.6180339887, 1.4142135624 - 1.0, 2.7182818285 - 2.0)

#: The Möbius centre ``x0`` of each hidden variable (``x = x0 + 1/y``).
MOBIUS = (0.7548776662, -1.3247179572, 2.2055694304)

#: The splits of step 1.
SPLITS = ("standard", "rebased")

_GRID = np.array([0.0, 2.0 * np.pi / 3.0, 4.0 * np.pi / 3.0])
#: The inverse of ``[1, cos g, sin g]`` at the grid angles: samples → coefficients.
_FROM_SAMPLES = np.linalg.inv(np.stack([np.ones(3), np.cos(_GRID), np.sin(_GRID)], axis=1))
#: ``(1, cos ψ, sin ψ)·(1 + x²)`` as coefficients of ``(1, x, x²)``, ``x = tan(ψ/2)``.
_HALF_ANGLE = np.array([[1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [0.0, 2.0, 0.0]])


# --------------------------------------------------------------------------------------
# The DH table of a chain (step 1)


@dataclass(frozen=True)
class DH:
    """A standard DH table equal to a screw chain.

    A standard DH table equal to a screw chain:
    ``T(q) = base · A_1(q_1 + offset_1) ⋯ A_6(q_6 + offset_6) · tool``.

    Attributes:
        d, a, alpha, offset: (6,) each.
        base, tool: (4, 4).
    """

    d: np.ndarray
    a: np.ndarray
    alpha: np.ndarray
    offset: np.ndarray
    base: np.ndarray
    tool: np.ndarray

    def links(self, i: int, theta: np.ndarray) -> np.ndarray:
        """The link transforms ``A_i(θ)`` on a grid of angles.

        ``A_i(θ)`` for an array of θ: shape (..., 4, 4)
        (:func:`redik.models.dh.row_transform`, standard convention, on a grid).
        """
        theta = np.asarray(theta, dtype=float)
        c, s = np.cos(theta), np.sin(theta)
        ca, sa = np.cos(self.alpha[i]), np.sin(self.alpha[i])
        A = np.zeros((*theta.shape, 4, 4))
        A[..., 0, 0], A[..., 0, 1], A[..., 0, 2] = c, -s * ca, s * sa
        A[..., 1, 0], A[..., 1, 1], A[..., 1, 2] = s, c * ca, -c * sa
        A[..., 0, 3], A[..., 1, 3] = self.a[i] * c, self.a[i] * s
        A[..., 2, 1], A[..., 2, 2], A[..., 2, 3] = sa, ca, self.d[i]
        A[..., 3, 3] = 1.0
        return A


def inverse_stack(T: np.ndarray) -> np.ndarray:
    """Inverses of rigid transforms (..., 4, 4)."""
    result = np.zeros_like(T)
    R = np.swapaxes(T[..., :3, :3], -1, -2)
    result[..., :3, :3] = R
    result[..., :3, 3] = -np.einsum("...ij,...j->...i", R, T[..., :3, 3])
    result[..., 3, 3] = 1.0
    return result


def _frame(x: np.ndarray, z: np.ndarray, origin: np.ndarray) -> np.ndarray:
    F = np.eye(4)
    F[:3, 0], F[:3, 1], F[:3, 2], F[:3, 3] = x, np.cross(z, x), z, origin
    return F


def _closest_on_first(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray):
    """The point of line ``(p1, u1)`` closest to line ``(p2, u2)`` (p1 if parallel)."""
    w = p1 - p2
    b = u1 @ u2
    denominator = 1.0 - b * b
    if denominator < 1e-24:
        return p1.copy()
    return p1 + (b * (u2 @ w) - (u1 @ w)) / denominator * u1


def _common_normal(
    h: np.ndarray, a: np.ndarray, i: int, z: np.ndarray, origin: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The common normal of two consecutive axes.

    ``(foot on axis i − 1, foot on axis i, x_i)``: the common normal of axes i − 1 and i
    (through the previous origin when they are parallel) and its direction.
    """
    foot_previous = _closest_on_first(a[i - 1], h[i - 1], a[i], h[i])
    foot = _closest_on_first(a[i], h[i], a[i - 1], h[i - 1])
    normal = np.cross(z, h[i])
    if np.linalg.norm(normal) <= 1e-12:  # parallel
        foot_previous = origin
        foot = a[i] + h[i] * ((origin - a[i]) @ h[i])
        gap = foot - foot_previous
        return foot_previous, foot, gap / np.linalg.norm(gap)
    gap = foot - foot_previous
    x_i = gap if np.linalg.norm(gap) > 1e-12 else normal
    return foot_previous, foot, x_i / np.linalg.norm(x_i)


def dh_of_chain(chain: Chain) -> DH:
    """The standard DH table of a 6R chain (step 1).

    The standard DH table of a 6R chain by the common normals of consecutive axes at
    q = 0 (Spong, Hutchinson & Vidyasagar 2006, §3.2).

    Frame ``i`` has ``z_i`` on axis ``i + 1``, its origin where the common normal of axes
    ``i`` and ``i + 1`` meets axis ``i + 1`` and ``x_i`` along that normal
    (``z_{i−1} × z_i`` when they meet; from axis ``i`` to axis ``i + 1`` when parallel).
    Frame 6 is frame 5 turned by θ6 (a6 = d6 = α6 = 0), so the last link is a pure
    rotation; the rest of the flange is ``tool``.
    """
    h, a = chain.h, chain.a
    z, x = [h[0]], [perpendicular(h[0])]
    origins = [_closest_on_first(a[0], h[0], a[1], h[1])]
    d, lengths, alpha, offset = np.zeros(6), np.zeros(6), np.zeros(6), np.zeros(6)
    for i in range(1, 6):
        foot_previous, foot, x_i = _common_normal(h, a, i, z[-1], origins[-1])
        d[i - 1] = (foot_previous - origins[-1]) @ z[-1]
        lengths[i - 1] = (foot - foot_previous) @ x_i
        alpha[i - 1] = np.arctan2(np.cross(z[-1], h[i]) @ x_i, z[-1] @ h[i])
        offset[i - 1] = np.arctan2(np.cross(x[-1], x_i) @ z[-1], x[-1] @ x_i)
        z.append(h[i])
        x.append(x_i)
        origins.append(foot)
    last = _frame(x[-1], z[-1], origins[-1])
    return DH(
        d, lengths, alpha, offset, _frame(x[0], z[0], origins[0]), inverse_stack(last) @ chain.M
    )


def fourteen(p: np.ndarray, l: np.ndarray) -> np.ndarray:
    """The 14 quantities of step 2 from positions and axes (..., 3): shape (..., 14)."""
    pp = np.einsum("...i,...i->...", p, p)[..., None]
    pl = np.einsum("...i,...i->...", p, l)[..., None]
    return np.concatenate([p, l, pp, pl, np.cross(p, l), pp * l - 2.0 * pl * p], axis=-1)


def _offset_basis(offset: float) -> np.ndarray:
    """``K`` with ``(1, cos θ, sin θ) = K (1, cos ψ, sin ψ)`` for ``θ = offset + ψ``."""
    c, s = np.cos(offset), np.sin(offset)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


# --------------------------------------------------------------------------------------
# Compiled: the pencil of a target (steps 2–3)


@numba.njit(**COMPILE)
def _sample(local, B, P, out):
    """The 14 quantities of one right-side sample.

    The 14 quantities of ``B · local · P`` into ``out`` (``P``: the z column and origin of
    what follows the target).
    """
    z = (
        local[0, 0] * P[0, 0] + local[0, 1] * P[1, 0] + local[0, 2] * P[2, 0],
        local[1, 0] * P[0, 0] + local[1, 1] * P[1, 0] + local[1, 2] * P[2, 0],
        local[2, 0] * P[0, 0] + local[2, 1] * P[1, 0] + local[2, 2] * P[2, 0],
    )
    o = (
        local[0, 0] * P[0, 1] + local[0, 1] * P[1, 1] + local[0, 2] * P[2, 1] + local[0, 3],
        local[1, 0] * P[0, 1] + local[1, 1] * P[1, 1] + local[1, 2] * P[2, 1] + local[1, 3],
        local[2, 0] * P[0, 1] + local[2, 1] * P[1, 1] + local[2, 2] * P[2, 1] + local[2, 3],
    )
    p = (
        B[0, 0] * o[0] + B[0, 1] * o[1] + B[0, 2] * o[2] + B[0, 3],
        B[1, 0] * o[0] + B[1, 1] * o[1] + B[1, 2] * o[2] + B[1, 3],
        B[2, 0] * o[0] + B[2, 1] * o[1] + B[2, 2] * o[2] + B[2, 3],
    )
    l = (
        B[0, 0] * z[0] + B[0, 1] * z[1] + B[0, 2] * z[2],
        B[1, 0] * z[0] + B[1, 1] * z[1] + B[1, 2] * z[2],
        B[2, 0] * z[0] + B[2, 1] * z[1] + B[2, 2] * z[2],
    )
    pp = dot(p, p)
    pl = dot(p, l)
    cross_pl = cross(p, l)
    for i in range(3):
        out[i], out[3 + i], out[8 + i] = p[i], l[i], cross_pl[i]
        out[11 + i] = pp * l[i] - 2.0 * pl * p[i]
    out[6], out[7] = pp, pl


@numba.njit(**COMPILE)
def _right(local, backs, posts, from_samples):
    """The right side's exact coefficients (step 2).

    ``right[b1, b2, k]``: the right side's coefficients over the bases ``(1, cos, sin)``
    of its two angles, from the 9 samples at the grid angles.
    """
    samples = np.empty((3, 3, 14))
    for g in range(3):
        for h in range(3):
            _sample(local, backs[g, h], posts[g, h], samples[g, h])
    right = np.zeros((3, 3, 14))
    for a in range(3):
        for b in range(3):
            for g in range(3):
                for h in range(3):
                    f = from_samples[a, g] * from_samples[b, h]
                    for k in range(14):
                        right[a, b, k] += f * samples[g, h, k]
    return right


@numba.njit(**COMPILE)
def _reflect(W, Qfull, v, k):
    """Apply one Householder reflection.

    Apply the Householder reflection ``I − 2vvᵀ/vᵀv`` (``v`` zero above row k) to ``W``
    from the left and to ``Qfull`` from the right.
    """
    m = W.shape[0]
    vv = 0.0
    for i in range(k, m):
        vv += v[i] * v[i]
    if vv == 0.0:
        return
    for j in range(W.shape[1]):
        s = 0.0
        for i in range(k, m):
            s += v[i] * W[i, j]
        s *= 2.0 / vv
        for i in range(k, m):
            W[i, j] -= s * v[i]
    for i in range(m):
        s = 0.0
        for j in range(k, m):
            s += Qfull[i, j] * v[j]
        s *= 2.0 / vv
        for j in range(k, m):
            Qfull[i, j] -= s * v[j]


@numba.njit(**COMPILE)
def householder(A, Qfull, R):
    """The Householder QR of a tall matrix.

    ``A`` (m × n, m > n) ``= Qfull[:, :n] R`` by Householder reflections; ``Qfull`` is
    orthogonal (m × m), its last m − n columns span the left null space of a full-rank A.
    """
    m, n = A.shape
    W = A.copy()
    Qfull[:, :] = 0.0
    for i in range(m):
        Qfull[i, i] = 1.0
    v = np.empty(m)
    for k in range(n):
        norm = 0.0
        for i in range(k, m):
            norm += W[i, k] * W[i, k]
        norm = math.sqrt(norm)
        if norm == 0.0:
            continue
        for i in range(m):
            v[i] = W[i, k] if i >= k else 0.0
        v[k] -= -norm if W[k, k] >= 0.0 else norm
        _reflect(W, Qfull, v, k)
    for i in range(n):
        for j in range(n):
            R[i, j] = W[i, j] if j >= i else 0.0


@numba.njit(**COMPILE)
def _reduced(left, constant, Qfull):
    """The six reduced equations over the left angles' bases (step 3).

    ``N (P R − const)``: the left side's coefficients times the left null space of ``Q``
    (the last 6 columns of ``Qfull``), (6, 3, 3, 3) over the bases of the three left angles.
    """
    reduced = np.zeros((6, 3, 3, 3))
    for e in range(6):
        for a in range(3):
            for b in range(3):
                for c in range(3):
                    s = 0.0
                    for k in range(14):
                        value = left[a, b, c, k]
                        if a == 0 and b == 0 and c == 0:
                            value -= constant[k]
                        s += Qfull[k, 8 + e] * value
                    reduced[e, a, b, c] = s
    return reduced


@numba.njit(**COMPILE)
def _polynomials(left, constant, Qfull, powers, hidden):
    """The six reduced equations as polynomials in the half-angle tangents.

    The six reduced equations as polynomials in the three shifted half-angle tangents,
    ``poly[e, h, s0, s1]`` with the axes ordered (hidden, first shown, second shown).
    """
    reduced = _reduced(left, constant, Qfull)
    poly = np.zeros((6, 3, 3, 3))
    index = np.empty(3, np.int64)
    order = (hidden, 1 if hidden == 0 else 0, 2 if hidden != 2 else 1)
    for e in range(6):
        for x in range(3):
            for y in range(3):
                for z in range(3):
                    s = 0.0
                    for a in range(3):
                        for b in range(3):
                            for c in range(3):
                                f = powers[0, a, x] * powers[1, b, y] * powers[2, c, z]
                                s += reduced[e, a, b, c] * f
                    index[0], index[1], index[2] = x, y, z
                    poly[e, index[order[0]], index[order[1]], index[order[2]]] = s
    return poly


@numba.njit(**COMPILE)
def _balance(M):
    """Divide each row of the pencil ``M`` (3, 12, 12) by its largest entry."""
    for r in range(M.shape[1]):
        big = 0.0
        for power in range(3):
            for c in range(M.shape[2]):
                big = max(big, abs(M[power, r, c]))
        if big > 0.0:
            for power in range(3):
                for c in range(M.shape[2]):
                    M[power, r, c] /= big


@numba.njit(**COMPILE)
def _pencil_matrices(poly):
    """The 12 × 12 quadratic pencil of the dialytic step.

    ``M[power]`` (3, 12, 12): the six equations and their multiples by the first shown
    tangent, over the 12 monomials ``y^i z^j``, rows balanced.
    """
    M = np.zeros((3, 12, 12))
    for shift in range(2):
        for i in range(3):
            for j in range(3):
                for e in range(6):
                    for power in range(3):
                        M[power, shift * 6 + e, 3 * (i + shift) + j] = poly[e, power, i, j]
    _balance(M)
    return M


@numba.njit(**COMPILE)
def lu_factor(A):
    """LU factorisation with partial pivoting.

    Factor ``A`` (n × n, overwritten by L and U) with partial pivoting; a pivot below
    1e-14 of the largest entry is replaced by one that size (inverse iteration wants the
    near-singular solve). Returns ``(permutation, regularity)``, the latter the smallest
    pivot over the largest entry.
    """
    n = A.shape[0]
    big = 1e-300
    for i in range(n):
        for j in range(n):
            big = max(big, abs(A[i, j]))
    permutation = np.arange(n)
    smallest = math.inf
    for c in range(n):
        p = c
        for r in range(c + 1, n):
            if abs(A[r, c]) > abs(A[p, c]):
                p = r
        for j in range(n):
            A[c, j], A[p, j] = A[p, j], A[c, j]
        permutation[c], permutation[p] = permutation[p], permutation[c]
        smallest = min(smallest, abs(A[c, c]))
        if abs(A[c, c]) < 1e-14 * big:
            A[c, c] = math.copysign(1e-14 * big, A[c, c])
        for r in range(c + 1, n):
            A[r, c] /= A[c, c]
            for j in range(c + 1, n):
                A[r, j] -= A[r, c] * A[c, j]
    return permutation, smallest / big


@numba.njit(**COMPILE)
def lu_apply(LU, permutation, b, x):
    """``x = A⁻¹ b`` from :func:`lu_factor`'s factors."""
    n = LU.shape[0]
    for r in range(n):
        x[r] = b[permutation[r]]
        for j in range(r):
            x[r] -= LU[r, j] * x[j]
    for r in range(n - 1, -1, -1):
        for j in range(r + 1, n):
            x[r] -= LU[r, j] * x[j]
        x[r] /= LU[r, r]


@numba.njit(**COMPILE)
def _companion(M, x0):
    """The companion matrix of the pencil after the Möbius change.

    The 24 × 24 companion matrix of ``y² M(x0) + y (M1 + 2 x0 M2) + M2`` (the pencil after
    ``x = x0 + 1/y``) and how regular ``M(x0)`` is (smallest LU pivot over the largest).
    """
    P2 = M[0] + x0 * M[1] + x0 * x0 * M[2]
    permutation, regular = lu_factor(P2)
    X = np.empty((12, 24))
    column, solution = np.empty(12), np.empty(12)
    for c in range(24):
        for r in range(12):
            column[r] = M[2, r, c] if c < 12 else M[1, r, c - 12] + 2.0 * x0 * M[2, r, c - 12]
        lu_apply(P2, permutation, column, solution)
        X[:, c] = solution
    companion = np.zeros((24, 24))
    for r in range(12):
        companion[r, 12 + r] = 1.0
        for c in range(24):
            companion[12 + r, c] = -X[r, c]
    return companion, regular


@numba.njit(**COMPILE)
def pencil(local, backs, posts, left, from_samples, powers, hidden, x0):
    """Steps 2–3 for the DH-frame target ``local``.

    Returns:
        ``(companion, M, Qfull, R, constant, rank, regular)``: the 24 × 24 companion matrix,
        the pencil ``M`` (3, 12, 12), the QR of ``Q`` (``Qfull`` 14 × 14, ``R`` 8 × 8), the
        constant right-side term, ``rank`` the smallest |R_ii| over the largest and
        ``regular`` how regular ``M(x0)`` is.
    """
    right = _right(local, backs, posts, from_samples)
    Q = np.empty((14, 8))
    constant = np.empty(14)
    for k in range(14):
        constant[k] = right[0, 0, k]
        for col in range(8):
            Q[k, col] = right[(col + 1) // 3, (col + 1) % 3, k]
    Qfull, R = np.empty((14, 14)), np.empty((8, 8))
    householder(Q, Qfull, R)
    smallest, largest = math.inf, 1e-300
    for i in range(8):
        smallest, largest = min(smallest, abs(R[i, i])), max(largest, abs(R[i, i]))
    rank = smallest / largest
    M = _pencil_matrices(_polynomials(left, constant, Qfull, powers, hidden))
    companion, regular = _companion(M, x0)
    return companion, M, Qfull, R, constant, rank, regular


# --------------------------------------------------------------------------------------
# Compiled: the solutions of the roots (steps 4–5)


@numba.njit(**COMPILE)
def _root_angle(yr, yi, x0):
    """The hidden angle of an eigenvalue, and whether it is real.

    ``(ψ, real)``: the hidden angle ``2 atan(x)`` of the eigenvalue ``y`` (``x = x0 + 1/y``)
    and whether it is real within :data:`IMAGINARY_TOL`.
    """
    size = yr * yr + yi * yi
    if size == 0.0:  # y = 0: x = ∞, the tangent's pole
        return math.pi, True
    xr, xi = x0 + yr / size, -yi / size
    # The imaginary part of 2 atan(x) is 2 xi / (1 + xr²) to first order.
    return 2.0 * math.atan(xr), abs(2.0 * xi / (1.0 + xr * xr)) <= IMAGINARY_TOL


@numba.njit(**COMPILE)
def _null_vector(M, x):
    """The null vector of ``M(x)`` (12,) by two steps of inverse iteration."""
    A = M[0] + x * M[1] + x * x * M[2]
    permutation, _ = lu_factor(A)
    v = np.empty(12)
    for i in range(12):
        v[i] = 1.0 + 0.1 * i
    w = np.empty(12)
    for _ in range(2):
        lu_apply(A, permutation, v, w)
        size = 0.0
        for i in range(12):
            size += w[i] * w[i]
        size = math.sqrt(size)
        for i in range(12):
            v[i] = w[i] / size
    return v


@numba.njit(**COMPILE)
def _ratio_angle(grid, di, dj):
    """An angle from a ratio of monomials.

    ``2 atan(t)`` for ``grid[i + di, j + dj] ≈ t · grid[i, j]`` over the monomial grid
    (least squares, finite at t = ∞).
    """
    num = den = 0.0
    for i in range(grid.shape[0] - di):
        for j in range(grid.shape[1] - dj):
            num += grid[i + di, j + dj] * grid[i, j]
            den += grid[i, j] * grid[i, j]
    return 2.0 * math.atan2(num, den)


@numba.njit(**COMPILE)
def _left_angles(m, psi, hidden, offsets):
    """The three left angles of a root.

    The three left angles: the hidden ``ψ`` and the shown two from the monomial ratios of
    ``m`` (``m[3 i + j] = y^i z^j``).
    """
    grid = m.reshape(4, 3)
    first = 1 if hidden == 0 else 0
    second = 2 if hidden != 2 else 1
    angles = np.empty(3)
    angles[hidden] = offsets[hidden] + psi
    angles[first] = offsets[first] + _ratio_angle(grid, 1, 0)
    angles[second] = offsets[second] + _ratio_angle(grid, 0, 1)
    return angles


@numba.njit(**COMPILE)
def _right_products(left, constant, Qfull, R, angles):
    """The right angles' products of a root.

    ``S`` (8,): the right angles' products from ``Q S = P R − const`` (least squares by the
    QR of ``Q``: ``S = R⁻¹ Q1ᵀ rhs``).
    """
    b0 = (1.0, math.cos(angles[0]), math.sin(angles[0]))
    b1 = (1.0, math.cos(angles[1]), math.sin(angles[1]))
    b2 = (1.0, math.cos(angles[2]), math.sin(angles[2]))
    rhs = -constant
    for a in range(3):
        for b in range(3):
            for c in range(3):
                f = b0[a] * b1[b] * b2[c]
                for k in range(14):
                    rhs[k] += f * left[a, b, c, k]
    qt = np.zeros(8)
    for i in range(8):
        for k in range(14):
            qt[i] += Qfull[k, i] * rhs[k]
    S = np.zeros(8)
    for i in range(7, -1, -1):
        acc = qt[i]
        for j in range(i + 1, 8):
            acc -= R[i, j] * S[j]
        S[i] = acc / R[i, i]
    return S


@numba.njit(**COMPILE)
def _link(theta, dh, i):
    """``A_i(θ)`` of the DH rows ``dh`` (4, 6: d, a, α, offset)."""
    c, s = math.cos(theta), math.sin(theta)
    ca, sa = math.cos(dh[2, i]), math.sin(dh[2, i])
    A = np.zeros((4, 4))
    A[0, 0], A[0, 1], A[0, 2], A[0, 3] = c, -s * ca, s * sa, dh[1, i] * c
    A[1, 0], A[1, 1], A[1, 2], A[1, 3] = s, c * ca, -c * sa, dh[1, i] * s
    A[2, 1], A[2, 2], A[2, 3] = sa, ca, dh[0, i]
    A[3, 3] = 1.0
    return A


@numba.njit(**COMPILE)
def _times(A, B):
    """``A B`` for 4 × 4 (loops: numba's matmul binds BLAS, which takes seconds to compile)."""
    C = np.zeros((4, 4))
    for i in range(4):
        for j in range(4):
            for k in range(4):
                C[i, j] += A[i, k] * B[k, j]
    return C


@numba.njit(**COMPILE)
def _remaining_angle(theta, dh, local, rebased):
    """The one angle the split leaves out.

    The angle left by the split: θ6 from :math:`A_6 = (A_1 ⋯ A_5)^{-1} T` (standard), or
    θ5 from :math:`A_5 = (A_1 ⋯ A_4)^{-1} T A_6^{-1}` (re-based), read off the first column
    of that link, ``(cos θ, sin θ, 0)``.
    """
    last = 4 if rebased else 5
    before = _link(theta[0], dh, 0)
    for i in range(1, last):
        before = _times(before, _link(theta[i], dh, i))
    column = (local[0, 0], local[1, 0], local[2, 0])
    if rebased:  # T A6⁻¹ e1 = R_T R6ᵀ e1, R6ᵀ e1 the first row of R6
        six = _link(theta[5], dh, 5)
        column = (
            local[0, 0] * six[0, 0] + local[0, 1] * six[0, 1] + local[0, 2] * six[0, 2],
            local[1, 0] * six[0, 0] + local[1, 1] * six[0, 1] + local[1, 2] * six[0, 2],
            local[2, 0] * six[0, 0] + local[2, 1] * six[0, 1] + local[2, 2] * six[0, 2],
        )
    x = before[0, 0] * column[0] + before[1, 0] * column[1] + before[2, 0] * column[2]
    y = before[0, 1] * column[0] + before[1, 1] * column[1] + before[2, 1] * column[2]
    return math.atan2(y, x)


@numba.njit(**COMPILE)
def _dh_angles(S, angles, dh, local, rebased):
    """The six DH angles of a root.

    The six DH angles of a root: the right pair from ``S`` (``c, s`` of the first right
    angle at entries 2, 5; of the second at 0, 1), the left triple, the remaining angle.
    """
    theta = np.empty(6)
    first = math.atan2(S[5], S[2])
    second = math.atan2(S[1], S[0])
    if rebased:  # right: θ1, θ6; left: θ2, θ3, θ4
        theta[0], theta[5] = first, second
        theta[1], theta[2], theta[3] = angles[0], angles[1], angles[2]
        theta[4] = _remaining_angle(theta, dh, local, True)
    else:  # right: θ1, θ2; left: θ3, θ4, θ5
        theta[0], theta[1] = first, second
        theta[2], theta[3], theta[4] = angles[0], angles[1], angles[2]
        theta[5] = _remaining_angle(theta, dh, local, False)
    return theta


@numba.njit(**COMPILE)
def _keep(theta, dh, G, target, length, out, found):
    """Polish, verify and keep a candidate.

    Polish the DH angles ``theta`` as a chain configuration, and append it to ``out``
    (``q`` wrapped, then its Hadamard ratio) if it reaches ``target`` within
    :data:`VERIFY_TOL` and is not within :data:`MERGE_TOL` of a kept one. Returns the count.
    """
    slot = np.empty(18)
    for j in range(6):
        slot[j] = theta[j] - dh[3, j]
        slot[6 + j], slot[12 + j] = math.cos(slot[j]), math.sin(slot[j])
    if newton(G, slot, target, -1, POLISH_STEPS, POLISH_STOP) > VERIFY_TOL:
        return found
    for other in range(found):
        same = True
        for j in range(6):
            if abs(wrap(out[other, j] - slot[j])) > MERGE_TOL:
                same = False
                break
        if same:
            return found
    if found >= out.shape[0]:
        return found
    for j in range(6):
        out[found, j] = wrap(slot[j])
    out[found, 6] = hadamard_ratio(G, slot, length)
    return found + 1


@numba.njit(**COMPILE)
def solution_of(m, psi, tables, hidden, local, target, out, found):
    """The solution of one monomial vector (steps 4–5).

    Steps 4–5 for one monomial vector ``m`` of the hidden angle ``ψ``; returns the count
    of ``out`` (``tables = (left, offsets, dh, G, length, rebased, M, Qfull, R, constant)``).
    """
    left, offsets, dh, G, length, rebased, _, Qfull, R, constant = tables
    angles = _left_angles(m, psi, hidden, offsets)
    S = _right_products(left, constant, Qfull, R, angles)
    theta = _dh_angles(S, angles, dh, local, rebased)
    return _keep(theta, dh, G, target, length, out, found)


@numba.njit(**COMPILE)
def _real_roots(y_re, y_im, x0):
    """The real hidden angles of the eigenvalues, sorted."""
    roots = np.empty(y_re.shape[0])
    count = 0
    for i in range(y_re.shape[0]):
        psi, real = _root_angle(y_re[i], y_im[i], x0)
        if not real:
            continue
        j = count  # insertion sort: at most 24 roots
        while j > 0 and roots[j - 1] > psi:
            roots[j] = roots[j - 1]
            j -= 1
        roots[j] = psi
        count += 1
    return roots[:count]


@numba.njit(**COMPILE)
def solutions(y_re, y_im, x0, tables, hidden, local, target, out, clusters):
    """Every solution of the simple real roots.

    Every solution of the simple real roots into ``out`` (k, 7); each multiple root (a
    cluster within :data:`CLUSTER_TOL`) goes to ``clusters`` as ``(ψ, multiplicity)`` for
    :func:`monomials_of`. Returns ``(found, n_clusters)``.
    """
    roots = _real_roots(y_re, y_im, x0)
    M = tables[6]
    found = n_clusters = 0
    start = 0
    while start < roots.shape[0]:
        stop = start + 1
        while stop < roots.shape[0] and roots[stop] - roots[start] <= CLUSTER_TOL:
            stop += 1
        psi = roots[start:stop].mean()
        if stop - start == 1:
            m = _null_vector(M, math.tan(0.5 * psi))
            found = solution_of(m, psi, tables, hidden, local, target, out, found)
        else:
            clusters[n_clusters, 0], clusters[n_clusters, 1] = psi, stop - start
            n_clusters += 1
        start = stop
    return found, n_clusters


def monomials_of(M: np.ndarray, psi: float, k: int) -> list[np.ndarray]:
    """The monomial vectors of a multiple root (step 4).

    The k monomial vectors of a k-fold root ``ψ`` (step 4): the k-dimensional null space
    of ``M(x)`` split by the shift of the first shown tangent (``m[3(i + 1) + j] = y
    m[3i + j]``), a k × k eigenproblem.
    """
    x = float(np.tan(psi / 2.0))
    matrix = M[0] + x * M[1] + x * x * M[2] if abs(x) <= 1.0 else M[2] + M[1] / x + M[0] / x**2
    V = np.linalg.svd(matrix)[2][-k:].T
    grid = V.reshape(4, 3, k)
    low, high = grid[:3].reshape(9, k), grid[1:].reshape(9, k)
    shift = np.linalg.lstsq(low, high, rcond=None)[0]
    _, vectors = np.linalg.eig(shift)
    return [np.ascontiguousarray((V @ vectors[:, c]).real) for c in range(k)]


@numba.njit(**COMPILE)
def local_target(T, reverse, length, base_inverse, tool_inverse):
    """The target of the chain as solved, in its DH frames.

    ``(target, local)``: the target of the chain as solved (``T⁻¹`` backwards) and it in
    the scaled chain's DH frames, ``base⁻¹ (target / length) tool⁻¹``.
    """
    target = inverse(T) if reverse else T.copy()
    scaled = target.copy()
    scaled[:3, 3] /= length
    return target, _times(_times(base_inverse, scaled), tool_inverse)


# --------------------------------------------------------------------------------------
# The elimination of one chain


@dataclass(frozen=True)
class Elimination:
    """One elimination of a chain: its tables and its solve.

    The target-independent part of one split of a (possibly reversed) chain, and its
    solve: every solution of a target, steps 2–5 of the module docstring.

    Attributes:
        chain: The chain as solved (the robot's, or run backwards for ``T⁻¹``).
        reversed: Whether ``chain`` is the robot's run backwards.
        split: ``"standard"`` or ``"rebased"`` (step 1).
        hidden: Which of the three left angles is the hidden variable (0, 1 or 2).
    """

    chain: Chain
    reversed: bool
    split: str
    hidden: int
    length: float
    dh: DH
    arrays: dict

    @classmethod
    def build(cls, chain: Chain, reverse: bool, split: str, hidden: int) -> Elimination:
        """The tables of one split and hidden variable.

        The tables of ``chain`` (already reversed if ``reverse``) for a split and hidden
        variable (step 1, and the left side's coefficients of step 2).
        """
        length = chain.length()
        dh = dh_of_chain(chain.scaled(length))
        rows = (1, 2, 3) if split == "rebased" else (2, 3, 4)
        g = np.meshgrid(_GRID, _GRID, _GRID, indexing="ij")
        triple = dh.links(rows[0], g[0]) @ dh.links(rows[1], g[1]) @ dh.links(rows[2], g[2])
        samples = fourteen(triple[..., :3, 3], triple[..., :3, 2])
        left = np.einsum("ag,bh,ci,ghik->abck", *(_FROM_SAMPLES,) * 3, samples)
        g1, g2 = np.meshgrid(_GRID, _GRID, indexing="ij")
        if split == "rebased":
            backs = inverse_stack(dh.links(0, g1))
            after = inverse_stack(dh.links(5, g2)) @ inverse_stack(dh.links(4, np.zeros(())))
            posts = after[..., :, 2:4]
        else:
            backs = inverse_stack(dh.links(0, g1) @ dh.links(1, g2))
            posts = np.zeros((3, 3, 4, 2))
            posts[..., 2, 0] = posts[..., 3, 1] = 1.0  # the z column and origin of I
        arrays = {
            "backs": backs, "posts": posts, "left": left,
            "powers": np.stack([_offset_basis(o) @ _HALF_ANGLE for o in OFFSETS]),
            "dh": np.vstack([dh.d, dh.a, dh.alpha, dh.offset]),
            "base_inverse": inverse_stack(dh.base), "tool_inverse": inverse_stack(dh.tool),
            "G": pack(chain, chain.a, chain.h[5]),
        }  # fmt: skip
        arrays = {k: np.ascontiguousarray(v, dtype=float) for k, v in arrays.items()}
        return cls(chain, reverse, split, hidden, length, dh, arrays)

    def solve(self, T: np.ndarray) -> tuple[np.ndarray, float, float]:
        """Every solution of the world-frame target ``T`` (a validated rigid transform).

        Returns:
            ``(rows, rank, regular)``: rows (k, 7) of the robot's joint values (wrapped to
            (−π, π]) and each one's Hadamard ratio, in the elimination's order; ``rank`` and
            ``regular`` say how far ``Q`` and the pencil are from degenerate (probes).
        """
        a = self.arrays
        target, local = local_target(
            np.ascontiguousarray(T, dtype=float), self.reversed, self.length,
            a["base_inverse"], a["tool_inverse"],
        )  # fmt: skip
        x0 = MOBIUS[self.hidden]
        companion, M, Qfull, R, constant, rank, regular = pencil(
            local, a["backs"], a["posts"], a["left"], _FROM_SAMPLES, a["powers"], self.hidden, x0
        )
        y = np.linalg.eigvals(companion)
        tables = (
            a["left"], np.array(OFFSETS), a["dh"], a["G"], self.length,
            self.split == "rebased", M, Qfull, R, constant,
        )  # fmt: skip
        out, clusters = np.empty((MAX_SOLUTIONS, 7)), np.empty((24, 2))
        found, n_clusters = solutions(
            y.real.copy(), y.imag.copy(), x0, tables, self.hidden, local, target, out, clusters
        )
        for psi, k in clusters[:n_clusters]:
            for m in monomials_of(M, float(psi), int(k)):
                found = solution_of(m, float(psi), tables, self.hidden, local, target, out, found)
        rows = out[:found].copy()
        if self.reversed:
            rows[:, :6] = rows[:, 5::-1]
        return rows, rank, regular
