r"""The limit contract: hard inequalities on the joint step ``Δq``.

A limit restricts the joint step (``robot.dof`` tangent coordinates, :mod:`redik.kinematics.robot`)
to

.. math::

    G(q)\, Δq \le h(q) .

Most limits are boxes, :math:`l(q) \le Δq \le u(q)` (:class:`BoxLimit`): they are
intersected into one pair of bounds per step, which every back-end takes natively
(simple bounds in daqp, box constraints in proxsuite). Other limits
(:class:`~redik.limits.mink_limit.MinkLimit`) give general rows ``(G, h)``.
A :class:`redik.Problem` binds its limits to its robot and passes the back-end's
feasibility ``tolerance``, by which position boxes are shrunk so that a solution
returned within tolerance still lies inside the true limits.
"""

from __future__ import annotations

import abc

import numpy as np

from redik.kinematics.robot import Robot


class Limit:
    """Base class of hard limits on the robot's joint step."""

    robot: Robot | None = None

    def bind(self, robot: Robot, tolerance: float = 0.0) -> Limit:
        """Prepare for ``robot``; ``tolerance`` is the back-end's feasibility tolerance."""
        self.robot = robot
        return self


class BoxLimit(Limit, abc.ABC):
    """A limit of the form ``lower(q, dt) ≤ Δq ≤ upper(q, dt)``, joint by joint."""

    @abc.abstractmethod
    def bounds_into(
        self, q: np.ndarray, dt: float | None, lower: np.ndarray, upper: np.ndarray
    ) -> None:
        """Intersect this box with ``[lower, upper]`` in place (``lower = max(lower, l)``…).

        ``q`` is per tangent coordinate, ``robot.scalar_values(q)``: the hinge and slide
        values (0 on ball and free joints, which have no position box).
        """

    def set_bounds(
        self, q: np.ndarray, dt: float | None, lower: np.ndarray, upper: np.ndarray
    ) -> None:
        """Overwrite ``lower``, ``upper`` with this box."""
        lower.fill(-np.inf)
        upper.fill(np.inf)
        self.bounds_into(q, dt, lower, upper)


class InequalityLimit(Limit, abc.ABC):
    """A limit of general rows ``G Δq ≤ h`` over the robot's tangent coordinates."""

    needs_configuration = False
    """True when the rows are computed from a ``mink.Configuration`` kept in sync."""

    @abc.abstractmethod
    def inequalities(self, state, dt: float | None) -> tuple[np.ndarray, np.ndarray] | None:
        """``(G, h)`` with ``G`` of shape (m, ``robot.dof``), or None when inactive."""

    def admits(self) -> bool:
        """Whether the robot's current state (a trial ``q ⊕ αΔq``, after forward kinematics)
        respects the limit itself, not only its linearisation at ``q``.

        :meth:`redik.Problem.solve` shortens (backtracks) a step until every limit admits
        it. Rows linear in ``Δq`` are exact (True); a limit linearised at ``q`` — a distance
        — checks the nonlinear quantity here.
        """
        return True
