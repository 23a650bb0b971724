r"""Rigid transforms SE(3): poses, inverse, adjoint, Jacobian references, exp and log.

Twists are ordered ``(v, ω)`` and poses are ``T_ab`` (:mod:`redik.core.conventions`).
Formulas follow Lynch & Park, *Modern Robotics* (2017), §3.3.3 (exp/log) and §3.3.2 (adjoint),
rewritten for the ``(v, ω)`` order:

.. math::

    \exp\begin{pmatrix} v \\ ω \end{pmatrix} =
    \begin{pmatrix} \exp([ω]) & V(ω) v \\ 0 & 1 \end{pmatrix}, \qquad
    V(ω) = I + \frac{1 - \cos θ}{θ^2}[ω] + \frac{θ - \sin θ}{θ^3}[ω]^2,

    \mathrm{Ad}_T = \begin{pmatrix} R & [p] R \\ 0 & R \end{pmatrix}.

These maps sit in every solver's inner loop, where ``mink.lie`` (a dataclass per call) costs
more; the tests check them against ``mink.lie`` as an independent implementation. They take
validated float input unchecked (:mod:`redik.core.rotation_policy`).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput
from redik.lie.so3 import (
    _SMALL_ANGLE,
    apply_inverse_v,
    left_jacobian_inverse_coefficients,
    skew,
    so3_exp,
    so3_log,
)


def make_pose(R: NDArray[np.float64], p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The transform ``[[R, p], [0, 1]]``.

    Args:
        R: Rotation (3, 3).
        p: Translation (3,).

    Returns:
        The pose (4, 4).
    """
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def inverse(T: NDArray[np.float64]) -> NDArray[np.float64]:
    """``T⁻¹ = [[Rᵀ, −Rᵀ p], [0, 1]]``, without a general matrix inverse.

    MuJoCo's ``mju_negPose`` takes ``(p, quat)``; going there and back through quaternions
    costs more than the transpose.

    Args:
        T: A pose (4, 4).

    Returns:
        Its inverse (4, 4).
    """
    Ti = np.eye(4)
    Rt = T[:3, :3].T
    Ti[:3, :3] = Rt
    Ti[:3, 3] = -Rt @ T[:3, 3]
    return Ti


def adjoint(T: NDArray[np.float64]) -> NDArray[np.float64]:
    """The adjoint ``Ad_T`` acting on ``(v, ω)`` twists: ``V_a = Ad_{T_ab} V_b``.

    Args:
        T: A pose ``T_ab`` (4, 4).

    Returns:
        ``Ad_T = [[R, [p] R], [0, R]]`` (6, 6).
    """
    R = T[:3, :3]
    Ad = np.zeros((6, 6))
    Ad[:3, :3] = R
    Ad[:3, 3:] = skew(T[:3, 3]) @ R
    Ad[3:, 3:] = R
    return Ad


def _space_from_world(
    J: NDArray[np.float64], p: NDArray[np.float64], out: NDArray[np.float64]
) -> None:
    """``v_s = ṗ + [p] ω`` into ``out`` (holding ``J``)."""
    if J.ndim == 2:
        out[:3] += skew(p) @ J[3:]
        return
    w, px, py, pz = J[3:], p[0][None], p[1][None], p[2][None]  # p × ω per column and target
    out[0] += py * w[2] - pz * w[1]
    out[1] += pz * w[0] - px * w[2]
    out[2] += px * w[1] - py * w[0]


def _body_from_world(
    J: NDArray[np.float64], R: NDArray[np.float64], out: NDArray[np.float64]
) -> None:
    """``(Rᵀ ṗ, Rᵀ ω)`` into ``out``."""
    if J.ndim > 2:  # (Rᵀ)[i, k] = R[k, i], per target
        out[:3], out[3:] = (
            np.einsum("ki...,kn...->in...", R, J[:3]),
            np.einsum("ki...,kn...->in...", R, J[3:]),
        )
    elif out is J:  # in place, assign: matmul into its own input would copy first
        out[:3], out[3:] = R.T @ J[:3], R.T @ J[3:]
    else:
        np.matmul(R.T, J[:3], out=out[:3])
        np.matmul(R.T, J[3:], out=out[3:])


def world_jacobian_to(
    reference: str,
    J: NDArray[np.float64],
    R: NDArray[np.float64],
    p: NDArray[np.float64],
    out: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Express a ``"world"`` Jacobian in another reference (:mod:`redik.core.conventions`).

    ``"space"``: ``v_s = ṗ − ω × p = ṗ + [p] ω``, so ``J_s = [[I, [p]], [0, I]] J``;
    ``"body"``: ``J_b = blockdiag(Rᵀ, Rᵀ) J``; ``"world"``: ``J`` itself. The one home of this
    conversion (robot, batch kinematics, pose IK, redundancy).

    Args:
        reference: ``"world"``, ``"space"`` or ``"body"``.
        J: The world Jacobian (6, n) of a frame, or a batch (6, n, …) trailing (the layout of
            :mod:`redik.solvers.batch`, where a vector per target is a column).
        R: The frame's rotation (3, 3), or (3, 3, …).
        p: The frame's origin (3,), or (3, …).
        out: Written with the result (may be ``J``); allocated when None.

    Returns:
        ``out``.

    Raises:
        InvalidInput: An unknown ``reference``.
    """
    if reference not in ("world", "space", "body"):
        raise InvalidInput(f"reference must be 'space', 'body' or 'world', got {reference!r}")
    if out is None:
        out = np.empty(np.shape(J))
    if reference == "body":
        _body_from_world(J, R, out)
        return out
    if out is not J:
        out[...] = J
    if reference == "space":
        _space_from_world(J, p, out)
    return out


def _v_matrices(omega: NDArray[np.float64]) -> tuple[NDArray[np.float64], float, float]:
    """``[ω]`` with the coefficients of ``V(ω) = I + c1 [ω] + c2 [ω]²``."""
    W = skew(omega)
    theta2 = float(omega @ omega)
    theta = math.sqrt(theta2)
    if theta < _SMALL_ANGLE:
        return W, 0.5 - theta2 / 24.0, 1.0 / 6.0 - theta2 / 120.0
    return W, (1.0 - math.cos(theta)) / theta2, (theta - math.sin(theta)) / (theta2 * theta)


def se3_exp(xi: NDArray[np.float64]) -> NDArray[np.float64]:
    """The exponential ``exp(ξ) ∈ SE(3)`` of a twist (Modern Robotics Prop. 3.25).

    Args:
        xi: The twist ``ξ = (v, ω)`` (6,).

    Returns:
        The pose (4, 4).
    """
    xi = np.asarray(xi, dtype=float)
    omega = xi[3:]
    W, c1, c2 = _v_matrices(omega)
    V = np.eye(3) + c1 * W + c2 * (W @ W)
    return make_pose(so3_exp(omega), V @ xi[:3])


def se3_log(T: NDArray[np.float64]) -> NDArray[np.float64]:
    """The logarithm: ``ξ = (v, ω)`` with ``exp(ξ) = T`` (Modern Robotics §3.3.3.2).

    ``ω = log(R)`` with ``‖ω‖ ≤ π`` (:func:`redik.lie.so3.so3_log`) and ``v = V(ω)⁻¹ p``
    (:func:`redik.lie.so3.apply_inverse_v`).

    Args:
        T: A pose (4, 4).

    Returns:
        ``ξ`` (6,).
    """
    omega = so3_log(T[:3, :3])
    wx, wy, wz = omega.tolist()
    xi = np.empty(6)
    xi[:3] = apply_inverse_v(wx, wy, wz, T[0, 3], T[1, 3], T[2, 3])
    xi[3:] = omega
    return xi


def se3_left_jacobian_inverse(xi: NDArray[np.float64]) -> NDArray[np.float64]:
    r"""The inverse left Jacobian ``J_l⁻¹(ξ)`` of SE(3), in closed form.

    ``J_l⁻¹(ξ) = Σ_k (B_k / k!) ad_ξ^k`` (Bernoulli numbers; Barfoot, *State Estimation for
    Robotics*, 2017, §7.1.5), with, in ``(v, ω)`` order, :math:`\mathrm{ad}_ξ =
    \begin{pmatrix} [ω] & [v] \\ 0 & [ω] \end{pmatrix}`. Because :math:`\mathrm{ad}_ξ`
    satisfies :math:`x (x^2 + θ^2)^2 = 0`, the series collapses to :math:`I - \tfrac12
    \mathrm{ad}_ξ + a\, \mathrm{ad}_ξ^2 + b\, \mathrm{ad}_ξ^4` with

    .. math::

        b = -\frac{A + Bθ^2}{θ^4}, \quad a = B + 2 b θ^2, \quad
        A = \frac{θ}{2}\cot\frac{θ}{2} - 1, \quad
        B = \frac{1}{8\sin^2(θ/2)} - \frac{\cot(θ/2)}{4θ}

    (matching :math:`\frac{x}{2}\coth\frac{x}{2} - 1` and its derivative at the double
    eigenvalues :math:`x = \pm iθ`). Expanding the powers with :math:`[ω]^2 = ωω^\top - θ^2 I`
    and :math:`[ω][v] = vω^\top - (ω·v) I` gives, with :math:`k = a - bθ^2`,

    .. math::

        J_l^{-1}(ξ) = \begin{pmatrix} J_ω & U \\ 0 & J_ω \end{pmatrix}, \qquad
        \begin{aligned}
        J_ω &= (1 - k θ^2) I - \tfrac12 [ω] + k\, ωω^\top, \\
        U &= -\tfrac12 [v] + k (vω^\top + ωv^\top) - 2b (ω·v)\, ωω^\top
             + 2(bθ^2 - k)(ω·v)\, I ,
        \end{aligned}

    ``J_ω`` being :func:`redik.lie.so3.so3_left_jacobian_inverse`. Tested against the defining
    series at every angle. ``mink.SE3.ljacinv`` agrees for θ ≥ 0.1 but returns the identity at
    tiny angles, where the ``−½[v]`` block of a nearly pure translation matters (there every
    converging pose error lives).

    Args:
        xi: The twist ``ξ = (v, ω)`` (6,).

    Returns:
        ``J_l⁻¹(ξ)`` (6, 6).
    """
    return np.array(se3_left_jacobian_inverse_entries(*xi.tolist())).reshape(6, 6)


@numba.njit(cache=True)
def se3_left_jacobian_inverse_entries(
    vx: float, vy: float, vz: float, wx: float, wy: float, wz: float
) -> tuple[float, ...]:
    """The 36 entries, row-major, of :func:`se3_left_jacobian_inverse`, from floats.

    Compiled, so that the pose task's compiled residual calls the same code.

    Args:
        vx: ``v_x``.
        vy: ``v_y``.
        vz: ``v_z``.
        wx: ``ω_x``.
        wy: ``ω_y``.
        wz: ``ω_z``.

    Returns:
        The entries of ``J_l⁻¹(ξ)``, row by row.
    """
    theta2 = wx * wx + wy * wy + wz * wz
    k, b = left_jacobian_inverse_coefficients(theta2)
    s = 1.0 - k * theta2
    wv = wx * vx + wy * vy + wz * vz
    m = -2.0 * b * wv
    d = 2.0 * (b * theta2 - k) * wv
    j00, j01, j02 = s + k * wx * wx, 0.5 * wz + k * wx * wy, -0.5 * wy + k * wx * wz
    j10, j11, j12 = -0.5 * wz + k * wy * wx, s + k * wy * wy, 0.5 * wx + k * wy * wz
    j20, j21, j22 = 0.5 * wy + k * wz * wx, -0.5 * wx + k * wz * wy, s + k * wz * wz
    u00 = 2.0 * k * vx * wx + m * wx * wx + d
    u11 = 2.0 * k * vy * wy + m * wy * wy + d
    u22 = 2.0 * k * vz * wz + m * wz * wz + d
    u01 = 0.5 * vz + k * (vx * wy + wx * vy) + m * wx * wy
    u10 = -0.5 * vz + k * (vy * wx + wy * vx) + m * wy * wx
    u02 = -0.5 * vy + k * (vx * wz + wx * vz) + m * wx * wz
    u20 = 0.5 * vy + k * (vz * wx + wz * vx) + m * wz * wx
    u12 = 0.5 * vx + k * (vy * wz + wy * vz) + m * wy * wz
    u21 = -0.5 * vx + k * (vz * wy + wz * vy) + m * wz * wy
    # fmt: off
    return (
        j00, j01, j02, u00, u01, u02,
        j10, j11, j12, u10, u11, u12,
        j20, j21, j22, u20, u21, u22,
        0.0, 0.0, 0.0, j00, j01, j02,
        0.0, 0.0, 0.0, j10, j11, j12,
        0.0, 0.0, 0.0, j20, j21, j22,
    )
    # fmt: on


def interpolate_pose(
    T_a: NDArray[np.float64], T_b: NDArray[np.float64], t: float
) -> NDArray[np.float64]:
    """The pose a fraction ``t`` of the way from ``T_a`` to ``T_b``.

    Position linear, orientation ``R_a exp(t log(R_aᵀ R_b))`` (SLERP: constant angular speed
    along the shorter arc).

    Args:
        T_a: The pose at ``t = 0`` (4, 4).
        T_b: The pose at ``t = 1`` (4, 4).
        t: The fraction of the way.

    Returns:
        The pose (4, 4).
    """
    R = T_a[:3, :3] @ so3_exp(t * so3_log(T_a[:3, :3].T @ T_b[:3, :3]))
    return make_pose(R, (1.0 - t) * T_a[:3, 3] + t * T_b[:3, 3])
