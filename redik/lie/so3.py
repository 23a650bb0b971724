r"""The rotation group SO(3): skew matrices, exp and log, quaternions, left Jacobians, SLERP.

Conventions (scalar-first quaternions ``(w, x, y, z)``, exponential coordinates ``ω = θ u``)
are those of :mod:`redik.core.conventions`. Formulas follow Lynch & Park, *Modern Robotics*
(2017), §3.2.3:

.. math::

    \exp([ω]) = I + \frac{\sin θ}{θ}[ω] + \frac{1 - \cos θ}{θ^2}[ω]^2, \qquad θ = ‖ω‖,

and Barfoot, *State Estimation for Robotics* (2017), §7.1.5 for the inverse left Jacobian.
Quaternion conversions, the log, and SLERP are MuJoCo's ``mju_*`` functions. The maps take
validated float input unchecked (:mod:`redik.core.validate`).
"""

from __future__ import annotations

import math

import mujoco
import numba
import numpy as np
from numpy.typing import NDArray

_SMALL_ANGLE = 1e-6  # below it, exp's coefficients by their series
_SERIES_ANGLE = 1e-3  # below it, the inverse Jacobians' coefficients by their series


def skew(w: NDArray[np.float64]) -> NDArray[np.float64]:
    """The skew-symmetric matrix ``[w]`` with ``[w] x = w × x``.

    Args:
        w: A 3-vector, or a (..., 3) stack.

    Returns:
        ``[w]``, (3, 3), or (..., 3, 3) for a stack.
    """
    if np.ndim(w) == 1:
        return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])
    w = np.asarray(w, dtype=float)
    S = np.zeros((*w.shape[:-1], 3, 3))
    S[..., 0, 1], S[..., 0, 2], S[..., 1, 2] = -w[..., 2], w[..., 1], -w[..., 0]
    S[..., 1, 0], S[..., 2, 0], S[..., 2, 1] = w[..., 2], -w[..., 1], w[..., 0]
    return S


def quat_from_matrix(R: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit quaternion of a rotation matrix (``mju_mat2Quat``).

    Args:
        R: A rotation matrix (3, 3).

    Returns:
        ``(w, x, y, z)`` with ``w ≥ 0``.
    """
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(R, dtype=float).reshape(9))
    if quat[0] < 0.0:
        quat *= -1.0
    return quat


def matrix_from_quat(quat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation matrix of a quaternion (``mju_quat2Mat``).

    Args:
        quat: ``(w, x, y, z)``, normalised first.

    Returns:
        The rotation matrix (3, 3).
    """
    quat = np.array(quat, dtype=float)
    mujoco.mju_normalize4(quat)
    R = np.empty(9)
    mujoco.mju_quat2Mat(R, quat)
    return R.reshape(3, 3)


def so3_exp(omega: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rodrigues' formula: ``exp([ω]) ∈ SO(3)`` (Modern Robotics Prop. 3.11).

    Args:
        omega: Exponential coordinates ``ω = θ u`` (3,).

    Returns:
        The rotation matrix (3, 3).
    """
    wx, wy, wz = float(omega[0]), float(omega[1]), float(omega[2])
    theta2 = wx * wx + wy * wy + wz * wz
    theta = math.sqrt(theta2)
    if theta < _SMALL_ANGLE:
        a, b = 1.0 - theta2 / 6.0, 0.5 - theta2 / 24.0
    else:
        a, b = math.sin(theta) / theta, (1.0 - math.cos(theta)) / theta2
    return np.array(
        [
            [1.0 - b * (wy * wy + wz * wz), b * wx * wy - a * wz, b * wx * wz + a * wy],
            [b * wx * wy + a * wz, 1.0 - b * (wx * wx + wz * wz), b * wy * wz - a * wx],
            [b * wx * wz - a * wy, b * wy * wz + a * wx, 1.0 - b * (wx * wx + wy * wy)],
        ]
    )


def so3_log(R: NDArray[np.float64]) -> NDArray[np.float64]:
    """The logarithm: ``ω = θ u`` with ``exp([ω]) = R`` and ``θ ∈ [0, π]``.

    MuJoCo's: the quaternion (``mju_mat2Quat``, Shepperd's robust branch selection) and its
    rotation vector ``2 atan2(‖x‖, w) x/‖x‖`` (``mju_quat2Vel``, the angle brought into
    ``[−π, π]``), so it stays accurate at θ → 0 (no arccos of the trace) and at θ → π (no
    division by sin θ). Below ``θ = 2e-15`` ``mju_normalize3`` replaces the axis by ``x``;
    there the first-order ``ω = 2 x`` is exact to rounding and is used instead.

    Args:
        R: A rotation matrix (3, 3).

    Returns:
        ``ω`` (3,).
    """
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(R, dtype=float).reshape(9))
    omega = np.empty(3)
    mujoco.mju_quat2Vel(omega, quat, 1.0)
    if omega[1] == 0.0 == omega[2] and abs(quat[1]) < 1e-15:  # the axis MuJoCo substitutes
        np.multiply(quat[1:], 2.0 if quat[0] >= 0.0 else -2.0, out=omega)
    return omega


def rotation_log(
    Rd: NDArray[np.float64], R: NDArray[np.float64], out: NDArray[np.float64]
) -> NDArray[np.float64]:
    r"""The logarithm of ``R_d Rᵀ`` over a batch: ``ω = log(R_d Rᵀ)^∨``.

    From the skew part ``s = sin θ u`` and ``cos θ = (tr − 1)/2``, ``θ = atan2(‖s‖, cos θ)``
    is accurate at every angle; near ``θ = π``, where ``s`` loses its direction, the axis
    comes from the symmetric part ``(E + Eᵀ)/2 − cos θ I = (1 − cos θ) u uᵀ``. The batch is
    last, so that each entry is one vector operation over it. :func:`so3_log` is the
    one-rotation form; the compiled scalar twin is
    :func:`redik.kinematics.compiled.pose_error`, tested equal to this one.

    Args:
        Rd: Rotations (3, 3, A).
        R: Rotations (3, 3, A).
        out: Written with ``ω`` (3, A).

    Returns:
        The angles ``‖ω‖`` (A,).
    """
    E: NDArray[np.float64] = np.einsum("ikb,jkb->ijb", Rd, R)
    out[0] = 0.5 * (E[2, 1] - E[1, 2])
    out[1] = 0.5 * (E[0, 2] - E[2, 0])
    out[2] = 0.5 * (E[1, 0] - E[0, 1])
    cos = 0.5 * (E[0, 0] + E[1, 1] + E[2, 2] - 1.0)
    sin = np.sqrt(np.einsum("ib,ib->b", out, out))
    angle: NDArray[np.float64] = np.arctan2(sin, cos)
    scale = np.divide(angle, sin, out=np.ones_like(angle), where=sin > 1e-300)
    out *= scale
    flipped = np.flatnonzero((cos < 0.0) & (sin < 1e-6))
    if flipped.size:
        sym = 0.5 * (E[:, :, flipped] + E[:, :, flipped].transpose(1, 0, 2))
        sym -= np.eye(3)[:, :, None] * cos[flipped]
        column = np.argmax(np.diagonal(sym).T, axis=0)
        picked = np.take_along_axis(sym, column[None, None], axis=1)[:, 0]
        axis = picked / np.sqrt(np.einsum("ib,ib->b", picked, picked))
        sign = np.where(np.einsum("ib,ib->b", axis, out[:, flipped]) < 0.0, -1.0, 1.0)
        out[:, flipped] = axis * (sign * angle[flipped])
    return angle


@numba.njit(cache=True)
def left_jacobian_inverse_coefficients(theta2: float) -> tuple[float, float]:
    r"""The coefficients ``(k, b)`` of the inverse left Jacobians at ``θ² = theta2``.

    ``k = −A/θ² = (1 − (θ/2)\cot(θ/2))/θ²`` and ``b = −(A + Bθ²)/θ⁴`` of
    :func:`so3_left_jacobian_inverse` and :func:`redik.lie.se3.se3_left_jacobian_inverse`;
    below ``θ = 1e-3`` their series ``1/12 + θ²/720`` and ``−1/720``, exact there to the
    rounding of ``k`` while the closed forms lose digits to cancellation.

    Args:
        theta2: The squared angle ``θ²``.

    Returns:
        ``(k, b)``.
    """
    if theta2 < _SERIES_ANGLE * _SERIES_ANGLE:
        return 1.0 / 12.0 + theta2 / 720.0, -1.0 / 720.0
    theta = math.sqrt(theta2)
    half = 0.5 * theta
    cot = math.cos(half) / math.sin(half)
    A = half * cot - 1.0
    B = 1.0 / (8.0 * math.sin(half) ** 2) - cot / (4.0 * theta)
    return -A / theta2, -(A + B * theta2) / (theta2 * theta2)


@numba.njit(cache=True)
def apply_inverse_v(
    wx: float, wy: float, wz: float, dx: float, dy: float, dz: float
) -> tuple[float, float, float]:
    r"""``V(ω)⁻¹ d = d − ½ ω × d + k ω × (ω × d)``: the linear part of an SE(3) log.

    ``V(ω)`` is the left Jacobian of SO(3), so ``V⁻¹ = J_l⁻¹(ω) = I − ½[ω] + k [ω]²``
    (:func:`so3_left_jacobian_inverse`; Modern Robotics §3.3.3.2). Compiled, from floats, so
    that :func:`redik.lie.se3.se3_log` and the compiled pose residual
    (:func:`redik.tasks.frame_task.pose_residual`) call the same code.

    Args:
        wx: ``ω_x``.
        wy: ``ω_y``.
        wz: ``ω_z``.
        dx: ``d_x``.
        dy: ``d_y``.
        dz: ``d_z``.

    Returns:
        ``V(ω)⁻¹ d`` as three floats.
    """
    k = left_jacobian_inverse_coefficients(wx * wx + wy * wy + wz * wz)[0]
    ax, ay, az = wy * dz - wz * dy, wz * dx - wx * dz, wx * dy - wy * dx  # ω × d
    bx, by, bz = wy * az - wz * ay, wz * ax - wx * az, wx * ay - wy * ax  # ω × (ω × d)
    return dx - 0.5 * ax + k * bx, dy - 0.5 * ay + k * by, dz - 0.5 * az + k * bz


def so3_left_jacobian_inverse(omega: NDArray[np.float64]) -> NDArray[np.float64]:
    r"""The inverse left Jacobian ``J_l⁻¹(ω) = I − ½[ω] + k [ω]²`` of SO(3).

    ``k = (1 − (θ/2)\cot(θ/2))/θ²`` (Barfoot, *State Estimation for Robotics*, 2017,
    eq. 7.80): how ``log`` of a rotation moves under a left perturbation, and ``V(ω)⁻¹`` of
    :func:`apply_inverse_v`. Written with ``[ω]² = ωωᵀ − θ²I``. ``mink.SO3.ljacinv`` divides
    by ``1 − cos θ``, which loses the digits at small angles; this form does not.

    Args:
        omega: Exponential coordinates ``ω`` (3,).

    Returns:
        ``J_l⁻¹(ω)`` (3, 3).
    """
    wx, wy, wz = omega.tolist()
    theta2 = wx * wx + wy * wy + wz * wz
    k = left_jacobian_inverse_coefficients(theta2)[0]
    s = 1.0 - k * theta2
    return np.array(
        (
            (s + k * wx * wx, 0.5 * wz + k * wx * wy, -0.5 * wy + k * wx * wz),
            (-0.5 * wz + k * wy * wx, s + k * wy * wy, 0.5 * wx + k * wy * wz),
            (0.5 * wy + k * wz * wx, -0.5 * wx + k * wz * wy, s + k * wz * wz),
        )
    )


def slerp(q_a: NDArray[np.float64], q_b: NDArray[np.float64], t: float) -> NDArray[np.float64]:
    """Spherical linear interpolation between unit quaternions, along the shorter arc.

    ``slerp(q_a, q_b, t) = q_a exp(t log(q_a⁻¹ q_b))``: constant angular speed (Shoemake,
    *Animating rotation with quaternion curves*, SIGGRAPH 1985). Two MuJoCo calls:
    ``mju_subQuat`` (the log, its angle brought into ``[−π, π]``: the shorter arc) and
    ``mju_quatIntegrate``.

    Args:
        q_a: The quaternion at ``t = 0``.
        q_b: The quaternion at ``t = 1``.
        t: The fraction of the way.

    Returns:
        The quaternion at ``t``: ``q_a`` at 0, ``±q_b`` (the same rotation) at 1.
    """
    out = np.array(q_a, dtype=float)
    velocity = np.empty(3)
    mujoco.mju_subQuat(velocity, np.asarray(q_b, dtype=float), out)
    mujoco.mju_quatIntegrate(out, velocity, t)
    return out
