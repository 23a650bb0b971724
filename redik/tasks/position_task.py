r"""Regulate the position of a frame's origin: :math:`e = p - p_d`, :math:`J = J_v`.

:math:`J_v` is the linear block of the world Jacobian (:mod:`redik.core.conventions`), the
derivative of the origin's world position. The orientation is left free.
"""

from __future__ import annotations

import numpy as np

from redik import lie
from redik.tasks.frame_task import FrameTask
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import weight_or_cost


class PositionTask(FrameTask):
    """Drive a frame's origin to a target position ``p_d`` (3,) in the world frame.

    Args:
        target_position: The target ``p_d`` in metres.
        frame: Site or body name; None is the robot's end-effector.
        weight: Scalar or per-axis (3) weight (default 1).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        priority: Priority level, 0 highest.
        cost: mink's name for ``weight`` (give one of them).
    """

    def __init__(
        self,
        target_position,
        frame: str | None = None,
        weight=None,
        gain: float = 1.0,
        priority: int = 0,
        *,
        cost=None,
    ):
        super().__init__(frame, weight_or_cost(weight, cost), gain, priority, size=3)
        self.target = lie.as_vector(target_position, 3, "target_position").copy()

    def set_target(self, target_position) -> None:
        """Replace the target position (validated)."""
        self.target = lie.as_vector(target_position, 3, "target_position").copy()

    def residual_into(self, state: KinematicState, e: np.ndarray, J: np.ndarray) -> None:
        _, p = state.pose(self.frame)
        np.subtract(p, self.target, out=e)
        J[:] = state.jacobian(self.frame)[:3]

    def pose_errors(self, state: KinematicState) -> tuple[float, None]:
        _, p = state.pose(self.frame)
        return float(np.linalg.norm(self.target - p)), None
