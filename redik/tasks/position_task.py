r"""Regulate the position of a frame's origin: :math:`e = p - p_d`, :math:`J = J_v`.

:math:`J_v` is the linear block of the world Jacobian (:mod:`redik.core.conventions`), the
derivative of the origin's world position. The orientation is left free.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.core.validate import as_vector
from redik.tasks.kinematics import KinematicState
from redik.tasks.single_frame_task import SingleFrameTask


class PositionTask(SingleFrameTask):
    """Drive a frame's origin to a target position ``p_d`` (3,) in the world frame.

    Args:
        frame_name: The site, body or geom name.
        frame_type: ``"site"``, ``"body"`` or ``"geom"``; None looks the name up as a site,
            body, then geom.
        cost: Scalar or per-axis (3) cost (default 1).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        lm_damping: Levenberg–Marquardt scale ``λ ≥ 0`` (:class:`~redik.tasks.task.ResidualTask`).
        target: The target ``p_d`` in metres, or None to set it later (:meth:`set_target`;
            using the task before raises :class:`~redik.core.exceptions.TargetNotSet`).
        priority: Priority level, 0 highest.
    """

    def __init__(
        self,
        frame_name: str,
        frame_type: str | None = None,
        cost: ArrayLike = 1.0,
        gain: float = 1.0,
        lm_damping: float = 0.0,
        *,
        target: ArrayLike | None = None,
        priority: int = 0,
    ):
        super().__init__(frame_name, frame_type, cost, gain, priority, 3, lm_damping=lm_damping)
        if target is not None:
            self.set_target(target)

    def set_target(self, target_position: ArrayLike) -> None:
        """Replace the target position (validated)."""
        self.target = as_vector(target_position, 3, "target_position").copy()

    def residual_into(
        self, state: KinematicState, e: NDArray[np.float64], J: NDArray[np.float64]
    ) -> None:
        """Write the error into ``e`` and its Jacobian into ``J`` (module docstring)."""
        if self.target is None:
            self._require_target()
        _, p = state.pose(self.frame)
        np.subtract(p, self.target, out=e)
        J[:] = state.jacobian(self.frame)[:3]

    def pose_errors(self, state: KinematicState) -> tuple[float, None]:
        """``(‖p_d − p‖, angle(Rᵀ R_d))`` at ``state``; None for what the task ignores."""
        if self.target is None:
            self._require_target()
        _, p = state.pose(self.frame)
        return float(np.linalg.norm(self.target - p)), None
