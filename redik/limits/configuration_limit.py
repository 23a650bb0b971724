r"""The configuration limit (mink's and pink's name), the joint position box.

Keep :math:`q + Δq` inside :math:`[q_{min}, q_{max}]`.

.. math::

    q_{min} + m - q \;\le\; Δq \;\le\; q_{max} - m - q, \qquad m = \text{margin} + τ

Joint positions are linear in ``q``, so unlike a velocity-damper this box is exact: a
step inside it lands inside the limits. The box is shrunk by the user's ``margin`` and by
the back-end's feasibility tolerance :math:`τ` (an interior-point or ADMM solver returns
bounds satisfied only to :math:`τ`), never by more than a quarter of a joint's range.
:class:`redik.Problem` additionally clips :math:`q + Δq` into the true limits, so the
configuration it returns never leaves them — mink's ``ConfigurationLimit`` (the same box)
does neither, and its steps overshoot by up to the solver tolerance (≈5e-5 rad with proxqp,
5e-3 rad with osqp). A joint outside its limits is pulled back inside by the box.

**Full turns, for IK.** With ``periodic=True`` a revolute joint whose range spans a full
turn or more (the UR arms' ±2π) gets no box: every angle has a representative in its range,
so :func:`redik.solve_problem` turns it back into the range by a multiple
of 2π after each step (:meth:`wrap`) — the same pose, and no stop against a bound that the
pose does not need (as ``solve_pose``'s ``"dls"`` wraps such joints). This is for finding a
configuration, not for motion: a real joint of ±2π range cannot jump a turn (cables), and a
joint-space task (posture) measures the turned angle differently; :meth:`Problem.step
<redik.Problem.step>` leaves the wrapping of ``q ⊕ Δq`` to the caller.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Robot
from redik.lie import periodic_coordinates, wrap_into_range
from redik.limits.limit import BoxLimit


class ConfigurationLimit(BoxLimit):
    """Box the step so that the hinge and slide joints stay within their limits.

    Args:
        margin: Distance (rad or m) to keep from each limit, ≥ 0.
        periodic: Leave revolute joints whose range spans a full turn unboxed; they are
            turned back into range by :meth:`wrap` (module docstring).
        priority: None (default): hard at every level; ``k``: ranked just above the tasks
            of priority ``k`` (:mod:`redik.limits.limit`).

    Attributes:
        turning: Per tangent coordinate, True for the joints :meth:`wrap` turns (none
            unless ``periodic``): the periodic joints (:func:`redik.lie.periodic_coordinates`)
            of the range shrunk by the margin, which must still span a full turn.
    """

    def __init__(self, margin: float = 0.0, *, periodic: bool = False, priority: int | None = None):
        try:
            margin = float(margin)
        except (TypeError, ValueError):
            raise InvalidInput(f"margin must be a number, got {margin!r}") from None
        if not np.isfinite(margin) or margin < 0.0:
            raise InvalidInput(f"margin must be finite and >= 0, got {margin}")
        if not isinstance(periodic, bool | np.bool_):
            raise InvalidInput(f"periodic must be True or False, got {periodic!r}")
        self.margin = margin
        self.periodic = bool(periodic)
        self._set_priority(priority)
        self.lower = np.empty(0)
        self.upper = np.empty(0)
        self.turning = np.zeros(0, dtype=bool)
        self._range_lower = self._range_upper = np.empty(0)

    def bind(self, robot: Robot, tolerance: float = 0.0) -> ConfigurationLimit:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        span = robot.upper - robot.lower
        shrink = np.minimum(self.margin + tolerance, np.where(np.isfinite(span), span / 4, 0.0))
        self.lower = robot.lower + shrink
        self.upper = robot.upper - shrink
        self.turning = np.zeros(robot.dof, dtype=bool)
        if self.periodic:
            # A range of a turn less the shrink still holds a representative of every angle.
            self.turning = periodic_coordinates(robot.revolute, self.lower, self.upper)
            self.lower[self.turning] = -np.inf
            self.upper[self.turning] = np.inf
        self._range_lower = robot.lower[self.turning] + shrink[self.turning]
        self._range_upper = robot.upper[self.turning] - shrink[self.turning]
        super().bind(robot, tolerance)
        return self

    def wrap(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """``q`` with each turning joint brought into its range by multiples of 2π.

        ``q`` with each turning joint moved by the multiple of 2π that brings it into its (shrunk)
        range; ``q`` itself when none is outside.
        """
        if not self.turning.any():
            return q
        robot = self._require_robot()
        values = robot.scalar_values(q)
        turned = values[self.turning]
        outside = (turned < self._range_lower) | (turned > self._range_upper)
        if not outside.any():
            return q
        lower = self._range_lower[outside]
        turned[outside] = wrap_into_range(turned[outside], lower)
        values[self.turning] = turned
        return robot.with_scalar_values(q, values)

    def bounds_into(
        self,
        q: NDArray[np.float64],
        dt: float | None,
        lower: NDArray[np.float64],
        upper: NDArray[np.float64],
    ) -> None:
        """Intersect this box with ``[lower, upper]`` in place (:meth:`BoxLimit.bounds_into`)."""
        np.maximum(lower, self.lower - q, out=lower)
        np.minimum(upper, self.upper - q, out=upper)

    def set_bounds(
        self,
        q: NDArray[np.float64],
        dt: float | None,
        lower: NDArray[np.float64],
        upper: NDArray[np.float64],
    ) -> None:
        """Overwrite ``lower``, ``upper`` with this box."""
        np.subtract(self.lower, q, out=lower)
        np.subtract(self.upper, q, out=upper)
