r"""The joint velocity box: :math:`|Δq_i| \le v_{max,i}\, dt`.

Needs the step duration ``dt`` (``problem.step(q, dt)``); it is the limit to use for
online control at a fixed rate.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Robot
from redik.limits.limit import BoxLimit


class VelocityLimit(BoxLimit):
    """Bound each joint's speed (each tangent coordinate of a ball or free joint).

    Args:
        max_velocity: A scalar, one value per tangent coordinate, or a mapping from joint name to
            its bound (rad/s or m/s, > 0); joints not in the mapping are unbounded.
        priority: None (default): hard at every level; ``k``: ranked just above the tasks
            of priority ``k`` (:mod:`redik.limits.limit`).
    """

    def __init__(
        self, max_velocity: ArrayLike | Mapping[str, float], *, priority: int | None = None
    ):
        self._spec = max_velocity
        self.max_velocity = np.empty(0)
        self._set_priority(priority)

    def bind(self, robot: Robot, tolerance: float = 0.0) -> VelocityLimit:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        self.max_velocity = self.positive_per_dof(
            self._spec, robot, "max_velocity", "VelocityLimit"
        )
        super().bind(robot, tolerance)
        return self

    def bounds_into(
        self,
        q: NDArray[np.float64],
        dt: float | None,
        lower: NDArray[np.float64],
        upper: NDArray[np.float64],
    ) -> None:
        """Intersect this box with ``[lower, upper]`` in place (:meth:`BoxLimit.bounds_into`)."""
        if dt is None:
            raise InvalidInput("VelocityLimit needs the step duration: call problem.step(q, dt)")
        np.maximum(lower, -self.max_velocity * dt, out=lower)
        np.minimum(upper, self.max_velocity * dt, out=upper)
