r"""Penalise the step itself: :math:`\tfrac12 \|W Δq\|^2` (:math:`e = 0`, :math:`J = I`).

A Levenberg–Marquardt / minimum-norm regulariser on the joint step: at the lowest
priority it selects the smallest step among those the higher levels leave equally good;
at the same priority as a pose task it trades accuracy per step for smoothness near
singularities (damped least squares, Nakamura & Hanafusa 1986; Wampler 1986). A
joint-space task (:mod:`redik.tasks.joint_space_task`) with :math:`d = 1` and
:math:`α = 0`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.kinematics.robot import Robot
from redik.tasks.joint_space_task import JointSpaceTask
from redik.tasks.kinematics import KinematicState


class DampingTask(JointSpaceTask):
    """Penalise joint motion with a scalar or per-joint ``cost``.

    Args:
        cost: Scalar or per-joint damping cost (default 1).
        priority: Priority level, 0 highest.
    """

    def __init__(self, cost: ArrayLike = 1.0, priority: int = 1):
        super().__init__(cost, gain=0.0, priority=priority)

    def bind(self, robot: Robot) -> DampingTask:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        super().bind(robot)
        self.jacobian_diagonal = np.ones(robot.dof)
        # No reference (the gain is 0); a configuration, so that q ⊖ r is defined.
        self.reference = np.zeros(robot.dof) if robot.flat else robot.home.copy()
        return self

    def residual_into(
        self, state: KinematicState, e: NDArray[np.float64], J: NDArray[np.float64]
    ) -> None:
        """Write the error into ``e`` and its Jacobian into ``J`` (module docstring)."""
        super().residual_into(state, e, J)
        e[:] = 0.0  # no reference to chase: the desired step is zero
