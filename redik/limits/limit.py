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

**Priority.** By default (``priority=None``) a limit is hard at every level: it belongs to
the feasible set :math:`\mathcal{X}` in which the whole lexicographic QP is solved
(:mod:`redik.qp.hierarchy`), so no task, however high, may break it — the joint box,
collision avoidance between arms. A limit given ``priority=k`` is instead an *inequality
task* placed just above the tasks of priority :math:`k` (Kanoun, Lamiraux & Wieber, IEEE
T-RO 2011, §III; Escande, Mansard & Wieber, IJRR 2014, the slack form). With
:math:`S` the step set the levels of priority :math:`< k` leave optimal (and the hard
limits), its level is

.. math::

    w^* = \arg\min_{Δq \in S,\ w} \tfrac12 \|w\|^2 \quad\text{s.t.}\quad
    G Δq - w \le h ,

and every level from :math:`k` down is solved subject to :math:`G Δq \le h + w^*`. So:

- tasks of priority :math:`< k` ignore the limit (they may violate it: a target inside an
  obstacle is reached when the collision limit ranks below the hand);
- the limit is then met as far as those tasks allow, with the least violation in the
  least-squares sense over its rows (of its own units: metres for a distance, radians for
  a joint) — no violation when their optimal set meets it;
- tasks of priority :math:`\ge k` cannot buy their objective with a violation: to them the
  limit is hard (relaxed by :math:`w^*` only).

Why not "a hard constraint of the levels :math:`\ge k` only": the higher levels' optimal set
need not meet :math:`Gx \le h` at all, and the QP of level :math:`k` would then be
infeasible; the slack level is the least-violation version of that intent, equal to it
whenever it is feasible (to the damping below). Why not a weighted penalty within level
:math:`k`: it trades millimetres of clearance against task error at a ratio set by units and
costs, and gives no guarantee that the limit holds when it can. ``priority=0`` is a hard
limit that degrades to least violation instead of
:class:`~redik.core.exceptions.InfeasibleProblem`.
The slack level is damped (:data:`redik.qp.hierarchy.SLACK_DAMPING` ``ρ``, as
Levenberg–Marquardt damps a least-squares step): one step removes the fraction
:math:`σ^2/(σ^2 + ρ)` of a violation the free directions can remove with gain :math:`σ`
(96 % at 0.5 m/rad, and a small :math:`σ` no longer calls for a huge step), and the
iteration (the driver, or a control loop) converges to the least violation itself.

Iterative solves (:func:`redik.solve_problem`) shorten a step by
:meth:`InequalityLimit.admits` only for the limits no task outranks (hard, or ranked at or
above the first level): a limit ranked below a task must let that task's steps through. A
prioritised position box does not clip :math:`q + Δq`: the levels above it may move the
joint out of that box.
"""

from __future__ import annotations

import abc
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Robot
from redik.tasks.task import as_priority


class Limit:
    """Base class of limits on the robot's joint step.

    Attributes:
        priority: None (the default): hard at every priority level; an integer ``k ≥ 0``:
            an inequality task ranked just above the tasks of priority ``k`` (module
            docstring). Every limit takes it as the keyword argument ``priority=``.
    """

    robot: Robot | None = None
    priority: int | None = None

    def _set_priority(self, priority: int | None) -> None:
        self.priority = None if priority is None else as_priority(priority)

    def _require_robot(self) -> Robot:
        """The bound robot; :class:`InvalidInput` naming the limit when it is not bound."""
        if self.robot is None:
            raise InvalidInput(
                f"{type(self).__name__} is not bound: pass it to a redik.Problem or call "
                "limit.bind(robot) first"
            )
        return self.robot

    def bind(self, robot: Robot, tolerance: float = 0.0) -> Limit:
        """Prepare for ``robot``; ``tolerance`` is the back-end's feasibility tolerance."""
        self.robot = robot
        return self

    def advance(self, dq: NDArray[np.float64], dt: float | None) -> None:
        """Record the step :meth:`redik.Problem.step` returns (a limit with memory).

        Called by :meth:`redik.Problem.step` with the step it returns; a limit with memory
        (:class:`~redik.limits.acceleration_limit.AccelerationLimit`) records it.
        """

    def reset(self, velocity: NDArray[np.float64] | None = None) -> None:
        """Forget what earlier steps recorded (:meth:`advance`).

        The next step starts a new motion with joint velocity ``velocity`` (``robot.dof``,; None: at
        rest).

        Called by :meth:`redik.Problem.reset`, which the loop drivers
        (:func:`redik.apps.sim.simulate`) call at the start of each run. A memoryless limit
        (every limit but :class:`~redik.limits.acceleration_limit.AccelerationLimit`) has
        nothing to forget: this default does nothing.
        """


class BoxLimit(Limit, abc.ABC):
    """A limit of the form ``lower(q, dt) ≤ Δq ≤ upper(q, dt)``, joint by joint."""

    @abc.abstractmethod
    def bounds_into(
        self,
        q: NDArray[np.float64],
        dt: float | None,
        lower: NDArray[np.float64],
        upper: NDArray[np.float64],
    ) -> None:
        """Intersect this box with ``[lower, upper]`` in place (``lower = max(lower, l)``…).

        ``q`` is per tangent coordinate, ``robot.scalar_values(q)``: the hinge and slide
        values (0 on ball and free joints, which have no position box).
        """

    def set_bounds(
        self,
        q: NDArray[np.float64],
        dt: float | None,
        lower: NDArray[np.float64],
        upper: NDArray[np.float64],
    ) -> None:
        """Overwrite ``lower``, ``upper`` with this box."""
        lower.fill(-np.inf)
        upper.fill(np.inf)
        self.bounds_into(q, dt, lower, upper)

    @staticmethod
    def positive_per_dof(spec: object, robot: Robot, name: str, owner: str) -> NDArray[np.float64]:
        """A per-coordinate bound from a scalar, an array or a mapping from joint name.

        A bound given as a scalar, one value per tangent coordinate, or a mapping from joint name to
        value (joints not named: unbounded), as one value per tangent coordinate of ``robot`` (a
        ball or free joint's value applies to each of its coordinates), every one > 0.

        Raises:
            InvalidInput: a joint the robot does not move, a wrong shape, text or None, or a
                value that is NaN or ≤ 0 (``name`` and ``owner`` name them).
        """
        try:
            if isinstance(spec, Mapping):
                unknown = sorted(set(spec) - set(robot.joint_names))
                if unknown:
                    raise InvalidInput(
                        f"{owner} names joints {unknown} the robot does not move "
                        f"{robot.joint_names}"
                    )
                bound = np.array([float(spec.get(joint, np.inf)) for joint in robot.dof_joints])
            else:
                bound = np.atleast_1d(np.asarray(spec, dtype=float))
                if bound.shape not in ((1,), (robot.dof,)):
                    raise InvalidInput(
                        f"{name} must be a scalar, ({robot.dof},) or a mapping, "
                        f"got shape {bound.shape}"
                    )
                bound = np.broadcast_to(bound, (robot.dof,)).copy()
        except (TypeError, ValueError) as error:  # text or None where a number belongs
            if isinstance(error, InvalidInput):
                raise
            raise InvalidInput(
                f"{name} must be a number, an array or a mapping from joint name to a "
                f"number, got {spec!r}"
            ) from None
        if np.any(np.isnan(bound)) or np.any(bound <= 0.0):
            raise InvalidInput(f"{name} must be > 0, got {bound.tolist()}")
        return bound


class InequalityLimit(Limit, abc.ABC):
    """A limit of general rows ``G Δq ≤ h`` over the robot's tangent coordinates."""

    needs_configuration = False
    """True when the rows are computed from a ``mink.Configuration`` kept in sync."""

    @abc.abstractmethod
    def inequalities(
        self,
        # A KinematicState, or the synchronised mink.Configuration when needs_configuration.
        state: Any,
        dt: float | None,
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
        """``(G, h)`` with ``G`` of shape (m, ``robot.dof``), or None when inactive."""

    def admits(self) -> bool:
        """Whether the current state respects the limit itself, not only its linearisation.

        Whether the robot's current state (a trial ``q ⊕ αΔq``, after forward kinematics) respects
        the limit itself, not only its linearisation at ``q``.

        :func:`redik.solve_problem` shortens (backtracks) a step until every limit admits
        it. Rows linear in ``Δq`` are exact (True); a limit linearised at ``q`` — a distance
        — checks the nonlinear quantity here.
        """
        return True
