r"""Pull the robot towards a nominal posture: :math:`e = q \ominus q_{nom}`, :math:`J = I`.

Usually a low-priority regulariser: in a redundant arm it picks, among the joint steps
that serve the higher levels equally well, the one that moves towards :math:`q_{nom}`.
A joint-space task (:mod:`redik.tasks.joint_space_task`) with :math:`d = 1`,
:math:`r = q_{nom}`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.core.validate import as_vector
from redik.kinematics.robot import Robot
from redik.tasks.joint_space_task import JointSpaceTask


class PostureTask(JointSpaceTask):
    """Drive the robot's joints towards ``q_nominal`` (across ball and free joints too).

    Args:
        q_nominal: The nominal configuration (``robot.nq``,); None is the robot's ``home``,
            taken when the task is bound.
        cost: Scalar or per-joint cost (default 1).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        priority: Priority level, 0 highest.
    """

    def __init__(
        self,
        q_nominal: ArrayLike | None = None,
        cost: ArrayLike = 1.0,
        gain: float = 1.0,
        priority: int = 1,
    ):
        super().__init__(cost, gain, priority)
        self._q_nominal_given = q_nominal

    def bind(self, robot: Robot) -> PostureTask:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        super().bind(robot)
        self.jacobian_diagonal = np.ones(robot.dof)
        if self._q_nominal_given is None:
            self.reference = robot.home.copy()
        else:
            self.reference = _nominal(robot, self._q_nominal_given)
        return self

    @property
    def q_nominal(self) -> NDArray[np.float64]:
        """The nominal posture (once bound)."""
        return self.reference

    def set_target(self, q_nominal: ArrayLike) -> None:
        """Replace the nominal posture (validated against the bound robot)."""
        robot = self._require_robot()
        self.reference = _nominal(robot, q_nominal)
        self.version += 1


def _nominal(robot: Robot, q_nominal: ArrayLike) -> NDArray[np.float64]:
    """``q_nominal`` checked (shape, finite, no zero quaternion) and clipped into the limits."""
    return robot.clip(robot.check_q(as_vector(q_nominal, robot.nq, "q_nominal"), "q_nominal"))
