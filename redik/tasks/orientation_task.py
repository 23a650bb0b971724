r"""Regulate the orientation of a frame: :math:`e = \log(R^\top R_d)`, in body axes.

.. math::

    e(q) = \log\big(R(q)^\top R_d\big) \in \mathbb{R}^3, \qquad
    J(q) = -J_l^{-1}(e)\, R^\top J_ω(q)

with :math:`J_ω` the angular block of the world Jacobian and :math:`J_l^{-1}` the SO(3)
inverse left Jacobian (:func:`redik.lie.so3_left_jacobian_inverse`; why it appears:
:mod:`redik.tasks.single_frame_task`). These are the angular rows of
:class:`~redik.tasks.frame_task.FrameTask`. The position is left free.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik import lie
from redik.core.exceptions import InvalidRotation
from redik.core.rotation_policy import as_quaternion, as_rotation
from redik.core.validate import real_array
from redik.tasks.kinematics import KinematicState
from redik.tasks.single_frame_task import SingleFrameTask


def as_target_rotation(target: object, *, strict: bool = False) -> NDArray[np.float64]:
    """A 3 × 3 rotation from a matrix, a unit quaternion or ``mink.SO3``.

    A 3 × 3 rotation from a matrix, a unit quaternion ``(w, x, y, z)`` or ``mink.SO3``, under
    :mod:`~redik.core.rotation_policy`.
    """
    if hasattr(target, "as_matrix"):
        target = target.as_matrix()
    target = real_array(target, "target_rotation", InvalidRotation)
    if target.shape == (4,):
        return lie.matrix_from_quat(as_quaternion(target, "target_rotation"))
    return as_rotation(target, name="target_rotation", strict=strict).copy()


class OrientationTask(SingleFrameTask):
    """Drive a frame to a target orientation ``R_d`` (world frame).

    Args:
        frame_name: The site, body or geom name.
        frame_type: ``"site"``, ``"body"`` or ``"geom"``; None looks the name up as a site,
            body, then geom.
        cost: Scalar or per-axis (3, body axes) cost (default 1).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        lm_damping: Levenberg–Marquardt scale ``λ ≥ 0`` (:class:`~redik.tasks.task.ResidualTask`).
        target: 3 × 3 rotation matrix, unit quaternion ``(w, x, y, z)`` or ``mink.SO3``, or
            None to set it later (:meth:`set_target`; using the task before raises
            :class:`~redik.core.exceptions.TargetNotSet`).
        priority: Priority level, 0 highest.
        strict: Refuse a near-rotation instead of projecting it onto SO(3) with a warning
            (:mod:`~redik.core.rotation_policy`); also the default of :meth:`set_target`.
    """

    def __init__(
        self,
        frame_name: str,
        frame_type: str | None = None,
        cost: ArrayLike = 1.0,
        gain: float = 1.0,
        lm_damping: float = 0.0,
        *,
        target: object = None,
        priority: int = 0,
        strict: bool = False,
    ):
        super().__init__(frame_name, frame_type, cost, gain, priority, 3, lm_damping=lm_damping)
        self.strict = strict
        if target is not None:
            self.set_target(target)

    def set_target(self, target_rotation: object, *, strict: bool | None = None) -> None:
        """Replace the target orientation (validated; ``strict`` defaults to the task's)."""
        self.target = as_target_rotation(
            target_rotation, strict=self.strict if strict is None else strict
        )

    def residual_into(
        self, state: KinematicState, e: NDArray[np.float64], J: NDArray[np.float64]
    ) -> None:
        """Write the error into ``e`` and its Jacobian into ``J`` (module docstring)."""
        if self.target is None:
            self._require_target()
        R, _ = state.pose(self.frame)
        Rt = R.T
        e[:] = lie.so3_log(Rt @ self.target)
        Jinv = lie.so3_left_jacobian_inverse(e)
        Jinv *= -1.0
        np.matmul(Jinv @ Rt, state.jacobian(self.frame)[3:], out=J)

    def pose_errors(self, state: KinematicState) -> tuple[None, float]:
        """``(‖p_d − p‖, angle(Rᵀ R_d))`` at ``state``; None for what the task ignores."""
        if self.target is None:
            self._require_target()
        R, _ = state.pose(self.frame)
        return None, lie.rotation_angle(R, self.target)
