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

:math:`J_l^{-1}` on SO(3) and SE(3) (closed forms, and the relation to ``V(ω)⁻¹`` of the
SE(3) log) is group math: :func:`redik.lie.so3_left_jacobian_inverse` and
:func:`redik.lie.se3_left_jacobian_inverse`.
"""

from __future__ import annotations

import abc

from redik.kinematics.robot import Frame, Robot
from redik.lie import (  # noqa: F401 (their home until this release: re-exported for one more)
    se3_left_jacobian_inverse,
    se3_left_jacobian_inverse_entries,
    so3_left_jacobian_inverse,
)
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import ResidualTask


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
