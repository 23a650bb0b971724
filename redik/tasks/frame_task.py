r"""Shared ground of the tasks on a frame's pose: frame binding and the log-map Jacobians.

:class:`PoseTask`, :class:`PositionTask` and :class:`OrientationTask` regulate one frame
(a site or body; ``None`` is the robot's end-effector) towards a target. Their errors are
those of :mod:`redik.conventions`: the body twist :math:`e = \log(T^{-1} T_d)` for a pose,
:math:`\log(R^\top R_d)` for an orientation, :math:`p - p_d` for a position.

The derivative of a log-map error needs the inverse left Jacobian of the group. Perturbing
the frame by a body twist :math:`δ = J_b Δq` (:math:`T \to T \exp(δ)`) changes
:math:`\log(T_d^{-1} T) = -e` by :math:`J_l^{-1}(e)\, δ` to first order (Barfoot, *State
Estimation for Robotics*, 2017, §7.1.5; Solà et al., *A micro Lie theory*, 2018, eq. 79),
so

.. math::

    \frac{\partial e}{\partial q} = -J_l^{-1}(e)\, J_b .

On SE(3) :math:`J_l^{-1}(ξ) = \sum_k \frac{B_k}{k!} \mathrm{ad}_ξ^k` (Bernoulli numbers).
Because :math:`\mathrm{ad}_ξ` satisfies :math:`x (x^2 + θ^2)^2 = 0`, the series collapses to

.. math::

    J_l^{-1}(ξ) = I - \tfrac12 \mathrm{ad}_ξ + a\, \mathrm{ad}_ξ^2 + b\, \mathrm{ad}_ξ^4,
    \quad
    b = -\frac{A + Bθ^2}{θ^4}, \quad a = B + 2 b θ^2,

with :math:`A = \frac{θ}{2}\cot\frac{θ}{2} - 1`, :math:`B = \frac{1}{8\sin^2(θ/2)} -
\frac{\cot(θ/2)}{4θ}` (matching :math:`\frac{x}{2}\coth\frac{x}{2} - 1` and its derivative
at the double eigenvalues :math:`x = \pm iθ`), :math:`a \to \frac1{12}`,
:math:`b \to -\frac1{720}` as :math:`θ \to 0`, and, for twists in ``(v, ω)`` order,
:math:`\mathrm{ad}_ξ = \begin{pmatrix} [ω] & [v] \\ 0 & [ω] \end{pmatrix}`. Its rotation
block is the SO(3) inverse left Jacobian
:math:`I - \frac12 [ω] + \frac{1 - (θ/2)\cot(θ/2)}{θ^2} [ω]^2`.
"""

from __future__ import annotations

import abc
import math

import numpy as np

from .. import lie
from ..robot import Frame, Robot
from .kinematics import KinematicState
from .task import ResidualTask

_SMALL_ANGLE = 1e-3  # below it the series values of a and b are exact to O(θ⁴)


def so3_left_jacobian_inverse(omega: np.ndarray) -> np.ndarray:
    """``J_l⁻¹(ω) = I − ½[ω] + c [ω]²`` with ``c = (1 − (θ/2) cot(θ/2)) / θ²``."""
    W = lie.skew(omega)
    theta2 = float(omega @ omega)
    if theta2 < _SMALL_ANGLE**2:
        c = 1.0 / 12.0 + theta2 / 720.0
    else:
        half = 0.5 * math.sqrt(theta2)
        c = (1.0 - half * math.cos(half) / math.sin(half)) / theta2
    Jinv = W @ W
    Jinv *= c
    Jinv -= 0.5 * W
    Jinv.flat[::4] += 1.0
    return Jinv


def se3_left_jacobian_inverse(xi: np.ndarray) -> np.ndarray:
    """``J_l⁻¹(ξ)`` (6 × 6) for a twist ``ξ = (v, ω)``, by the ad-polynomial above."""
    ad = np.zeros((6, 6))
    W = lie.skew(xi[3:])
    ad[:3, :3] = W
    ad[3:, 3:] = W
    ad[:3, 3:] = lie.skew(xi[:3])
    theta2 = float(xi[3:] @ xi[3:])
    if theta2 < _SMALL_ANGLE**2:
        a, b = 1.0 / 12.0, -1.0 / 720.0
    else:
        theta = math.sqrt(theta2)
        half = 0.5 * theta
        cot = math.cos(half) / math.sin(half)
        A = half * cot - 1.0
        B = 1.0 / (8.0 * math.sin(half) ** 2) - cot / (4.0 * theta)
        b = -(A + B * theta2) / (theta2 * theta2)
        a = B + 2.0 * b * theta2
    ad2 = ad @ ad
    Jinv = ad2 @ ad2
    Jinv *= b
    Jinv += a * ad2
    Jinv -= 0.5 * ad
    Jinv.flat[::7] += 1.0
    return Jinv


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
