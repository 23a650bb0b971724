r"""Keep joints away from their limits by descending a quadratic potential.

.. math::

    φ(q) = \sum_i \left(\frac{q_i - \bar q_i}{q_{max,i} - q_{min,i}}\right)^2, \qquad
    \bar q = \tfrac12 (q_{min} + q_{max})

(Liégeois 1977; Chan & Dubey 1995 use the same normalisation). With
:math:`s_i = 1 / (q_{max,i} - q_{min,i})` (0 for a joint without limits), the gradient and
Hessian are

.. math::

    ∇φ = 2 s^2 ⊙ (q - \bar q), \qquad ∇^2 φ = 2\,\mathrm{diag}(s^2).

The task enters the QP through them, as the residual :math:`e = \sqrt2\, s ⊙ (q - \bar q)`
with :math:`J = \sqrt2\, \mathrm{diag}(s)`, so :math:`φ = \|e\|^2/2`, :math:`J^\top J =
∇^2φ` and :math:`J^\top e = ∇φ`: its objective :math:`w^2 (\tfrac12 Δq^\top ∇^2φ\, Δq +
α ∇φ^\top Δq)` is a (damped, for :math:`α < 1`) Newton step on :math:`w^2 φ`. The potential
and its derivatives are those of :mod:`redik.criteria`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik import criteria
from redik.kinematics.robot import Robot
from redik.tasks.joint_space_task import JointSpaceTask


class JointLimitAvoidanceTask(JointSpaceTask):
    """Descend ``φ(q)`` towards the middle of each limited joint's range.

    A joint-space task (:mod:`redik.tasks.joint_space_task`) with ``d = √2 s``, ``r = q̄``.

    Args:
        cost: Scalar or per-joint cost ``w`` (the objective scales with ``w²``; default 1).
        gain: Newton step fraction ``α ∈ [0, 1]``.
        priority: Priority level, 0 highest.
    """

    def __init__(self, cost: ArrayLike = 1.0, gain: float = 1.0, priority: int = 1):
        super().__init__(cost, gain, priority)
        self.scale = np.empty(0)

    def bind(self, robot: Robot) -> JointLimitAvoidanceTask:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        super().bind(robot)
        self.scale, middle = criteria.joint_limit_scaling(robot.lower, robot.upper)
        if robot.flat:
            self.reference = middle
        else:  # a configuration: the middle on hinges and slides (s = 0 elsewhere)
            self.reference = robot.with_scalar_values(robot.home, middle)
        self.jacobian_diagonal = math.sqrt(2.0) * self.scale
        return self

    @property
    def middle(self) -> NDArray[np.float64]:
        """``q̄``, the middle of each limited joint's range (0 where unlimited)."""
        return self.reference

    def value(self, q: NDArray[np.float64]) -> float:
        """The potential ``φ(q)``."""
        deviation = self._require_robot().difference(self.reference, q)
        return float(criteria.joint_limit_potential(deviation, self.scale))

    def gradient(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """``∇φ(q) = 2 s² ⊙ (q − q̄)``."""
        deviation = self._require_robot().difference(self.reference, q)
        return criteria.joint_limit_potential_gradient(deviation, self.scale)

    def hessian(self) -> NDArray[np.float64]:
        """``∇²φ = 2 diag(s²)`` (constant)."""
        return criteria.joint_limit_potential_hessian(self.scale)
