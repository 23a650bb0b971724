r"""Regulate the full pose of a frame: :math:`e = \log(T^{-1} T_d)`, a body twist.

.. math::

    e(q) = \log\big(T(q)^{-1} T_d\big) \in \mathbb{R}^6, \qquad
    J(q) = -J_l^{-1}(e)\, J_b(q)

with :math:`J_b` the body Jacobian (:mod:`redik.conventions`) and :math:`J_l^{-1}` the
SE(3) inverse left Jacobian (:mod:`redik.tasks.frame_task`). This is the error and
Jacobian of ``mink.FrameTask``, so the two give the same step.
"""

from __future__ import annotations

import numpy as np

from .. import lie
from .frame_task import FrameTask, se3_left_jacobian_inverse
from .kinematics import KinematicState
from .task import as_weight


def as_target_pose(target, name: str = "target") -> np.ndarray:
    """A 4 × 4 target pose from an array or anything with ``as_matrix()`` (``mink.SE3``)."""
    if hasattr(target, "as_matrix"):
        target = target.as_matrix()
    return lie.as_pose(target, name=name).copy()


class PoseTask(FrameTask):
    """Drive a frame to a target pose ``T_d`` (4 × 4, world frame).

    Args:
        target: The target pose ``T_wd`` (4 × 4 array or ``mink.SE3``).
        frame: Site or body name; None is the robot's end-effector.
        position_weight: Weight of the linear part ``v`` of the error (scalar or 3).
        orientation_weight: Weight of the angular part ``ω`` (scalar or 3).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        priority: Priority level, 0 highest.
    """

    def __init__(
        self,
        target,
        frame: str | None = None,
        position_weight=1.0,
        orientation_weight=1.0,
        gain: float = 1.0,
        priority: int = 0,
    ):
        super().__init__(frame, 1.0, gain, priority, size=6)
        self.set_weights(position_weight, orientation_weight)
        self.target = as_target_pose(target)
        self._T_rel = np.eye(4)

    def set_weights(self, position_weight, orientation_weight) -> None:
        """Weights of the linear and angular parts (each a scalar or 3 values)."""
        self.cost[:3] = as_weight(position_weight, 3, "position_weight")
        self.cost[3:] = as_weight(orientation_weight, 3, "orientation_weight")

    def set_target(self, target) -> None:
        """Replace the target pose (validated)."""
        self.target = as_target_pose(target)

    def residual_into(self, state: KinematicState, e: np.ndarray, J: np.ndarray) -> None:
        R, p = state.pose(self.frame)
        Rt = R.T
        T_rel = self._T_rel
        np.matmul(Rt, self.target[:3, :3], out=T_rel[:3, :3])
        np.matmul(Rt, self.target[:3, 3] - p, out=T_rel[:3, 3])
        e[:] = lie.se3_log(T_rel)
        J_world = state.jacobian(self.frame)
        np.matmul(Rt, J_world[:3], out=J[:3])
        np.matmul(Rt, J_world[3:], out=J[3:])
        Jinv = se3_left_jacobian_inverse(e)
        Jinv *= -1.0
        J[:] = Jinv @ J

    def pose_errors(self, state: KinematicState) -> tuple[float, float]:
        R, p = state.pose(self.frame)
        return (
            float(np.linalg.norm(self.target[:3, 3] - p)),
            lie.rotation_angle(R, self.target[:3, :3]),
        )
