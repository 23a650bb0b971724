r"""The joint-space tasks' gradient on a robot with ball or free joints, compiled.

Each joint-space task of a level adds :math:`α w^2 d^2 \odot (q \ominus r)` to the level's
linear term (:meth:`redik.qp.assembly.LevelAssembly.joint_gradient_into`). Across hinge and
slide joints, and a free joint's position, :math:`q \ominus r` is the difference of the
coordinates; across a ball joint, or a free joint's orientation, it is the rotation vector of
:math:`\bar r \otimes q` (the quaternions normalised first), as ``mj_differentiatePos``
computes it with ``dt = 1``: ``mju_subQuat`` then ``mju_quat2Vel``, the angle taken in
:math:`(-π, π]` (:mod:`redik.core.conventions`).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.compiled import COMPILE

_MINVAL = 1e-15
"""``mjMINVAL``: below this norm MuJoCo's normalisations give a fixed unit vector."""


@numba.njit(**COMPILE)
def _unit_quaternion(q: NDArray[np.float64], start: int, out: NDArray[np.float64]) -> None:
    """``mju_normalize4`` of ``q[start:start + 4]`` into ``out``."""
    w, x, y, z = q[start], q[start + 1], q[start + 2], q[start + 3]
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    if norm < _MINVAL:
        out[0], out[1], out[2], out[3] = 1.0, 0.0, 0.0, 0.0
        return
    scale = 1.0 / norm if abs(norm - 1.0) > _MINVAL else 1.0
    for i in range(4):
        out[i] = q[start + i] * scale


@numba.njit(**COMPILE)
def rotation_difference(
    q: NDArray[np.float64],
    r: NDArray[np.float64],
    start: int,
    work: NDArray[np.float64],
) -> None:
    r"""Write the rotation vector of :math:`\bar r \otimes q` (module docstring), ``work[8:11]``.

    Args:
        q: A configuration.
        r: The reference configuration.
        start: Where the quaternion starts in both.
        work: Scratch (≥ 11); ``work[8:11]`` receives the result.
    """
    a, b = work[0:4], work[4:8]
    _unit_quaternion(r, start, a)
    _unit_quaternion(q, start, b)
    a[1], a[2], a[3] = -a[1], -a[2], -a[3]
    w = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3]
    x = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2]
    y = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1]
    z = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]
    sin_half = math.sqrt(x * x + y * y + z * z)
    if sin_half < _MINVAL:
        x, y, z = 1.0, 0.0, 0.0
    else:
        inverse = 1.0 / sin_half
        x, y, z = x * inverse, y * inverse, z * inverse
    angle = 2.0 * math.atan2(sin_half, w)
    if angle > math.pi:
        angle -= 2.0 * math.pi
    work[8], work[9], work[10] = x * angle, y * angle, z * angle


@numba.njit(**COMPILE)
def joint_gradients(
    q: NDArray[np.float64],
    references: NDArray[np.float64],
    factors: NDArray[np.float64],
    level_of: NDArray[np.int64],
    count: int,
    linear_q: NDArray[np.int64],
    rotations: NDArray[np.int64],
    gradients: NDArray[np.float64],
) -> None:
    """Write each level's ``Σ α w²d² ⊙ (q ⊖ r)`` over its joint-space tasks into ``gradients``.

    Args:
        q: The configuration (nq,).
        references: Per task, its reference ``r`` (≥ count × nq).
        factors: Per task, its ``α w²d²`` (≥ count × n).
        level_of: Per task, its level.
        count: How many tasks.
        linear_q: Per tangent coordinate, its index in ``q`` where ``q ⊖ r`` is a difference of
            coordinates, else −1.
        rotations: Per ball joint or free joint's orientation, ``(quaternion's start in q,
            first tangent coordinate)``.
        gradients: Written (levels × n).
    """
    gradients[:] = 0.0
    work = np.empty(11)
    for t in range(count):
        g, r, factor = gradients[level_of[t]], references[t], factors[t]
        for i in range(linear_q.shape[0]):
            if linear_q[i] >= 0:
                g[i] += factor[i] * (q[linear_q[i]] - r[linear_q[i]])
        for k in range(rotations.shape[0]):
            rotation_difference(q, r, rotations[k, 0], work)
            for axis in range(3):
                i = rotations[k, 1] + axis
                g[i] += factor[i] * work[8 + axis]
