r"""Penalise the step itself: :math:`\tfrac12 \|W Δq\|^2` (:math:`e = 0`, :math:`J = I`).

A Levenberg–Marquardt / minimum-norm regulariser on the chain joints: at the lowest
priority it selects the smallest step among those the higher levels leave equally good;
at the same priority as a pose task it trades accuracy per step for smoothness near
singularities (damped least squares, Nakamura & Hanafusa 1986; Wampler 1986).
"""

from __future__ import annotations

import numpy as np

from ..robot import Robot
from .kinematics import KinematicState
from .task import ResidualTask


class DampingTask(ResidualTask):
    """Penalise joint motion with a scalar or per-joint ``weight``.

    Args:
        weight: Scalar or per-joint damping weight.
        priority: Priority level, 0 highest.
    """

    def __init__(self, weight=1.0, priority: int = 1):
        super().__init__(weight, gain=0.0, priority=priority)

    def bind(self, robot: Robot) -> DampingTask:
        self._set_size(robot.dof)
        return super().bind(robot)

    def residual_into(self, state: KinematicState, e: np.ndarray, J: np.ndarray) -> None:
        e[:] = 0.0
        J[:] = 0.0
        J[np.arange(self.k), state.chain_columns] = 1.0
