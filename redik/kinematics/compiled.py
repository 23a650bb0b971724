r"""Compiled kinematics of a :class:`~redik.kinematics.chain.Chain`: FK, world Jacobian, pose error.

The scalar building blocks of every compiled pose solver (:mod:`redik.solvers.dls`, which
:func:`redik.solvers.batch.solve_batch` and :func:`redik.solve_pose` with ``method="dls"``
run) and of :class:`redik.tasks.frame_task.FrameTask`'s residual, compiled by numba
(``cache=True``).

The chain is ``T(q) = F_0 M_1(q_1) F_1 ⋯ M_n(q_n) F_n``; FK walks it joint by joint and the
world Jacobian (``"world"`` in :mod:`redik.core.conventions`) follows from each joint's world axis
``ω_i`` and origin ``o_i``: ``J_i = (ω_i × (p − o_i), ω_i)`` for a hinge, ``(ω_i, 0)`` for a
slide. The pose error is ``e = (p_d − p, log(R_d Rᵀ)^∨)``.

Why redik keeps its own rather than MuJoCo's ``mj_kinematics``/``mj_jacSite`` (or mink's
``Configuration``, which calls them) and numpy's :func:`redik.lie.rotation_log`: inside a
Levenberg–Marquardt iteration these run on a handful of 3-vectors per target, where any call
into MuJoCo or numpy from Python costs more than the arithmetic, and a compiled kernel cannot
call MuJoCo at all (``redik bench kinematics`` measures both forms). Each function has a reference
it is tested equal to: the FK and Jacobian MuJoCo's (``tests/test_batch_kernel.py``, to 1e-12),
:func:`pose_error` the numpy :func:`redik.lie.rotation_log` at every angle
(``test_kernel_pose_error_matches_the_batched_rotation_log``), which ``tests/test_batch_solve.py``
pins to :func:`redik.lie.so3_log`.
"""

from __future__ import annotations

import math
from typing import Literal, TypedDict

import numba
import numpy as np
from numpy.typing import NDArray

from redik.core.validate import MAX_COORDINATE


class CompileOptions(TypedDict):
    """The keyword arguments of ``numba.njit`` that :data:`COMPILE` sets."""

    cache: bool
    error_model: Literal["python", "numpy"]
    fastmath: set[str]


COMPILE: CompileOptions = {"cache": True, "error_model": "numpy", "fastmath": {"contract"}}
"""numba options of every compiled kernel of redik: compiled once per machine; a division
by zero gives inf or NaN as in numpy (every such result is caught as a non-finite step), not
a Python exception, so divisions carry no checks; fused multiply-adds are allowed (no
reassociation: results stay reproducible)."""


@numba.njit(**COMPILE)
def valid_target(T: NDArray[np.float64], tol: float) -> bool:
    """Whether ``T`` is a rigid transform to use as it is.

    As :func:`~redik.core.rotation_policy.as_pose` checks it: finite, last row
    ``[0, 0, 0, 1]``, ``RᵀR = I`` and ``det R = 1``, each within ``tol``, and a translation
    within ``±MAX_COORDINATE``.
    """
    for a in range(4):
        for b in range(4):
            if not math.isfinite(T[a, b]):
                return False
    if abs(T[0, 3]) > MAX_COORDINATE or abs(T[1, 3]) > MAX_COORDINATE:
        return False
    if abs(T[2, 3]) > MAX_COORDINATE:
        return False
    if abs(T[3, 0]) > tol or abs(T[3, 1]) > tol or abs(T[3, 2]) > tol or abs(T[3, 3] - 1.0) > tol:
        return False
    for a in range(3):
        for b in range(a + 1):
            product = T[0, a] * T[0, b] + T[1, a] * T[1, b] + T[2, a] * T[2, b]
            if abs(product - (1.0 if a == b else 0.0)) > tol:
                return False
    det: float = (
        T[0, 0] * (T[1, 1] * T[2, 2] - T[1, 2] * T[2, 1])
        - T[0, 1] * (T[1, 0] * T[2, 2] - T[1, 2] * T[2, 0])
        + T[0, 2] * (T[1, 0] * T[2, 1] - T[1, 1] * T[2, 0])
    )
    return abs(det - 1.0) <= tol


@numba.njit(parallel=True, **COMPILE)
def valid_targets(T: NDArray[np.float64], tol: float, out: NDArray[np.bool_]) -> None:
    """``out[t]`` = :func:`valid_target` of each ``T[t]`` (B × 4 × 4), over every thread."""
    for t in numba.prange(T.shape[0]):
        out[t] = valid_target(T[t], tol)


@numba.njit(**COMPILE)
def chain_kinematics(
    base: NDArray[np.float64],
    links: NDArray[np.float64],
    revolute: NDArray[np.bool_],
    q: NDArray[np.float64],
    R: NDArray[np.float64],
    p: NDArray[np.float64],
    axes: NDArray[np.float64],
    origins: NDArray[np.float64],
) -> None:
    """Forward kinematics of the chain at ``q``, into the caller's buffers.

    Writes the pose into ``R`` (3 × 3) and ``p``, and each joint's world axis and origin
    into ``axes`` and ``origins`` (n × 3).
    """
    for a in range(3):
        p[a] = base[a, 3]
        for b in range(3):
            R[a, b] = base[a, b]
    for i in range(q.shape[0]):
        for a in range(3):
            axes[i, a] = R[a, 2]
            origins[i, a] = p[a]
        if revolute[i]:  # R · R_z(q): the x and y columns turn
            c, s = math.cos(q[i]), math.sin(q[i])
            for a in range(3):
                x, y = R[a, 0], R[a, 1]
                R[a, 0] = c * x + s * y
                R[a, 1] = c * y - s * x
        else:
            for a in range(3):
                p[a] += R[a, 2] * q[i]
        for a in range(3):
            r0, r1, r2 = R[a, 0], R[a, 1], R[a, 2]
            p[a] += r0 * links[i, 0, 3] + r1 * links[i, 1, 3] + r2 * links[i, 2, 3]
            for b in range(3):
                R[a, b] = r0 * links[i, 0, b] + r1 * links[i, 1, b] + r2 * links[i, 2, b]


@numba.njit(**COMPILE)
def world_jacobian(
    revolute: NDArray[np.bool_],
    p: NDArray[np.float64],
    axes: NDArray[np.float64],
    origins: NDArray[np.float64],
    J: NDArray[np.float64],
) -> None:
    """The world Jacobian (6 × n) from :func:`chain_kinematics`' axes and origins."""
    for i in range(revolute.shape[0]):
        ax, ay, az = axes[i, 0], axes[i, 1], axes[i, 2]
        if revolute[i]:
            dx, dy, dz = p[0] - origins[i, 0], p[1] - origins[i, 1], p[2] - origins[i, 2]
            J[0, i] = ay * dz - az * dy
            J[1, i] = az * dx - ax * dz
            J[2, i] = ax * dy - ay * dx
            J[3, i], J[4, i], J[5, i] = ax, ay, az
        else:
            J[0, i], J[1, i], J[2, i] = ax, ay, az
            J[3, i] = J[4, i] = J[5, i] = 0.0


@numba.njit(**COMPILE)
def pose_error(
    Rd: NDArray[np.float64],
    pd: NDArray[np.float64],
    R: NDArray[np.float64],
    p: NDArray[np.float64],
    e: NDArray[np.float64],
) -> tuple[float, float]:
    r"""Fill ``e = (p_d − p, log(R_d Rᵀ)^∨)``; return ``(‖p_d − p‖, rotation angle)``.

    From the skew part ``s = sin θ u`` and ``cos θ = (tr − 1)/2``, ``θ = atan2(‖s‖, cos θ)``
    is accurate at every angle; near ``θ = π``, where ``s`` loses its direction, the axis
    comes from the symmetric part ``(E + Eᵀ)/2 − cos θ I = (1 − cos θ) u uᵀ``.
    """
    for i in range(3):
        e[i] = pd[i] - p[i]
    # E = R_d Rᵀ, entry by entry (no temporary array in the hot loop).
    e00 = Rd[0, 0] * R[0, 0] + Rd[0, 1] * R[0, 1] + Rd[0, 2] * R[0, 2]
    e01 = Rd[0, 0] * R[1, 0] + Rd[0, 1] * R[1, 1] + Rd[0, 2] * R[1, 2]
    e02 = Rd[0, 0] * R[2, 0] + Rd[0, 1] * R[2, 1] + Rd[0, 2] * R[2, 2]
    e10 = Rd[1, 0] * R[0, 0] + Rd[1, 1] * R[0, 1] + Rd[1, 2] * R[0, 2]
    e11 = Rd[1, 0] * R[1, 0] + Rd[1, 1] * R[1, 1] + Rd[1, 2] * R[1, 2]
    e12 = Rd[1, 0] * R[2, 0] + Rd[1, 1] * R[2, 1] + Rd[1, 2] * R[2, 2]
    e20 = Rd[2, 0] * R[0, 0] + Rd[2, 1] * R[0, 1] + Rd[2, 2] * R[0, 2]
    e21 = Rd[2, 0] * R[1, 0] + Rd[2, 1] * R[1, 1] + Rd[2, 2] * R[1, 2]
    e22 = Rd[2, 0] * R[2, 0] + Rd[2, 1] * R[2, 1] + Rd[2, 2] * R[2, 2]
    sx, sy, sz = 0.5 * (e21 - e12), 0.5 * (e02 - e20), 0.5 * (e10 - e01)
    cos = 0.5 * (e00 + e11 + e22 - 1.0)
    sin = math.sqrt(sx * sx + sy * sy + sz * sz)
    angle = math.atan2(sin, cos)
    scale = angle / sin if sin > 1e-300 else 1.0
    e[3], e[4], e[5] = sx * scale, sy * scale, sz * scale
    if cos < 0.0 and sin < 1e-6:
        # The column of the largest diagonal entry of the symmetric part is the best axis.
        if e00 >= e11 and e00 >= e22:
            ux, uy, uz = e00 - cos, 0.5 * (e10 + e01), 0.5 * (e20 + e02)
        elif e11 >= e22:
            ux, uy, uz = 0.5 * (e01 + e10), e11 - cos, 0.5 * (e21 + e12)
        else:
            ux, uy, uz = 0.5 * (e02 + e20), 0.5 * (e12 + e21), e22 - cos
        norm = math.sqrt(ux * ux + uy * uy + uz * uz)
        sign = -1.0 if ux * e[3] + uy * e[4] + uz * e[5] < 0.0 else 1.0
        scale = sign * angle / norm
        e[3], e[4], e[5] = ux * scale, uy * scale, uz * scale
    position = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    return position, angle
