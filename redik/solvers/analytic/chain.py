r"""A 6-joint screw chain in packed form, compiled: forward kinematics, Jacobian, polishing.

The arm is :math:`T(q) = e^{[S_1]q_1} ⋯ e^{[S_6]q_6} M` (Modern Robotics §4.1), written as in
IK-Geo (Elias & Wen 2022, §II) with unit axes ``h_i`` and points ``a_i`` on them at q = 0
(world frame) and the rotations :math:`R_i = \mathrm{rot}(h_i, q_i)`:

.. math::
    p(q) = a_1 + R_1 (a_2 - a_1) + R_1 R_2 (a_3 - a_2) + ⋯ + R_1 ⋯ R_6 (p_M - a_6),\qquad
    R(q) = R_1 ⋯ R_6 R_M ;

a prismatic joint translates by ``q_i`` along ``h_i`` instead of rotating.

Everything the compiled kernels know of the arm is one (19, 3) array ``G``
(:func:`redik.solvers.analytic.geometry.pack` makes it): rows 0–5 the axes, 6–11 the points
(where axes meet, the same point), 12 ``p_M``, 13–15 the rows of ``R_M``, 16 a unit vector
perpendicular to the axis of the kernel's last SP1, 17–18 one flag per joint, non-zero for a
prismatic joint. A configuration is a *slot row* of 18 numbers: the six joint values, then
the cosines and sines of the angles (the subproblems produce them with each root, so that
forward kinematics needs no trigonometric call).

The damped Gauss–Newton polish (:func:`newton`) solves its 6 × 6 system by Gaussian elimination in
loops: numba's LAPACK-backed ``np.linalg`` calls take seconds to compile and cost more than
the arithmetic at this size.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from redik.kinematics.compiled import COMPILE
from redik.solvers.analytic.vectors import add, cross, dot, norm, rotate_cs, row, scale, sub

#: Rows of ``G``.
AXES, POINTS, TIP, TIP_ROTATION, PERPENDICULAR, FLAGS = 0, 6, 12, 13, 16, 17

#: Size of ``G`` (19 rows of 3).
GEOMETRY_ROWS = 19

#: A pivot below this fraction of the largest entry is a singular direction.
PIVOT_TOL = 1e-12

#: Levenberg–Marquardt damping of the polish, relative to the Jacobian's largest column.
DAMPING = 1e-7


@numba.njit(**COMPILE)
def is_prismatic(G, i):
    """Whether joint ``i`` of the chain of ``G`` slides."""
    return G[FLAGS + i // 3, i % 3] != 0.0


@numba.njit(**COMPILE)
def target_of(T, G):
    r"""The target as the kernels read it.

    Returns ``(z0, z1, z2, p)``: the rows of :math:`Z = R R_M^\top = R_1 ⋯ R_6` and the
    position.
    """
    m0, m1, m2 = row(G, TIP_ROTATION), row(G, TIP_ROTATION + 1), row(G, TIP_ROTATION + 2)
    r0, r1, r2 = (
        (T[0, 0], T[0, 1], T[0, 2]),
        (T[1, 0], T[1, 1], T[1, 2]),
        (T[2, 0], T[2, 1], T[2, 2]),
    )
    return (
        (dot(r0, m0), dot(r0, m1), dot(r0, m2)),
        (dot(r1, m0), dot(r1, m1), dot(r1, m2)),
        (dot(r2, m0), dot(r2, m1), dot(r2, m2)),
        (T[0, 3], T[1, 3], T[2, 3]),
    )


@numba.njit(**COMPILE)
def fk_error(G, slot, T):
    r"""``max(‖p(q) − p‖, max |R(q) − R| over the first two columns)`` at a slot row.

    Evaluated from the tip inwards, :math:`p = a_1 + R_1(a_2 - a_1 + R_2(⋯ + R_6(p_M - a_6)))`
    and :math:`R\,\hat x = R_1(⋯ R_6 (R_M \hat x))`: three vectors rotated per joint (the
    third column of a rotation follows from the first two).
    """
    p = sub(row(G, TIP), row(G, POINTS + 5))
    x = (G[TIP_ROTATION, 0], G[TIP_ROTATION + 1, 0], G[TIP_ROTATION + 2, 0])
    y = (G[TIP_ROTATION, 1], G[TIP_ROTATION + 1, 1], G[TIP_ROTATION + 2, 1])
    for i in range(5, -1, -1):
        k = row(G, AXES + i)
        if is_prismatic(G, i):
            p = add(p, scale(k, slot[i]))
        else:
            c, s = slot[6 + i], slot[12 + i]
            p = rotate_cs(k, c, s, p)
            x = rotate_cs(k, c, s, x)
            y = rotate_cs(k, c, s, y)
        if i > 0:
            p = add(p, sub(row(G, POINTS + i), row(G, POINTS + i - 1)))
    p = add(p, row(G, POINTS))
    error = norm(sub(p, (T[0, 3], T[1, 3], T[2, 3])))
    for i in range(3):
        error = max(error, max(abs(x[i] - T[i, 0]), abs(y[i] - T[i, 1])))
    return error


@numba.njit(**COMPILE)
def wrap(angle):
    """An angle wrapped to (−π, π].

    ``angle`` wrapped to (−π, π], equal bit for bit to :func:`redik.lie.wrap_angle`: within
    a few turns (every kernel angle) by exact shifts of 2π, which is what ``fmod`` then one
    shift give there, and beyond by that algorithm itself.
    """
    if -math.pi < angle <= math.pi:
        return angle
    two_pi = 2.0 * math.pi
    if abs(angle) > 8.0 * math.pi:
        r = np.fmod(angle, two_pi)
        return r - two_pi if r > math.pi else (r + two_pi if r <= -math.pi else r)
    while angle > math.pi:
        angle -= two_pi
    while angle <= -math.pi:
        angle += two_pi
    return angle


@numba.njit(**COMPILE)
def inverse(T):
    """``T⁻¹`` of a rigid transform (4 × 4)."""
    result = np.zeros((4, 4))
    for i in range(3):
        for j in range(3):
            result[i, j] = T[j, i]
        result[i, 3] = -(T[0, i] * T[0, 3] + T[1, i] * T[1, 3] + T[2, i] * T[2, 3])
    result[3, 3] = 1.0
    return result


@numba.njit(**COMPILE)
def _times_rotation(R, k, c, s):
    """The rows of ``R · rot(k, θ)`` for the rows ``R`` (3 tuples) and ``c, s = cos θ, sin θ``."""
    x = rotate_cs(k, c, s, (1.0, 0.0, 0.0))
    y = rotate_cs(k, c, s, (0.0, 1.0, 0.0))
    z = rotate_cs(k, c, s, (0.0, 0.0, 1.0))
    return (
        (dot(R[0], x), dot(R[0], y), dot(R[0], z)),
        (dot(R[1], x), dot(R[1], y), dot(R[1], z)),
        (dot(R[2], x), dot(R[2], y), dot(R[2], z)),
    )


@numba.njit(**COMPILE)
def axes_at(G, slot, axes, points):
    """The world axes and a point on each at a slot row.

    The world axes and a point on each at a slot row: fills ``axes`` and ``points`` (6, 3)
    and returns ``(R, p)``, the rows of :math:`R_1 ⋯ R_6` and the tip point.

    The point of axis i is where ``a_i`` is carried by the joints before it (for a prismatic
    joint, its line's point at its own value 0).
    """
    R = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    P = row(G, POINTS)
    for i in range(6):
        k = row(G, AXES + i)
        w = (dot(R[0], k), dot(R[1], k), dot(R[2], k))
        axes[i, 0], axes[i, 1], axes[i, 2] = w
        points[i, 0], points[i, 1], points[i, 2] = P
        if is_prismatic(G, i):
            P = add(P, scale(w, slot[i]))
        else:
            R = _times_rotation(R, k, slot[6 + i], slot[12 + i])
        following = row(G, TIP) if i == 5 else row(G, POINTS + i + 1)
        offset = sub(following, row(G, POINTS + i))
        P = add(P, (dot(R[0], offset), dot(R[1], offset), dot(R[2], offset)))
    return R, P


@numba.njit(**COMPILE)
def jacobian_system(G, slot, T, A):
    r"""Fill the 6 × 7 augmented system ``[J | e]`` at a slot row.

    ``J`` is the world Jacobian of the chain, rows ``(ω, v)``: ``(ω_i, ω_i × (p − o_i))`` for a
    hinge through ``o_i``, ``(0, ω_i)`` for a slide; ``e = (½ Σ_j R_{:j} × R_{d,:j},\; p_d − p)``
    is the pose error to first order (Siciliano et al. 2009, §3.7.3).
    """
    axes = np.empty((6, 3))
    points = np.empty((6, 3))
    R, P = axes_at(G, slot, axes, points)
    for i in range(6):
        w = row(axes, i)
        if is_prismatic(G, i):
            A[0, i], A[1, i], A[2, i] = 0.0, 0.0, 0.0
            A[3, i], A[4, i], A[5, i] = w
        else:
            A[0, i], A[1, i], A[2, i] = w
            A[3, i], A[4, i], A[5, i] = cross(w, sub(P, row(points, i)))
    rotation = (0.0, 0.0, 0.0)
    for j in range(3):
        m = (G[TIP_ROTATION, j], G[TIP_ROTATION + 1, j], G[TIP_ROTATION + 2, j])
        column = (dot(R[0], m), dot(R[1], m), dot(R[2], m))
        rotation = add(rotation, cross(column, (T[0, j], T[1, j], T[2, j])))
    A[0, 6], A[1, 6], A[2, 6] = scale(rotation, 0.5)
    A[3, 6], A[4, 6], A[5, 6] = T[0, 3] - P[0], T[1, 3] - P[1], T[2, 3] - P[2]


@numba.njit(**COMPILE)
def _pivot_to(A, col):
    """Swap into row ``col`` the row at or below it with the largest ``|A[r, col]|``."""
    pivot = col
    for r in range(col + 1, A.shape[0]):
        if abs(A[r, col]) > abs(A[pivot, col]):
            pivot = r
    for j in range(A.shape[1]):
        A[col, j], A[pivot, j] = A[pivot, j], A[col, j]


@numba.njit(**COMPILE)
def eliminate(A, x):
    """Solve a 6 × 7 augmented system by Gaussian elimination.

    Solve the 6 × 7 augmented system ``A`` (destroyed) into ``x`` by Gaussian elimination
    with partial pivoting; a pivot below :data:`PIVOT_TOL` of the largest entry (a singular
    direction) takes no step. Returns the product of the pivots (``det`` up to sign).
    """
    largest = np.abs(A[:, :6]).max()
    determinant = 1.0
    for col in range(6):
        _pivot_to(A, col)
        determinant *= A[col, col]
        if abs(A[col, col]) <= PIVOT_TOL * largest:
            A[col, col] = math.inf
        for r in range(col + 1, 6):
            f = A[r, col] / A[col, col]
            for j in range(col, 7):
                A[r, j] -= f * A[col, j]
    for r in range(5, -1, -1):
        acc = A[r, 6]
        for j in range(r + 1, 6):
            acc -= A[r, j] * x[j]
        x[r] = acc / A[r, r]
    return determinant


@numba.njit(**COMPILE)
def _damped_step(A, fixed, x):
    r"""One damped least-squares (Levenberg–Marquardt) step.

    The Levenberg–Marquardt step :math:`(J^\top J + λ^2 I)\,Δq = J^\top e` of the
    augmented ``A = [J | e]`` into ``x`` (column ``fixed`` of J zeroed first, unless −1),
    ``λ`` = :data:`DAMPING` times the largest column norm of J.
    """
    if fixed >= 0:
        for r in range(6):
            A[r, fixed] = 0.0
    normal = np.empty((6, 7))
    largest = 0.0
    for i in range(6):
        for j in range(7):
            total = 0.0
            for r in range(6):
                total += A[r, i] * A[r, j]
            normal[i, j] = total
        largest = max(largest, normal[i, i])
    damping = DAMPING * DAMPING * max(largest, 1e-300)
    for i in range(6):
        normal[i, i] += damping
    eliminate(normal, x)


@numba.njit(**COMPILE)
def newton(G, slot, T, fixed, steps, stop):
    r"""Damped Gauss–Newton (Levenberg–Marquardt) steps on a slot row towards ``T``.

    Each step solves :math:`(J^	op J + λ^2 I)\,Δq = J^	op e` (:func:`jacobian_system`,
    :func:`eliminate`) with a small λ (:data:`DAMPING`), so that next to a singularity, where
    a subproblem gives its angles to only √ε (SP4 with ``C ≈ ±r``), the steps along the
    nearly singular directions stay small; a step that does not lower the FK error is undone
    and ends the polish.

    Args:
        G: The packed chain.
        slot: The slot row (18,), updated in place (cosines and sines with it).
        T: The target (4, 4).
        fixed: A joint held still (a family's free joint), or −1.
        steps: At most this many steps.
        stop: Fewer once the error is at most this.

    Returns:
        The final :func:`fk_error`.
    """
    A = np.empty((6, 7))
    x = np.empty(6)
    before = np.empty(18)
    error = fk_error(G, slot, T)
    for _ in range(steps):
        if error <= stop:
            break
        jacobian_system(G, slot, T, A)
        _damped_step(A, fixed, x)
        before[:] = slot
        for i in range(6):
            slot[i] += x[i]
            if not is_prismatic(G, i):
                slot[6 + i], slot[12 + i] = math.cos(slot[i]), math.sin(slot[i])
        stepped = fk_error(G, slot, T)
        if not stepped < error:
            slot[:] = before
            break
        error = stepped
    return error


@numba.njit(**COMPILE)
def hadamard_ratio(G, slot, length):
    r"""How far a slot row is from a singularity, in [0, 1].

    How far a slot row is from a singularity: :math:`|\det J| / \prod_i ‖J_i‖ \in [0, 1]`
    (Hadamard's inequality), with the Jacobian's linear rows divided by ``length`` (m) so
    that every column is of order 1. It is 0 exactly at a singular configuration and, near a
    simple singularity, proportional to the smallest singular value.
    """
    A = np.zeros((6, 7))
    x = np.empty(6)
    jacobian_system(G, slot, np.eye(4), A)
    product = 1.0
    for i in range(6):
        for r in range(3, 6):
            A[r, i] /= length
        column = 0.0
        for r in range(6):
            column += A[r, i] * A[r, i]
        product *= math.sqrt(column)
        A[i, 6] = 0.0
    if product == 0.0:
        return 0.0
    return min(abs(eliminate(A, x)) / product, 1.0)
