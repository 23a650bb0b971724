r"""The joint velocity box: :math:`|Δq_i| \le v_{max,i}\, dt`.

Needs the step duration ``dt`` (``problem.step(q, dt)``); it is the limit to use for
online control at a fixed rate.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

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

    def __init__(self, max_velocity, *, priority: int | None = None):
        self._spec = max_velocity
        self.max_velocity = np.empty(0)
        self._set_priority(priority)

    def bind(self, robot: Robot, tolerance: float = 0.0) -> VelocityLimit:
        try:
            limit = self._per_dof(robot)
        except InvalidInput:
            raise
        except (TypeError, ValueError):  # text or None where a number belongs
            raise InvalidInput(
                f"max_velocity must be a number, an array or a mapping from joint name to a "
                f"number, got {self._spec!r}"
            ) from None
        if np.any(np.isnan(limit)) or np.any(limit <= 0.0):
            raise InvalidInput(f"max_velocity must be > 0, got {limit.tolist()}")
        self.max_velocity = limit
        return super().bind(robot, tolerance)

    def _per_dof(self, robot: Robot) -> np.ndarray:
        """The bound of each tangent coordinate (unchecked values)."""
        spec = self._spec
        if isinstance(spec, Mapping):
            unknown = sorted(set(spec) - set(robot.joint_names))
            if unknown:
                raise InvalidInput(
                    f"VelocityLimit names joints {unknown} the robot does not move "
                    f"{robot.joint_names}"
                )
            # A ball or free joint's bound applies to each of its tangent coordinates.
            return np.array([float(spec.get(name, np.inf)) for name in robot.dof_joints])
        limit = np.atleast_1d(np.asarray(spec, dtype=float))
        if limit.shape not in ((1,), (robot.dof,)):
            raise InvalidInput(
                f"max_velocity must be a scalar, ({robot.dof},) or a mapping, "
                f"got shape {limit.shape}"
            )
        return np.broadcast_to(limit, (robot.dof,)).copy()

    def bounds_into(
        self, q: np.ndarray, dt: float | None, lower: np.ndarray, upper: np.ndarray
    ) -> None:
        if dt is None:
            raise InvalidInput("VelocityLimit needs the step duration: call problem.step(q, dt)")
        np.maximum(lower, -self.max_velocity * dt, out=lower)
        np.minimum(upper, self.max_velocity * dt, out=upper)
