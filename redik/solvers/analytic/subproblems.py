r"""The subproblems of closed-form 6R IK, compiled: Paden–Kahan's SP1–SP4 and IK-Geo's SP5–SP6.

Each subproblem asks for the angle(s) of one or two revolute axes that move given vectors into
a given relation (Paden 1985; Murray, Li & Sastry 1994, §3.2.2; Elias & Wen 2022, "IK-Geo",
arXiv 2211.05737, §III, whose numbering and forms these follow). ``rot(k, θ)`` is the rotation
about the unit axis ``k`` (:mod:`.vectors`).

SP1
    ``rot(k, θ) p1 = p2``: with :math:`a, b` the parts of p1, p2 perpendicular to k,
    :math:`θ = \operatorname{atan2}(k·(a × b),\; a·b)`. One solution; any θ when a = 0.
SP2
    ``rot(k1, θ1) p1 = rot(k2, θ2) p2`` (k1 ∦ k2): the common image
    :math:`x = α k_1 + β k_2 + γ (k_1 × k_2)` keeps the axial components,
    :math:`k_1·x = k_1·p_1`, :math:`k_2·x = k_2·p_2`; its height above the plane of k1
    and k2 follows from the circle about k1 (or k2) it lies on, of radius r = ‖p1 ⊥ k1‖:
    :math:`γ‖k_1 × k_2‖ = ±\sqrt{r^2 - s^2}`, s its in-plane part: two solutions, then SP1
    on each axis.
SP3
    ``‖rot(k, θ) p1 − p2‖ = d``: with a, b the perpendicular parts and
    :math:`δ = k·(p_1 − p_2)`, :math:`\cos(θ − φ) = (‖a‖^2 + ‖b‖^2 + δ^2 − d^2) / (2‖a‖‖b‖)`,
    φ the SP1 angle from a to b: two solutions :math:`θ = φ ± \arccos(⋅)`.
SP4
    ``h·rot(k, θ) p = d``: :math:`A \cos θ + B \sin θ = C` with
    :math:`A = h·p − (h·k)(k·p)`, :math:`B = h·(k × p)`, :math:`C = d − (h·k)(k·p)`:
    two solutions :math:`θ = \operatorname{atan2}(B, A) ± \arccos(C / \sqrt{A^2 + B^2})`.
SP5
    ``p0 + rot(k1, θ1) p1 = rot(k2, θ2)(p2 + rot(k3, θ3) p3)``: the circles
    :math:`v_1(θ_1) = p_0 + \mathrm{rot}(k_1, θ_1) p_1` and
    :math:`v_3(θ_3) = p_2 + \mathrm{rot}(k_3, θ_3) p_3` need the same height
    :math:`H = k_2·v` and the same length (then SP1 about k2 gives θ2). On each circle
    :math:`k_2·v = g + x·α` and :math:`‖v‖^2 = n + 2 x·β` are linear in
    :math:`x = (\cos θ, \sin θ)`, so H fixes x up to the sign σ of a square root and
    :math:`‖v‖^2 = L(H) + σ M \sqrt{Q(H)}`, L linear and Q quadratic in H. Squaring
    :math:`L_1 - L_3 + σ_1 M_1 \sqrt{Q_1} = σ_3 M_3 \sqrt{Q_3}` twice gives a quartic in H
    (:mod:`.polynomial`): up to 4 solutions. A circle of constant height (k1 ∥ k2 or
    k3 ∥ k2) fixes H; the lengths then match by a second line cut (SP4, then SP3's length
    match). When M = 0 (a circle's length does not depend on its branch) the quartic is a
    perfect square and its quadratic is solved instead, so that double roots keep their digits.
SP6
    ``h1·rot(k1, θ1) p1 + h2·rot(k2, θ2) p2 = d1`` and
    ``h3·rot(k3, θ1) p3 + h4·rot(k4, θ2) p4 = d2``: each term is ``c + e cos θ + f sin θ``, so
    the pair is :math:`A_1 u_1 + A_2 u_2 = b` in :math:`u_i = (\cos θ_i, \sin θ_i)`. With
    the better-conditioned 2 × 2 block inverted, :math:`u_2 = m + N u_1` and ‖u2‖ = 1 is a
    conic in u1; the half-angle tangent of :math:`θ_1 - ω` (ω a fixed offset, so that no
    generic root sits at the tangent's pole) turns it into a quartic: up to 4 solutions.

Vectors are 3-tuples. SP3 and SP4 return a status: :data:`OK`, :data:`BOUNDARY` (the two
solutions coincide: the target is within ``tol`` of the edge of the reachable set and was
clipped onto it), :data:`OUT` (no solution) or :data:`FREE` (the equation does not depend on θ
and holds: any θ solves it). SP5 and SP6 return how many solutions they wrote; a tangency is
kept (:mod:`.polynomial`), and the caller's forward-kinematics check decides.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from redik.kinematics.compiled import COMPILE
from redik.solvers.analytic.polynomial import near_double, real_roots
from redik.solvers.analytic.vectors import add, cross, dot, norm, perp, scale, sub

OK, BOUNDARY, OUT, FREE = 0, 1, 2, 3

#: SP6's half-angle offset ω (rad): any value no special geometry singles out.
SP6_OFFSET = 1.2345678

#: Relative slack by which an SP5 line may miss its circle (squared lengths) and still be cut
#: at the tangent point, and by which the two circles' lengths may differ at a root.
SP5_TANGENT = 1e-9
SP5_MATCH = 1e-7

#: A quartic root whose derivative is below this (relative) is a double root: two solutions
#: of SP5 or SP6 merge there (a singular arm), and the row says so.
DOUBLE_ROOT = 1e-6


@numba.njit(**COMPILE)
def sp1_cs(k, p1, p2):
    """SP1: θ with ``rot(k, θ) p1 = p2`` (least squares in the plane ⊥ k).

    Returns:
        ``(θ, cos θ, sin θ, ‖a‖)``: the cosine and sine read off the projections (no
        trigonometric call) and the length of p1's perpendicular part; θ is arbitrary when
        that length is 0, and then 0.
    """
    a = perp(k, p1)
    b = perp(k, p2)
    y, x = dot(k, cross(a, b)), dot(a, b)
    r = math.sqrt(x * x + y * y)
    if r == 0.0:
        return 0.0, 1.0, 0.0, norm(a)
    return math.atan2(y, x), x / r, y / r, norm(a)


@numba.njit(**COMPILE)
def sp1(k, p1, p2):
    """SP1 without the cosine and sine: ``(θ, ‖a‖)`` (:func:`sp1_cs`)."""
    theta, _, _, length = sp1_cs(k, p1, p2)
    return theta, length


@numba.njit(**COMPILE)
def _roots_cs(cos_phi, sin_phi, cosine):
    """Cosines and sines of ``φ ± arccos(cosine)`` from those of φ (angle-sum formulas)."""
    c = min(max(cosine, -1.0), 1.0)
    s = math.sqrt(1.0 - c * c)
    return (
        cos_phi * c - sin_phi * s,
        sin_phi * c + cos_phi * s,
        cos_phi * c + sin_phi * s,
        sin_phi * c - cos_phi * s,
    )


@numba.njit(**COMPILE)
def sp3_cs(k, p1, p2, d, tol):
    """SP3: θ with ``‖rot(k, θ) p1 − p2‖ = d``.

    The reachable distances run from ``√((‖a‖ − ‖b‖)² + δ²)`` to ``√((‖a‖ + ‖b‖)² + δ²)``;
    ``d`` within ``tol`` (m) of either end is moved onto it (status BOUNDARY: one root).

    Returns:
        ``(θ+, θ−, status, cos θ+, sin θ+, cos θ−, sin θ−)``.
    """
    a = perp(k, p1)
    b = perp(k, p2)
    na, nb = norm(a), norm(b)
    delta = dot(k, p1) - dot(k, p2)
    nearest = math.sqrt((na - nb) ** 2 + delta * delta)
    if na * nb <= tol * tol:
        return 0.0, 0.0, (FREE if abs(nearest - d) <= tol else OUT), 1.0, 0.0, 1.0, 0.0
    y, x = dot(k, cross(a, b)), dot(a, b)
    phi = math.atan2(y, x)
    farthest = math.sqrt((na + nb) ** 2 + delta * delta)
    cosine = (na * na + nb * nb + delta * delta - d * d) / (2.0 * na * nb)
    status = OK
    if d < nearest - tol or d > farthest + tol:
        status = OUT
    elif abs(d - nearest) <= tol or abs(d - farthest) <= tol:
        status = BOUNDARY
        cosine = math.copysign(1.0, cosine)  # the two roots are one
    spread = math.acos(min(max(cosine, -1.0), 1.0))
    r = na * nb
    cp, sp, cm, sm = _roots_cs(x / r, y / r, cosine)
    return phi + spread, phi - spread, status, cp, sp, cm, sm


@numba.njit(**COMPILE)
def sp4_cs(h, k, p, d, tol):
    """SP4: θ with ``h · rot(k, θ) p = d``.

    SP4: θ with ``h · rot(k, θ) p = d``; ``C`` within ``tol`` of ``±r`` is moved onto it
    (status BOUNDARY: one root).

    Returns:
        ``(θ+, θ−, status, cos θ+, sin θ+, cos θ−, sin θ−)``.
    """
    hk, kp = dot(h, k), dot(k, p)
    A = dot(h, p) - hk * kp
    B = dot(h, cross(k, p))
    C = d - hk * kp
    r = math.sqrt(A * A + B * B)
    if r <= tol:
        return 0.0, 0.0, (FREE if abs(C) <= tol else OUT), 1.0, 0.0, 1.0, 0.0
    status = OK
    if abs(C) > r + tol:
        status = OUT
    elif abs(abs(C) - r) <= tol:
        status = BOUNDARY
        C = math.copysign(r, C)  # the two roots are one
    phi = math.atan2(B, A)
    spread = math.acos(min(max(C / r, -1.0), 1.0))
    cp, sp, cm, sm = _roots_cs(A / r, B / r, C / r)
    return phi + spread, phi - spread, status, cp, sp, cm, sm


@numba.njit(**COMPILE)
def sp2_cs(k1, p1, k2, p2, fixed1, fixed2, tol):
    """SP2: θ1, θ2 with ``rot(k1, θ1) p1 = rot(k2, θ2) p2`` (k1 ∦ k2, ‖p1‖ = ‖p2‖).

    Returns:
        ``(θ1+, θ2+, θ1−, θ2−, status, free, trig)``, ``trig`` the cosines and sines
        ``(c1+, s1+, c2+, s2+, c1−, s1−, c2−, s2−)``. ``free`` is 0 normally, 1 when p1 lies
        on k1 (θ1 arbitrary: it takes ``fixed1``), 2 when p2 lies on k2 (θ2 takes
        ``fixed2``); then the two solutions are the same.
    """
    # On its axis a vector does not move: the common image x is that vector itself.
    if norm(perp(k1, p1)) <= tol:
        t2, c2, s2, _ = sp1_cs(k2, p2, p1)
        c1, s1 = math.cos(fixed1), math.sin(fixed1)
        return fixed1, t2, fixed1, t2, FREE, 1, (c1, s1, c2, s2, c1, s1, c2, s2)
    if norm(perp(k2, p2)) <= tol:
        t1, c1, s1, _ = sp1_cs(k1, p1, p2)
        c2, s2 = math.cos(fixed2), math.sin(fixed2)
        return t1, fixed2, t1, fixed2, FREE, 2, (c1, s1, c2, s2, c1, s1, c2, s2)
    c12 = dot(k1, k2)
    u1, u2 = dot(k1, p1), dot(k2, p2)
    w = 1.0 - c12 * c12
    alpha = (u1 - c12 * u2) / w
    beta = (u2 - c12 * u1) / w
    # The height of x above the plane of k1, k2 is read off the smaller of the two circles
    # x moves on: its radius r (a perpendicular part, exact to rounding) and its in-plane
    # part s give height² = (r − s)(r + s), which keeps its digits when that circle is small
    # (a wrist next to its singularity) rather than losing half of them to a cancellation.
    r1, r2 = norm(perp(k1, p1)), norm(perp(k2, p2))
    if r1 <= r2:
        radius, across = r1, (u2 - c12 * u1) / math.sqrt(w)
    else:
        radius, across = r2, (u1 - c12 * u2) / math.sqrt(w)
    rest = (radius - across) * (radius + across)
    height = math.sqrt(max(rest, 0.0))
    status = OK
    if rest < -2.0 * tol * max(radius, tol):
        status = OUT
    elif height <= tol:
        status = BOUNDARY
    gamma = height / math.sqrt(w)
    base = add(scale(k1, alpha), scale(k2, beta))
    n = cross(k1, k2)
    xa = add(base, scale(n, gamma))
    xb = sub(base, scale(n, gamma))
    t1a, c1a, s1a, _ = sp1_cs(k1, p1, xa)
    t2a, c2a, s2a, _ = sp1_cs(k2, p2, xa)
    t1b, c1b, s1b, _ = sp1_cs(k1, p1, xb)
    t2b, c2b, s2b, _ = sp1_cs(k2, p2, xb)
    return t1a, t2a, t1b, t2b, status, 0, (c1a, s1a, c2a, s2a, c1b, s1b, c2b, s2b)


# --------------------------------------------------------------------------------------
# SP5


@numba.njit(**COMPILE)
def _circle(p0, k, p, axis):
    """The circle ``p0 + rot(k, θ) p = c + e cos θ + f sin θ`` read along ``axis``.

    Returns:
        ``(c, e, f, g, αx, αy, n, βx, βy)``: the height ``axis·v = g + (αx, αy)·x`` and the
        squared length ``‖v‖² = n + 2 (βx, βy)·x`` for ``x = (cos θ, sin θ)``.
    """
    along = scale(k, dot(k, p))
    c = add(p0, along)
    e = sub(p, along)
    f = cross(k, p)
    return (
        c, e, f, dot(axis, c), dot(axis, e), dot(axis, f), dot(c, c) + dot(e, e), dot(c, e),
        dot(c, f),
    )  # fmt: skip


@numba.njit(**COMPILE)
def _line_cut(ax, ay, value, sign):
    """Cut the unit circle by a line.

    The point ``x = (cos, sin)`` of the unit circle with ``x·α = value`` on the branch
    ``sign``, and the slack ``‖α‖² − value²`` (negative: the line misses the circle; the
    tangent point is returned).
    """
    a2 = ax * ax + ay * ay
    slack = a2 - value * value
    root = math.sqrt(max(slack, 0.0))
    return (ax * value - sign * ay * root) / a2, (ay * value + sign * ax * root) / a2, slack


@numba.njit(**COMPILE)
def _length_of_height(g, ax, ay, n, bx, by):
    """A circle's squared length as a function of its height.

    ``(l1, l0, M, Q)`` with ``‖v‖² = l1 H + l0 + σ M √Q(H)`` on a circle at height H,
    ``Q = (−1, 2g, ‖α‖² − g²)`` (coefficients of H², H, 1).
    """
    a2 = ax * ax + ay * ay
    l1 = 2.0 * (bx * ax + by * ay) / a2
    return l1, n - l1 * g, 2.0 * (by * ax - bx * ay) / a2, (-1.0, 2.0 * g, a2 - g * g)


@numba.njit(**COMPILE)
def _times(a, b):
    """The product of two quadratics (highest power first) as a quartic."""
    return (
        a[0] * b[0], a[0] * b[1] + a[1] * b[0], a[0] * b[2] + a[1] * b[1] + a[2] * b[0],
        a[1] * b[2] + a[2] * b[1], a[2] * b[2],
    )  # fmt: skip


@numba.njit(**COMPILE)
def _heights(first, third, roots, double):
    """The heights where SP5's two circles can match.

    The heights H where the two circles' lengths can match: the real roots of
    ``G² − 4 D² E₁`` (``D = L₁ − L₃``, ``E = M² Q``, ``G = D² + E₁ − E₃``), or of the quadratic
    it is the square of when one circle has M = 0. Writes ``roots`` and whether each is a
    double root (``double``); returns how many.
    """
    l1, l0, M1, Q1 = _length_of_height(first[3], first[4], first[5], first[6], first[7], first[8])
    m1, m0, M3, Q3 = _length_of_height(third[3], third[4], third[5], third[6], third[7], third[8])
    d1, d0 = l1 - m1, l0 - m0
    size = max(abs(l1), abs(l0), abs(m1), abs(m0), 1e-300)
    poly = np.zeros(5)
    if abs(M1) <= 1e-12 * size and abs(M3) <= 1e-12 * size:
        poly[3], poly[4] = d1, d0
    elif abs(M1) <= 1e-12 * size or abs(M3) <= 1e-12 * size:
        M, Q = (M3, Q3) if abs(M1) <= 1e-12 * size else (M1, Q1)
        poly[2] = d1 * d1 - M * M * Q[0]
        poly[3] = 2.0 * d1 * d0 - M * M * Q[1]
        poly[4] = d0 * d0 - M * M * Q[2]
    else:
        D2 = (d1 * d1, 2.0 * d1 * d0, d0 * d0)
        E1 = (M1 * M1 * Q1[0], M1 * M1 * Q1[1], M1 * M1 * Q1[2])
        G = (D2[0] + E1[0] - M3 * M3 * Q3[0], D2[1] + E1[1] - M3 * M3 * Q3[1],
             D2[2] + E1[2] - M3 * M3 * Q3[2])  # fmt: skip
        GG, DE = _times(G, G), _times(D2, E1)
        for i in range(5):
            poly[i] = GG[i] - 4.0 * DE[i]
    count = real_roots(poly, roots)
    for r in range(count):
        double[r] = near_double(poly, roots[r], DOUBLE_ROOT)
    return count


@numba.njit(**COMPILE)
def _emit(first, x1, third, x3, k2, tangent, out, found):
    """Write one row of SP5.

    Write ``(θ1, θ2, θ3, tangent)`` of the circle points x1, x3 into ``out[found]`` (θ2 by
    SP1 about k2, from v3 to v1); returns ``found + 1``.
    """
    v1 = add(first[0], add(scale(first[1], x1[0]), scale(first[2], x1[1])))
    v3 = add(third[0], add(scale(third[1], x3[0]), scale(third[2], x3[1])))
    out[found, 0] = math.atan2(x1[1], x1[0])
    out[found, 1], _ = sp1(k2, v3, v1)
    out[found, 2] = math.atan2(x3[1], x3[0])
    out[found, 3] = 1.0 if tangent else 0.0
    return found + 1


@numba.njit(**COMPILE)
def _sp5_flat(first, third, flat_first, k2, scale2, out):
    """SP5 when one circle keeps a constant height.

    SP5 when one circle keeps a constant height (its axis ∥ k2): H is that height; the
    other circle is cut at H (two points), and the flat circle is cut where its length
    matches (two points each). Returns how many rows were written.
    """
    moving = third if flat_first else first
    fixed = first if flat_first else third
    H = fixed[3]
    found = 0
    for sign in (1.0, -1.0):
        xc, xs, slack = _line_cut(moving[4], moving[5], H - moving[3], sign)
        bx, by = fixed[7], fixed[8]
        if slack < -SP5_TANGENT * scale2 or bx * bx + by * by <= 1e-24 * scale2:
            continue
        length = moving[6] + 2.0 * (xc * moving[7] + xs * moving[8])
        for other in (1.0, -1.0):
            yc, ys, slack2 = _line_cut(bx, by, 0.5 * (length - fixed[6]), other)
            if slack2 < -SP5_TANGENT * scale2 or found >= 4:
                continue
            tangent = min(slack, slack2) <= SP5_TANGENT * scale2
            if flat_first:
                found = _emit(first, (yc, ys), third, (xc, xs), k2, tangent, out, found)
            else:
                found = _emit(first, (xc, xs), third, (yc, ys), k2, tangent, out, found)
    return found


@numba.njit(**COMPILE)
def _sp5_at_height(first, third, H, double, k2, scale2, out, found):
    """The rows of SP5 at one height.

    The rows of SP5 at one height H (``double``: a double root of the quartic): each pair
    of branches (σ1, σ3) whose lengths match. Returns the new count.
    """
    for s1 in (1.0, -1.0):
        x1c, x1s, q1 = _line_cut(first[4], first[5], H - first[3], s1)
        if q1 < -SP5_TANGENT * scale2:
            continue
        length1 = first[6] + 2.0 * (x1c * first[7] + x1s * first[8])
        for s3 in (1.0, -1.0):
            x3c, x3s, q3 = _line_cut(third[4], third[5], H - third[3], s3)
            if q3 < -SP5_TANGENT * scale2 or found >= 4:
                continue
            length3 = third[6] + 2.0 * (x3c * third[7] + x3s * third[8])
            if abs(length1 - length3) <= SP5_MATCH * scale2:
                tangent = double or min(q1, q3) <= SP5_TANGENT * scale2
                found = _emit(first, (x1c, x1s), third, (x3c, x3s), k2, tangent, out, found)
    return found


@numba.njit(**COMPILE)
def sp5(p0, k1, p1, k2, p2, k3, p3, out):
    """SP5: ``p0 + rot(k1, θ1) p1 = rot(k2, θ2)(p2 + rot(k3, θ3) p3)`` (module docstring).

    Args:
        p0: The offset of the first circle's centre (3-tuple).
        k1: The first unit axis.
        p1: The vector it turns.
        k2: The unit axis of the middle rotation.
        p2: The offset inside the middle rotation.
        k3: The third unit axis.
        p3: The vector it turns.
        out: A (4, 4) array for the rows ``(θ1, θ2, θ3, tangent)``, ``tangent`` 1 where two
            solutions merge (a double root of the quartic, or a line touching its circle).

    Returns:
        How many rows were written (0 to 4).
    """
    first = _circle(p0, k1, p1, k2)
    third = _circle(p2, k3, p3, k2)
    scale2 = max(first[6], third[6], 1e-300)
    flat_first = first[4] ** 2 + first[5] ** 2 <= 1e-20 * scale2
    flat_third = third[4] ** 2 + third[5] ** 2 <= 1e-20 * scale2
    if flat_first and flat_third:
        return 0
    if flat_first or flat_third:
        return _sp5_flat(first, third, flat_first, k2, scale2, out)
    heights = np.empty(4)
    double = np.zeros(4, np.bool_)
    found = 0
    for r in range(_heights(first, third, heights, double)):
        found = _sp5_at_height(first, third, heights[r], double[r], k2, scale2, out, found)
    return found


# --------------------------------------------------------------------------------------
# SP6


@numba.njit(**COMPILE)
def _linear(h, k, v):
    """``h·rot(k, θ) v = c + e cos θ + f sin θ`` → ``(c, e, f)``."""
    kv = dot(k, v)
    return dot(h, k) * kv, dot(h, v) - dot(h, k) * kv, dot(h, cross(k, v))


@numba.njit(**COMPILE)
def _conic_quartic(N, m):
    """SP6's quartic in the half-angle tangent.

    The quartic in ``t = tan(φ/2)``, ``φ = θ − ω`` (ω = :data:`SP6_OFFSET`), of
    ``‖m + N (cos θ, sin θ)‖² = 1``, highest power first.
    """
    co, so = math.cos(SP6_OFFSET), math.sin(SP6_OFFSET)
    P00, P01 = N[0] * co + N[1] * so, -N[0] * so + N[1] * co
    P10, P11 = N[2] * co + N[3] * so, -N[2] * so + N[3] * co
    s11, s12, s22 = P00 * P00 + P10 * P10, P00 * P01 + P10 * P11, P01 * P01 + P11 * P11
    g1, g2 = P00 * m[0] + P10 * m[1], P01 * m[0] + P11 * m[1]
    f0 = m[0] * m[0] + m[1] * m[1] - 1.0
    poly = np.empty(5)
    poly[0] = s11 - 2.0 * g1 + f0
    poly[1] = 4.0 * (g2 - s12)
    poly[2] = 4.0 * s22 - 2.0 * s11 + 2.0 * f0
    poly[3] = 4.0 * (s12 + g2)
    poly[4] = s11 + 2.0 * g1 + f0
    return poly


@numba.njit(**COMPILE)
def sp6_linear(A, b, out):
    """SP6 in its linear form.

    SP6 in its linear form: ``(θ1, θ2)`` with ``A[:, 0:2] u1 + A[:, 2:4] u2 = b`` on the
    unit circles ``u_i = (cos θ_i, sin θ_i)`` (module docstring).

    Args:
        A: (2, 4) coefficients.
        b: (2,) right-hand side.
        out: A (4, 3) array for the rows ``(θ1, θ2, tangent)``, ``tangent`` 1 at a double
            root (two solutions merge).

    Returns:
        How many rows were written (0 to 4; 0 when neither 2 × 2 block is invertible).
    """
    det1 = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    det2 = A[0, 2] * A[1, 3] - A[0, 3] * A[1, 2]
    # Keep the angle whose block is worse conditioned; eliminate the other.
    swap = abs(det1) > abs(det2)
    kept, gone = (2, 0) if swap else (0, 2)
    det = det1 if swap else det2
    if det == 0.0:
        return 0
    inv = (A[1, gone + 1] / det, -A[0, gone + 1] / det, -A[1, gone] / det, A[0, gone] / det)
    m = (inv[0] * b[0] + inv[1] * b[1], inv[2] * b[0] + inv[3] * b[1])
    N = (
        -(inv[0] * A[0, kept] + inv[1] * A[1, kept]),
        -(inv[0] * A[0, kept + 1] + inv[1] * A[1, kept + 1]),
        -(inv[2] * A[0, kept] + inv[3] * A[1, kept]),
        -(inv[2] * A[0, kept + 1] + inv[3] * A[1, kept + 1]),
    )
    roots = np.empty(4)
    poly = _conic_quartic(N, m)
    count = real_roots(poly, roots)
    for r in range(count):
        out[r, 2] = 1.0 if near_double(poly, roots[r], DOUBLE_ROOT) else 0.0
        theta = 2.0 * math.atan(roots[r]) + SP6_OFFSET
        c, s = math.cos(theta), math.sin(theta)
        other = math.atan2(m[1] + N[2] * c + N[3] * s, m[0] + N[0] * c + N[1] * s)
        out[r, 0], out[r, 1] = (other, theta) if swap else (theta, other)
    return count


@numba.njit(**COMPILE)
def sp6(h1, k1, p1, h2, k2, p2, h3, k3, p3, h4, k4, p4, d1, d2, out):
    """SP6: two angles from two equations in both.

    SP6: ``(θ1, θ2)`` with ``h1·rot(k1, θ1) p1 + h2·rot(k2, θ2) p2 = d1`` and
    ``h3·rot(k3, θ1) p3 + h4·rot(k4, θ2) p4 = d2`` (module docstring).

    Args:
        h1: The direction the first term of the first equation is read along.
        k1: The unit axis θ1 turns in it.
        p1: The vector θ1 turns.
        h2: The direction of the first equation's second term.
        k2: The unit axis θ2 turns in it.
        p2: The vector θ2 turns.
        h3: As h1 for the second equation.
        k3: As k1 for the second equation.
        p3: As p1 for the second equation.
        h4: As h2 for the second equation.
        k4: As k2 for the second equation.
        p4: As p2 for the second equation.
        d1: The first right-hand side.
        d2: The second right-hand side.
        out: A (4, 3) array for the rows ``(θ1, θ2, tangent)`` (:func:`sp6_linear`).

    Returns:
        How many rows were written (0 to 4).
    """
    A = np.empty((2, 4))
    b = np.empty(2)
    c1, A[0, 0], A[0, 1] = _linear(h1, k1, p1)
    c2, A[0, 2], A[0, 3] = _linear(h2, k2, p2)
    c3, A[1, 0], A[1, 1] = _linear(h3, k3, p3)
    c4, A[1, 2], A[1, 3] = _linear(h4, k4, p4)
    b[0], b[1] = d1 - c1 - c2, d2 - c3 - c4
    return sp6_linear(A, b, out)
