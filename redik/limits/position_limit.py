r"""The joint position box: keep :math:`q + Δq` inside :math:`[q_{min}, q_{max}]`.

.. math::

    q_{min} + m - q \;\le\; Δq \;\le\; q_{max} - m - q, \qquad m = \text{margin} + τ

Joint positions are linear in ``q``, so unlike a velocity-damper this box is exact: a
step inside it lands inside the limits. The box is shrunk by the user's ``margin`` and by
the back-end's feasibility tolerance :math:`τ` (an interior-point or ADMM solver returns
bounds satisfied only to :math:`τ`), never by more than a quarter of a joint's range.
:class:`redik.Problem` additionally clips :math:`q + Δq` into the true limits, so the
configuration it returns never leaves them — mink's ``ConfigurationLimit`` does neither,
and its steps overshoot by up to the solver tolerance (≈5e-5 rad with proxqp, 5e-3 rad
with osqp). A joint outside its limits is pulled back inside by the box.
"""

from __future__ import annotations

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Robot
from redik.limits.limit import BoxLimit


class PositionLimit(BoxLimit):
    """Box the step so that the hinge and slide joints stay within their limits.

    Args:
        margin: Distance (rad or m) to keep from each limit, ≥ 0.
    """

    def __init__(self, margin: float = 0.0):
        margin = float(margin)
        if not np.isfinite(margin) or margin < 0.0:
            raise InvalidInput(f"margin must be finite and >= 0, got {margin}")
        self.margin = margin
        self.lower = np.empty(0)
        self.upper = np.empty(0)

    def bind(self, robot: Robot, tolerance: float = 0.0) -> PositionLimit:
        span = robot.upper - robot.lower
        shrink = np.minimum(self.margin + tolerance, np.where(np.isfinite(span), span / 4, 0.0))
        self.lower = robot.lower + shrink
        self.upper = robot.upper - shrink
        return super().bind(robot, tolerance)

    def bounds_into(
        self, q: np.ndarray, dt: float | None, lower: np.ndarray, upper: np.ndarray
    ) -> None:
        np.maximum(lower, self.lower - q, out=lower)
        np.minimum(upper, self.upper - q, out=upper)

    def set_bounds(
        self, q: np.ndarray, dt: float | None, lower: np.ndarray, upper: np.ndarray
    ) -> None:
        np.subtract(self.lower, q, out=lower)
        np.subtract(self.upper, q, out=upper)
