r"""The joint acceleration box.

Bound the change of joint velocity from one control tick to the next.

With :math:`v_{k-1} = Δq_{k-1}/dt_{k-1}` the velocity of the previous step
:meth:`redik.Problem.step` returned and :math:`a` the bound (rad/s², m/s²),

.. math::

    (v_{k-1} - a\,dt)\,dt \;\le\; Δq_k \;\le\; (v_{k-1} + a\,dt)\,dt ,

i.e. :math:`|v_k - v_{k-1}| \le a\,dt`: the commanded velocity is Lipschitz in time. mink has
no such limit (its limits are memoryless).

**Why a tracking loop needs it.** Near a singularity of the level-0 tasks (a stretched
elbow), the null space a lower level moves in turns by :math:`O(‖δJ‖/σ)` per tick
(:meth:`redik.Problem.step`), so a posture regulator at priority 1 that saturates the velocity
box may push one way at one tick and the other way at the next: a two-tick cycle at
:math:`2 v_{max}/dt` (400 rad/s² at 2 rad/s, 100 Hz) that a servo cannot follow. Damping level
0 (``step_damping``) does not reach it. Bounding :math:`Δq_k - Δq_{k-1}` does, whatever level
causes it, and it is the constraint a real drive has. It is a hard limit like the others:
the levels share what it allows, level 0 first (a path demanding more acceleration is then
tracked late rather than with a jump).

**Braking (viability).** A velocity bound and an acceleration bound together can leave a
joint unable to stop before its position limit. The box therefore also caps the velocity
towards a finite limit at distance :math:`d` to the one from which braking at :math:`a`
stops in time: after this tick's :math:`v\,dt` the remaining :math:`d - v\,dt` must cover the
stopping distance :math:`v^2/(2a)` (:math:`≥` the discrete one, :math:`\sum_j (v - j a\,dt)\,dt`):

.. math::

    |v| \le a\Bigl(\sqrt{dt^2 + 2d/a} - dt\Bigr)

(the viability constraint of Del Prete, *Joint position and velocity bounds in discrete-time
acceleration/torque control of robot manipulators*, IEEE RA-L 2018, in its simplest form).
Where the previous velocity already exceeds this cap (a start at speed next to a limit), the
cap wins over the acceleration bound; and where the window lies outside the position and
velocity boxes it is moved to their nearest point: those are never given up
(:class:`redik.Problem` applies this box after the others).

The limit has memory: :meth:`redik.Problem.step` reports each step it returns
(:meth:`advance`); :meth:`reset` forgets it (a new motion, from rest by default), and
:meth:`redik.Problem.reset` resets every limit of a problem — the loop drivers
(:func:`redik.apps.sim.simulate`) call it at the start of each run.
:func:`redik.solve_problem` (iterative IK towards a static solution, not a motion) leaves
the limit out: it neither applies it to its iterates nor changes its state.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Robot
from redik.limits.limit import BoxLimit


class AccelerationLimit(BoxLimit):
    """Bound each joint's acceleration between control ticks.

    Each tangent coordinate of a ball or free joint is bounded alike.

    Args:
        max_acceleration: A scalar, one value per tangent coordinate, or a mapping from
            joint name to its bound (rad/s² or m/s², > 0); joints not in the mapping are
            unbounded.
        priority: See :class:`redik.limits.limit.Limit` (None: hard at every level).

    Attributes:
        max_acceleration: The bound per tangent coordinate, once bound.
        velocity: The velocity of the last recorded step (zero: at rest).
    """

    def __init__(
        self, max_acceleration: ArrayLike | Mapping[str, float], *, priority: int | None = None
    ):
        self._spec = max_acceleration
        self.max_acceleration = np.empty(0)
        self.velocity = np.empty(0)
        self._set_priority(priority)

    def bind(self, robot: Robot, tolerance: float = 0.0) -> AccelerationLimit:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        bound = self.positive_per_dof(self._spec, robot, "max_acceleration", "AccelerationLimit")
        self.max_acceleration = bound
        self.velocity = np.zeros(robot.dof)
        self._low = np.zeros(robot.dof)
        self._high = np.zeros(robot.dof)
        self._lower_range = robot.lower
        self._upper_range = robot.upper
        super().bind(robot, tolerance)
        return self

    def reset(self, velocity: ArrayLike | None = None) -> None:
        """Forget the recorded motion: the next step starts from ``velocity`` (default rest)."""
        self._require_bound()
        if velocity is None:
            self.velocity.fill(0.0)
            return
        given = np.asarray(velocity, dtype=float)
        if given.shape != self.velocity.shape or not np.isfinite(given).all():
            raise InvalidInput(
                f"velocity must be finite with shape {self.velocity.shape}, got {velocity!r}"
            )
        self.velocity[:] = given

    def advance(self, dq: NDArray[np.float64], dt: float | None) -> None:
        """Record the step ``dq`` taken over ``dt`` (called by :meth:`redik.Problem.step`)."""
        if dt is not None:
            np.divide(dq, dt, out=self.velocity)

    def bounds_into(
        self,
        q: NDArray[np.float64],
        dt: float | None,
        lower: NDArray[np.float64],
        upper: NDArray[np.float64],
    ) -> None:
        """Intersect this box with ``[lower, upper]`` in place (:meth:`BoxLimit.bounds_into`)."""
        if dt is None:
            raise InvalidInput(
                "AccelerationLimit needs the step duration: call problem.step(q, dt)"
            )
        a = self.max_acceleration
        with np.errstate(invalid="ignore"):  # inf − inf on unbounded joints
            # Fastest velocity from which braking at a stops before each finite limit.
            room_up = np.maximum(self._upper_range - q, 0.0)
            room_down = np.maximum(q - self._lower_range, 0.0)
            cap_up = a * (np.sqrt(dt * dt + 2.0 * room_up / a) - dt)
            cap_down = a * (np.sqrt(dt * dt + 2.0 * room_down / a) - dt)
        # An unbounded joint (a = inf, or no finite limit) gives nan or inf: no cap.
        cap_up = np.where(np.isnan(cap_up), np.inf, cap_up)
        cap_down = np.where(np.isnan(cap_down), np.inf, cap_down)
        # The acceleration window, moved to the nearest point of the braking window where
        # they do not meet (braking wins), then into the boxes already applied (position,
        # velocity): those are never given up for this one.
        np.clip((self.velocity - a * dt) * dt, -cap_down * dt, cap_up * dt, out=self._low)
        np.clip((self.velocity + a * dt) * dt, -cap_down * dt, cap_up * dt, out=self._high)
        low, high = self._low, self._high
        np.clip(low, lower, upper, out=low)
        np.clip(high, lower, upper, out=high)
        lower[:] = low
        upper[:] = high

    def _require_bound(self) -> None:
        if self.robot is None:
            raise InvalidInput(
                "AccelerationLimit is not bound: pass it to a redik.Problem or call "
                "limit.bind(robot) first"
            )
