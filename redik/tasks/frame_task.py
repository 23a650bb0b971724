r"""Shared ground of the tasks on a frame's pose: frame binding and the log-map Jacobians.

:class:`PoseTask`, :class:`PositionTask` and :class:`OrientationTask` regulate one frame
(a site or body; ``None`` is the robot's end-effector) towards a target. Their errors are
those of :mod:`redik.core.conventions`: the body twist :math:`e = \log(T^{-1} T_d)` for a pose,
:math:`\log(R^\top R_d)` for an orientation, :math:`p - p_d` for a position.

The derivative of a log-map error needs the inverse left Jacobian of the group. Perturbing
the frame by a body twist :math:`δ = J_b Δq` (:math:`T \to T \exp(δ)`) changes
:math:`\log(T_d^{-1} T) = -e` by :math:`J_l^{-1}(e)\, δ` to first order (Barfoot, *State
Estimation for Robotics*, 2017, §7.1.5; Solà et al., *A micro Lie theory*, 2018, eq. 79),
so

.. math::

    \frac{\partial e}{\partial q} = -J_l^{-1}(e)\, J_b .

On SE(3) :math:`J_l^{-1}(ξ) = \sum_k \frac{B_k}{k!} \mathrm{ad}_ξ^k` (Bernoulli numbers),
with, for twists in ``(v, ω)`` order, :math:`\mathrm{ad}_ξ = \begin{pmatrix} [ω] & [v] \\ 0 &
[ω] \end{pmatrix}`. Because :math:`\mathrm{ad}_ξ` satisfies :math:`x (x^2 + θ^2)^2 = 0`,
the series collapses to :math:`I - \tfrac12 \mathrm{ad}_ξ + a\, \mathrm{ad}_ξ^2 + b\,
\mathrm{ad}_ξ^4` with

.. math::

    b = -\frac{A + Bθ^2}{θ^4}, \quad a = B + 2 b θ^2, \quad
    A = \frac{θ}{2}\cot\frac{θ}{2} - 1, \quad
    B = \frac{1}{8\sin^2(θ/2)} - \frac{\cot(θ/2)}{4θ}

(matching :math:`\frac{x}{2}\coth\frac{x}{2} - 1` and its derivative at the double
eigenvalues :math:`x = \pm iθ`; :math:`a \to \frac1{12}`, :math:`b \to -\frac1{720}` as
:math:`θ \to 0`). Expanding the powers with :math:`[ω]^2 = ωω^\top - θ^2 I` and
:math:`[ω][v] = vω^\top - (ω·v) I` gives the closed form that is evaluated:

.. math::

    J_l^{-1}(ξ) = \begin{pmatrix} J_ω & U \\ 0 & J_ω \end{pmatrix}, \qquad
    \begin{aligned}
    J_ω &= (1 - k θ^2) I - \tfrac12 [ω] + k\, ωω^\top, \qquad k = a - bθ^2, \\
    U &= -\tfrac12 [v] + k (vω^\top + ωv^\top) - 2b (ω·v)\, ωω^\top
         + 2(2bθ^2 - a)(ω·v)\, I .
    \end{aligned}

:math:`J_ω` is the SO(3) inverse left Jacobian
:math:`I - \frac12 [ω] + \frac{1 - (θ/2)\cot(θ/2)}{θ^2} [ω]^2`.
"""

from __future__ import annotations

import abc
import math

import numba
import numpy as np

from redik.kinematics.robot import Frame, Robot
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import ResidualTask

_SMALL_ANGLE = 1e-3  # below it the series values of a and b are exact to O(θ⁴)


@numba.njit(cache=True)
def _coefficients(theta2: float) -> tuple[float, float]:
    """``(a, b)`` of the ad-polynomial at ``θ² = theta2``."""
    if theta2 < _SMALL_ANGLE**2:
        return 1.0 / 12.0, -1.0 / 720.0
    theta = math.sqrt(theta2)
    half = 0.5 * theta
    cot = math.cos(half) / math.sin(half)
    A = half * cot - 1.0
    B = 1.0 / (8.0 * math.sin(half) ** 2) - cot / (4.0 * theta)
    b = -(A + B * theta2) / (theta2 * theta2)
    return B + 2.0 * b * theta2, b


def so3_left_jacobian_inverse(omega: np.ndarray) -> np.ndarray:
    """``J_ω = J_l⁻¹(ω)`` (3 × 3) on SO(3), the closed form above."""
    wx, wy, wz = omega.tolist()
    theta2 = wx * wx + wy * wy + wz * wz
    a, b = _coefficients(theta2)
    k = a - b * theta2
    s = 1.0 - k * theta2
    return np.array(
        (
            (s + k * wx * wx, 0.5 * wz + k * wx * wy, -0.5 * wy + k * wx * wz),
            (-0.5 * wz + k * wy * wx, s + k * wy * wy, 0.5 * wx + k * wy * wz),
            (0.5 * wy + k * wz * wx, -0.5 * wx + k * wz * wy, s + k * wz * wz),
        )
    )


def se3_left_jacobian_inverse(xi: np.ndarray) -> np.ndarray:
    """``J_l⁻¹(ξ)`` (6 × 6) for a twist ``ξ = (v, ω)``, the closed form above."""
    return np.array(se3_left_jacobian_inverse_entries(*xi.tolist())).reshape(6, 6)


@numba.njit(cache=True)
def se3_left_jacobian_inverse_entries(
    vx: float, vy: float, vz: float, wx: float, wy: float, wz: float
) -> tuple[float, ...]:
    """The 36 entries (row-major) of :func:`se3_left_jacobian_inverse`, from floats.

    Compiled (numba) so that the pose task's compiled residual calls the same code.
    """
    theta2 = wx * wx + wy * wy + wz * wz
    a, b = _coefficients(theta2)
    k = a - b * theta2
    s = 1.0 - k * theta2
    wv = wx * vx + wy * vy + wz * vz
    m = -2.0 * b * wv
    d = 2.0 * (2.0 * b * theta2 - a) * wv
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


class FrameTask(ResidualTask):
    """Base of the tasks on one frame: resolves ``frame`` (None = end-effector) on bind.

    Attributes:
        frame_name: The site or body name given, or None for the end-effector.
        frame: The resolved :class:`redik.Frame` once bound.
    """

    def __init__(self, frame: str | None, weight, gain: float, priority: int, size: int):
        super().__init__(weight, gain, priority, size)
        self.frame_name = frame
        self.frame: Frame | None = None

    def bind(self, robot: Robot) -> FrameTask:
        self.frame = robot.frame(self.frame_name)
        return super().bind(robot)

    @abc.abstractmethod
    def pose_errors(self, state: KinematicState) -> tuple[float | None, float | None]:
        """``(‖p_d − p‖, angle(Rᵀ R_d))`` at ``state``; None for what the task ignores."""
