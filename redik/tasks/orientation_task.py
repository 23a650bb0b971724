r"""Regulate the orientation of a frame: :math:`e = \log(R^\top R_d)`, in body axes.

.. math::

    e(q) = \log\big(R(q)^\top R_d\big) \in \mathbb{R}^3, \qquad
    J(q) = -J_l^{-1}(e)\, R^\top J_ω(q)

with :math:`J_ω` the angular block of the world Jacobian and :math:`J_l^{-1}` the SO(3)
inverse left Jacobian (:func:`redik.lie.so3_left_jacobian_inverse`; why it appears:
:mod:`redik.tasks.frame_task`). These are the angular rows of
:class:`~redik.tasks.pose_task.PoseTask`. The position is left free.
"""

from __future__ import annotations

import numpy as np

from redik import lie
from redik.core.exceptions import InvalidRotation
from redik.tasks.frame_task import FrameTargetTask
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import weight_or_cost


def as_target_rotation(target, *, strict: bool = False) -> np.ndarray:
    """A 3 × 3 rotation from a matrix, a unit quaternion ``(w, x, y, z)`` or ``mink.SO3``,
    under :mod:`redik.lie`'s rotation tolerance policy."""
    if hasattr(target, "as_matrix"):
        target = target.as_matrix()
    target = lie.real_array(target, "target_rotation", InvalidRotation)
    if target.shape == (4,):
        return lie.matrix_from_quat(lie.as_quaternion(target, "target_rotation"))
    return lie.as_rotation(target, name="target_rotation", strict=strict).copy()


class OrientationTask(FrameTargetTask):
    """Drive a frame to a target orientation ``R_d`` (world frame).

    Args:
        target_rotation: 3 × 3 rotation matrix, unit quaternion ``(w, x, y, z)`` or
            ``mink.SO3``.
        frame: Site or body name; None is the robot's end-effector.
        weight: Scalar or per-axis (3, body axes) weight (default 1).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        priority: Priority level, 0 highest.
        strict: Refuse a near-rotation instead of projecting it onto SO(3) with a warning
            (:mod:`redik.lie`'s tolerance policy); also the default of :meth:`set_target`.
        cost: mink's name for ``weight`` (give one of them).
    """

    def __init__(
        self,
        target_rotation,
        frame: str | None = None,
        weight=None,
        gain: float = 1.0,
        priority: int = 0,
        *,
        strict: bool = False,
        cost=None,
    ):
        super().__init__(frame, weight_or_cost(weight, cost), gain, priority, size=3)
        self.strict = strict
        self.target = as_target_rotation(target_rotation, strict=strict)

    def set_target(self, target_rotation, *, strict: bool | None = None) -> None:
        """Replace the target orientation (validated; ``strict`` defaults to the task's)."""
        self.target = as_target_rotation(
            target_rotation, strict=self.strict if strict is None else strict
        )

    def residual_into(self, state: KinematicState, e: np.ndarray, J: np.ndarray) -> None:
        R, _ = state.pose(self.frame)
        Rt = R.T
        e[:] = lie.so3_log(Rt @ self.target)
        Jinv = lie.so3_left_jacobian_inverse(e)
        Jinv *= -1.0
        np.matmul(Jinv @ Rt, state.jacobian(self.frame)[3:], out=J)

    def pose_errors(self, state: KinematicState) -> tuple[None, float]:
        R, _ = state.pose(self.frame)
        return None, lie.rotation_angle(R, self.target)
