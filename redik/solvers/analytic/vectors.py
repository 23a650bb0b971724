r"""3-vectors as tuples of floats, compiled: the arithmetic of every closed-form kernel.

A kernel moves a handful of 3-vectors per solution; as tuples they live in registers and no
array is allocated on the hot path. ``rot(k, θ) p = p cos θ + (k × p) sin θ + k (k·p)(1 − cos θ)``
is Rodrigues' formula for a unit axis ``k`` (Murray, Li & Sastry 1994, §2.2).
"""

from __future__ import annotations

import math

import numba

from redik.kinematics.compiled import COMPILE


@numba.njit(**COMPILE)
def dot(a, b):
    """``a · b``."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@numba.njit(**COMPILE)
def cross(a, b):
    """``a × b``."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@numba.njit(**COMPILE)
def add(a, b):
    """``a + b``."""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@numba.njit(**COMPILE)
def sub(a, b):
    """``a − b``."""
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@numba.njit(**COMPILE)
def scale(a, s):
    """``s a``."""
    return (a[0] * s, a[1] * s, a[2] * s)


@numba.njit(**COMPILE)
def neg(a):
    """``−a``."""
    return (-a[0], -a[1], -a[2])


@numba.njit(**COMPILE)
def norm(a):
    """``‖a‖`` (not ``hypot``: a libm call several times slower)."""
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
def row(G, i):
    """Row ``i`` of a 2-D array as a 3-tuple."""
    return (G[i, 0], G[i, 1], G[i, 2])


@numba.njit(**COMPILE)
def mul(r0, r1, r2, v):
    """``R v`` for the rows ``r0, r1, r2`` of ``R``."""
    return (dot(r0, v), dot(r1, v), dot(r2, v))


@numba.njit(**COMPILE)
def mul_t(r0, r1, r2, v):
    """``Rᵀ v`` for the rows ``r0, r1, r2`` of ``R``."""
    return add(add(scale(r0, v[0]), scale(r1, v[1])), scale(r2, v[2]))
