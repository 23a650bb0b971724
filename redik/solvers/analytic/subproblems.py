r"""Paden–Kahan subproblems, compiled: the geometric building blocks of closed-form 6R IK.

Each subproblem asks for the joint angle(s) of one or two revolute axes through the origin
that move given vectors into a given relation (Paden 1985; Murray, Li & Sastry 1994, §3.2.2;
Elias & Wen 2022, "IK-Geo", arXiv 2211.05737, whose numbering and forms these follow).
``rot(k, θ) p = p cos θ + (k × p) sin θ + k (k·p)(1 − cos θ)`` (Rodrigues), ``k`` a unit axis.

SP1
    ``rot(k, θ) p1 = p2``: with :math:`a, b` the parts of p1, p2 perpendicular to k,
    :math:`θ = \operatorname{atan2}(k·(a × b),\; a·b)`. One solution; any θ when a = 0.
SP2
    ``rot(k1, θ1) p1 = rot(k2, θ2) p2`` (k1 ∦ k2): the common image
    :math:`x = α k_1 + β k_2 + γ (k_1 × k_2)` keeps the axial components,
    :math:`k_1·x = k_1·p_1`, :math:`k_2·x = k_2·p_2`, and the length ‖x‖ = ‖p2‖, so
    γ = ±√(…)/‖k1 × k2‖: two solutions, then SP1 on each axis.
SP3
    ``‖rot(k, θ) p1 − p2‖ = d``: with a, b the perpendicular parts and
    :math:`δ = k·(p_1 − p_2)`, :math:`\cos(θ − φ) = (‖a‖^2 + ‖b‖^2 + δ^2 − d^2) / (2‖a‖‖b‖)`,
    φ the SP1 angle from a to b: two solutions :math:`θ = φ ± \arccos(⋅)`.
SP4
    ``h·rot(k, θ) p = d``: :math:`A \cos θ + B \sin θ = C` with
    :math:`A = h·p − (h·k)(k·p)`, :math:`B = h·(k × p)`, :math:`C = d − (h·k)(k·p)`:
    two solutions :math:`θ = \operatorname{atan2}(B, A) ± \arccos(C / \sqrt{A^2 + B^2})`.

Vectors are 3-tuples of floats (no array is allocated on the hot path). SP3 and SP4 return a
status: :data:`OK`, :data:`BOUNDARY` (the two solutions coincide: the target is within ``tol``
of the edge of the reachable set and was clipped onto it), :data:`OUT` (no solution) or
:data:`FREE` (the equation does not depend on θ and holds: any θ solves it).
"""

from __future__ import annotations

import math

import numba

from redik.kinematics.compiled import COMPILE

OK, BOUNDARY, OUT, FREE = 0, 1, 2, 3


@numba.njit(**COMPILE)
def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@numba.njit(**COMPILE)
def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@numba.njit(**COMPILE)
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@numba.njit(**COMPILE)
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@numba.njit(**COMPILE)
def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


@numba.njit(**COMPILE)
def norm(a):
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@numba.njit(**COMPILE)
def perp(k, p):
    """The part of ``p`` perpendicular to the unit axis ``k``."""
    return sub(p, scale(k, dot(k, p)))


@numba.njit(**COMPILE)
def rotate_cs(k, c, s, p):
    """``rot(k, θ) p`` for ``c = cos θ``, ``s = sin θ`` (Rodrigues' formula)."""
    kp = dot(k, p) * (1.0 - c)
    return (
        p[0] * c + (k[1] * p[2] - k[2] * p[1]) * s + k[0] * kp,
        p[1] * c + (k[2] * p[0] - k[0] * p[2]) * s + k[1] * kp,
        p[2] * c + (k[0] * p[1] - k[1] * p[0]) * s + k[2] * kp,
    )


@numba.njit(**COMPILE)
def rotate(k, theta, p):
    """``rot(k, θ) p``."""
    return rotate_cs(k, math.cos(theta), math.sin(theta), p)


@numba.njit(**COMPILE)
def sp1_cs(k, p1, p2):
    """SP1: θ with ``rot(k, θ) p1 = p2`` (least squares in the plane ⊥ k), its cosine and
    sine (read off the projections, no trigonometric call) and ``‖a‖``, the length of p1's
    perpendicular part (θ is arbitrary when it is 0; then cos θ = 1)."""
    a = perp(k, p1)
    b = perp(k, p2)
    y, x = dot(k, cross(a, b)), dot(a, b)
    r = math.sqrt(x * x + y * y)  # (not hypot: a libm call several times slower)
    if r == 0.0:
        return 0.0, 1.0, 0.0, norm(a)
    return math.atan2(y, x), x / r, y / r, norm(a)


@numba.njit(**COMPILE)
def sp1(k, p1, p2):
    """SP1 without the cosine and sine: ``(θ, ‖a‖)`` (see :func:`sp1_cs`)."""
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
    """SP3: ``(θ+, θ−, status, cos θ+, sin θ+, cos θ−, sin θ−)`` with
    ``‖rot(k, θ) p1 − p2‖ = d``.

    The reachable distances run from ``√((‖a‖ − ‖b‖)² + δ²)`` to ``√((‖a‖ + ‖b‖)² + δ²)``;
    ``d`` within ``tol`` (m) outside that range is clipped onto it (status BOUNDARY).
    """
    a = perp(k, p1)
    b = perp(k, p2)
    na, nb = norm(a), norm(b)
    delta = dot(k, p1) - dot(k, p2)
    if na * nb <= tol * tol:
        distance = math.sqrt((na - nb) ** 2 + delta * delta)
        return 0.0, 0.0, (FREE if abs(distance - d) <= tol else OUT), 1.0, 0.0, 1.0, 0.0
    y, x = dot(k, cross(a, b)), dot(a, b)
    phi = math.atan2(y, x)
    nearest = math.sqrt((na - nb) ** 2 + delta * delta)
    farthest = math.sqrt((na + nb) ** 2 + delta * delta)
    cosine = (na * na + nb * nb + delta * delta - d * d) / (2.0 * na * nb)
    status = OK
    if d < nearest - tol or d > farthest + tol:
        status = OUT
    elif abs(d - nearest) <= tol or abs(d - farthest) <= tol:
        status = BOUNDARY
    spread = math.acos(min(max(cosine, -1.0), 1.0))
    r = na * nb
    cp, sp, cm, sm = _roots_cs(x / r, y / r, cosine)
    return phi + spread, phi - spread, status, cp, sp, cm, sm


@numba.njit(**COMPILE)
def sp3(k, p1, p2, d, tol):
    """SP3 without cosines and sines: ``(θ+, θ−, status)`` (see :func:`sp3_cs`)."""
    plus, minus, status, _, _, _, _ = sp3_cs(k, p1, p2, d, tol)
    return plus, minus, status


@numba.njit(**COMPILE)
def sp4_cs(h, k, p, d, tol):
    """SP4: ``(θ+, θ−, status, cos θ+, sin θ+, cos θ−, sin θ−)`` with ``h · rot(k, θ) p = d``;
    ``C`` within ``tol`` outside ``[−r, r]`` is clipped (status BOUNDARY)."""
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
    phi = math.atan2(B, A)
    spread = math.acos(min(max(C / r, -1.0), 1.0))
    cp, sp, cm, sm = _roots_cs(A / r, B / r, C / r)
    return phi + spread, phi - spread, status, cp, sp, cm, sm


@numba.njit(**COMPILE)
def sp4(h, k, p, d, tol):
    """SP4 without cosines and sines: ``(θ+, θ−, status)`` (see :func:`sp4_cs`)."""
    plus, minus, status, _, _, _, _ = sp4_cs(h, k, p, d, tol)
    return plus, minus, status


@numba.njit(**COMPILE)
def sp2_cs(k1, p1, k2, p2, fixed1, fixed2, tol):
    """SP2: ``(θ1+, θ2+, θ1−, θ2−, status, free, trig)`` with
    ``rot(k1, θ1) p1 = rot(k2, θ2) p2`` (k1 ∦ k2, ‖p1‖ = ‖p2‖), ``trig`` the cosines and
    sines ``(c1+, s1+, c2+, s2+, c1−, s1−, c2−, s2−)``.

    ``free`` is 0 normally, 1 when p1 lies on k1 (θ1 arbitrary: it takes ``fixed1``), 2 when
    p2 lies on k2 (θ2 takes ``fixed2``); then the two solutions are the same.
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
    length2 = 0.5 * (dot(p1, p1) + dot(p2, p2))
    rest = length2 - alpha * alpha - beta * beta - 2.0 * alpha * beta * c12
    n = cross(k1, k2)
    # γ‖k1 × k2‖ is the distance of x from the plane of k1 and k2 (m).
    height = math.sqrt(max(rest, 0.0))
    status = OK
    scale_length = math.sqrt(length2)
    if rest < -2.0 * tol * scale_length:
        status = OUT
    elif height <= tol:
        status = BOUNDARY
    gamma = height / math.sqrt(w)
    base = add(scale(k1, alpha), scale(k2, beta))
    xa = add(base, scale(n, gamma))
    xb = sub(base, scale(n, gamma))
    t1a, c1a, s1a, _ = sp1_cs(k1, p1, xa)
    t2a, c2a, s2a, _ = sp1_cs(k2, p2, xa)
    t1b, c1b, s1b, _ = sp1_cs(k1, p1, xb)
    t2b, c2b, s2b, _ = sp1_cs(k2, p2, xb)
    return t1a, t2a, t1b, t2b, status, 0, (c1a, s1a, c2a, s2a, c1b, s1b, c2b, s2b)
