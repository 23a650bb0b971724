r"""The differential IK problem: a robot, a stack of tasks and limits, one QP per step.

A :class:`Problem` builds, at a configuration :math:`q`, the lexicographic QP of its tasks
(one objective per priority level, :mod:`redik.qp.assembly`) subject to its limits
(:mod:`redik.limits`), and answers the joint step :math:`Δq` (:mod:`redik.qp.hierarchy`),
as mink's ``build_ik``/``solve_ik`` do:

.. math::

    Δq_0^* \in \arg\min_{Δq \in \mathcal{X}(q)} f_0(Δq), \quad
    Δq_k^* \in \arg\min_{Δq \in S_k} f_k(Δq), \qquad
    f_k(Δq) = \tfrac12 Δq^\top H_k(q) Δq + c_k(q)^\top Δq .

:meth:`Problem.step` is one control tick (motion limits apply and remember the step);
:meth:`Problem.reset` starts a new motion. Iterating towards a static solution is a
driver's job (:func:`redik.solve_problem`): the problem answers what the driver asks at a
configuration — the static step (:meth:`Problem.static_step`), the level-0 errors and
rows (:meth:`Problem.measure`, :meth:`Problem.target_rows`), the box on the step
(:meth:`Problem.step_bounds`), each optimised level's value and projected gradient
(:meth:`Problem.objective_values`, :meth:`Problem.stationarity`).

**Limits are never left.** The position box is shrunk by the back-end's tolerance and
:math:`Δq` is clipped into it, so every configuration a step leads to lies within the
joint limits (:mod:`redik.limits.configuration_limit`). The default limits also hold every
limited ball joint in its cone (:mod:`redik.limits.ball_joint_limit`).

**Whole models.** On a robot with ball or free joints ``q`` has ``robot.nq`` entries and
``Δq`` ``robot.dof`` (the tangent space); apply a step with :meth:`Problem.integrate`
(``robot.integrate``, ``mj_integratePos``). mink tasks and limits may be mixed in; a
``mink.Configuration`` is then kept in sync with ``q`` (one more forward kinematics per
step, paid only when one is present), and an exception raised inside one reaches the
caller as a :class:`~redik.core.exceptions.TaskError` naming it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any, TypeGuard

import mink
import numpy as np
from mink.tasks import BaseTask
from mink.tasks import Task as MinkTask
from numpy.typing import NDArray
from scipy.optimize import nnls

from redik.core.exceptions import InfeasibleProblem, InvalidInput
from redik.core.validate import non_negative, positive, real_array
from redik.kinematics.robot import Robot
from redik.limits import (
    AccelerationLimit,
    BallJointLimit,
    BoxLimit,
    ConfigurationLimit,
    InequalityLimit,
    Limit,
    MinkLimit,
)
from redik.limits.ball_joint_limit import limited_ball_joints
from redik.qp.assembly import Assembly
from redik.qp.backends import Backend, make_backend
from redik.qp.compiled import compiled_plan
from redik.qp.curvature import CURVATURE_STEP, bound_multipliers, on_free_face
from redik.qp.hierarchy import (
    Curvature,
    kernel_directions,
    row_null_space,
    solve_lexicographic,
)
from redik.tasks.foreign import foreign_call
from redik.tasks.joint_space_task import JointSpaceTask
from redik.tasks.kinematics import KinematicState
from redik.tasks.single_frame_task import SingleFrameTask
from redik.tasks.task import ResidualTask, Task

if TYPE_CHECKING:
    from mink.limits import Limit as MinkLimitBase

ACTIVE_TOL = 1e-6
"""A bound on ``Δq`` within this (rad or m) of zero, or a row with ``h`` within it, is active:
Bertsekas's ε-active set (*Projected Newton methods for optimization problems with simple
constraints*, SIAM J. Control Optim. 1982). With exact activity an iterate approaching a
bound geometrically is never stationary although it is within round-off of the constrained
optimum."""

FEASIBILITY_TOL = 1e-9
"""Violation of a hard inequality row (``h ≥ −tol`` at ``Δq = 0``) :meth:`Problem.feasible`
accepts."""


@dataclasses.dataclass(slots=True)
class Measurement:
    """Level 0 at one configuration (:meth:`Problem.measure`).

    Attributes:
        converged: Every target of level 0 is met: the position of a task with
            ``pose_errors`` (a frame or relative-frame task) within ``pos_tol`` and its
            rotation within ``rot_tol`` (a part of zero cost is not judged), any other
            target's cost-weighted error ``‖W e‖`` within ``pos_tol``.
        error: ``‖W e‖`` over every target of level 0 (0 without targets).
        position_error: The largest position error of those tasks (m), or None.
        rotation_error: The largest rotation error of those tasks (rad), or None.
        admitted: Every hard limit linearised at a configuration (a collision distance)
            holds at this one (:meth:`~redik.limits.limit.InequalityLimit.admits`).
    """

    converged: bool
    error: float
    position_error: float | None
    rotation_error: float | None
    admitted: bool


def _is_real(value: object) -> TypeGuard[float]:
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)


def _check_dt(dt: object) -> None:
    if dt is not None:
        positive(dt, "dt", unit="s")


def _as_list(items: object, name: str, marker: str) -> list[Any]:
    """``items`` as a list; one object having ``marker`` (a task, a limit) is the list of it."""
    if hasattr(items, marker) or isinstance(items, Limit):
        return [items]
    if isinstance(items, Iterable) and not isinstance(items, str | bytes):
        try:
            return list(items)
        except TypeError:  # a 0-d array
            pass
    raise InvalidInput(f"{name} must be a list (or a single one), got {items!r}")


def _checked_tasks(tasks: object) -> list[BaseTask]:
    checked = _as_list(tasks, "tasks", "compute_qp_objective")
    if not checked:
        raise InvalidInput("a Problem needs at least one task")
    for task in checked:
        if not hasattr(task, "compute_qp_objective"):
            raise InvalidInput(f"{task!r} is not a task (no compute_qp_objective)")
    return checked


def _check_settings(
    damping: object, step_damping: object, rank_tol: object, backend_options: object
) -> None:
    non_negative(damping, "damping")
    non_negative(step_damping, "step_damping")
    if not _is_real(rank_tol) or not (np.isfinite(rank_tol) and 0.0 <= rank_tol < 1.0):
        raise InvalidInput(f"rank_tol must be in [0, 1), got {rank_tol!r}")
    if backend_options is not None and not isinstance(backend_options, dict):
        raise InvalidInput(f"backend_options must be a dict, got {backend_options!r}")


def _bound_limits(robot: Robot, limits: object, tolerance: float) -> list[Limit]:
    """The limits (default: the robot's own ranges), mink's wrapped, bound to ``robot``."""
    given: list[Any]
    if limits is None:
        given = [ConfigurationLimit()] + ([BallJointLimit()] if limited_ball_joints(robot) else [])
    else:
        given = _as_list(limits, "limits", "compute_qp_inequalities")
    bound = []
    for limit in given:
        if not isinstance(limit, Limit):
            if not hasattr(limit, "compute_qp_inequalities"):
                raise InvalidInput(f"{limit!r} is not a limit")
            limit = MinkLimit(limit)
        bound.append(limit.bind(robot, tolerance))
    return bound


def _cost(task: BaseTask) -> NDArray[np.float64]:
    """A target's cost ``w``: mink's tasks carry one (redik's residual tasks are mink's), 1 else."""
    return np.asarray(task.cost if isinstance(task, MinkTask) else 1.0, dtype=float)


def _is_target(task: BaseTask) -> bool:
    """A task with a target.

    A residual task that is not a joint-space regulariser, or a mink task (what "level 0 is met"
    waits for).
    """
    if isinstance(task, JointSpaceTask):
        return False
    return isinstance(task, ResidualTask) or not isinstance(task, Task)


class Problem:
    """Differential IK as a (hierarchical) QP over the joints ``robot`` moves.

    Args:
        robot: The robot; ``Δq`` has ``robot.dof`` entries (its tangent coordinates), a
            configuration ``q`` has ``robot.nq`` (see :mod:`redik.kinematics.robot`).
        tasks: redik tasks and/or mink tasks (``mink.FrameTask``, ``mink.ComTask``…). Tasks
            of equal ``priority`` are weighted and summed; priorities are strict. A single
            task is accepted as the list of it, ``Problem(robot, FrameTask("ee", target=T))``.
        limits: redik or mink limits; None is the robot's own ranges, ``[ConfigurationLimit()]``
            plus a :class:`~redik.limits.BallJointLimit` when it moves limited ball joints;
            ``[]`` is none; a single limit is the list of it. A limit is hard at every level
            unless given ``priority=k`` (:mod:`redik.limits.limit`).
        backend: A back-end name, a list of names (a fallback chain) or a
            :class:`~redik.qp.backends.Backend` (:func:`~redik.qp.backends.make_backend`);
            an instance serves one priority level only, since back-ends keep per-QP state:
            with several levels, pass a name.
        damping: Regularisation ``ε`` added to each level's Hessian (default 1e-6: keeps
            active-set solvers out of trouble, changes a converged solution by nothing).
        rank_tol: Relative eigenvalue threshold of the null space between levels.
        backend_options: Settings passed to the back-end.
        step_damping: Levenberg–Marquardt scale ``μ ≥ 0`` of :meth:`step` (default 0): level
            0's Hessian gets ``λ = μ‖b₀‖²``, ``b₀`` its stacked weighted residual.
        compiled: Let :meth:`step` and :meth:`static_step` (without its curvature term) run
            the compiled plan when the stack allows it (default); False forces the general
            path.

    With ``backend="daqp"`` (the default) or ``"quadprog"`` and a stack of frame and position
    tasks, posture, joint-limit avoidance and damping on one level or two, and configuration,
    velocity and collision limits, :meth:`step` runs a compiled plan
    (:mod:`redik.qp.compiled`): box-constrained steps are solved by redik's compiled
    active-set method, steps whose collision rows bind by DAQP called directly. It answers
    what the general path answers, up to round-off; anything else (mink tasks, ranked or
    acceleration limits, other back-ends, three levels, ``step_damping``) takes the general
    path, chosen once per problem (:attr:`compiled`).

    Attributes:
        robot: The robot.
        tasks: The tasks, as given.
        limits: The limits, bound to the robot.
        levels: The priority values, highest first.
        backends: One back-end per level.
        frame_tasks: The frame tasks of level 0 (:class:`~redik.tasks.SingleFrameTask`).
        has_targets: Level 0 holds a task with a target (a frame, position, equality or mink
            task); without, level 0 is a regulariser optimised like the lower levels.
        stats: Counters; ``"skipped_levels"``: lower levels whose back-end failed
            (:mod:`redik.qp.hierarchy`).
        compiled: Whether :meth:`step` and :meth:`static_step` run the compiled plan.
    """

    def __init__(
        self,
        robot: Robot,
        tasks: BaseTask | Sequence[BaseTask],
        limits: Limit | MinkLimitBase | Sequence[Limit | MinkLimitBase] | None = None,
        backend: str | Sequence[str] | Backend = "daqp",
        *,
        damping: float = 1e-6,
        rank_tol: float = 1e-10,
        backend_options: dict[str, Any] | None = None,
        step_damping: float = 0.0,
        compiled: bool = True,
    ) -> None:
        if not isinstance(robot, Robot):
            raise InvalidInput(f"robot must be a redik.Robot, got {type(robot).__name__}")
        checked = _checked_tasks(tasks)
        _check_settings(damping, step_damping, rank_tol, backend_options)
        self.robot = robot
        self.tasks: list[Any] = checked  # redik's tasks and mink's
        self.damping = float(damping)
        self.rank_tol = float(rank_tol)
        self.step_damping = float(step_damping)
        self._assembly = Assembly(robot, checked, self.damping)
        self.levels = [level.priority for level in self._assembly.levels]
        self._make_backends(backend, backend_options or {})
        self.limits = _bound_limits(robot, limits, max(b.tolerance for b in self.backends))
        self._sort_limits(backend, backend_options or {})
        self._prepare_targets()
        self.stats: dict[str, int] = {}
        self._state = KinematicState.for_robot(robot)
        self._configuration = None
        if self._assembly.needs_configuration or any(
            getattr(limit, "needs_configuration", False) for limit in self.limits
        ):
            self._configuration = mink.Configuration(robot.model)
        self._at = (b"", b"")  # the q and qpos the state was built at, as bytes
        self._lb = np.full(robot.dof, -np.inf)
        self._ub = np.full(robot.dof, np.inf)
        self._plan = None
        if compiled and self._configuration is None:
            self._plan = compiled_plan(
                robot, self._state, self._assembly.levels, self.limits, self.backends,
                damping=self.damping, rank_tol=self.rank_tol, step_damping=self.step_damping,
            )  # fmt: skip
        self.compiled = self._plan is not None

    # ----------------------------------------------------------------------------------
    # Construction

    def _make_backends(
        self, backend: str | Sequence[str] | Backend, options: dict[str, Any]
    ) -> None:
        if isinstance(backend, Backend) and (len(self.levels) > 1 or options):
            raise InvalidInput(
                f"a Backend instance ({backend.name!r}) keeps one QP's state and its own "
                f"settings: it cannot serve {len(self.levels)} priority levels or take "
                "backend_options; pass the back-end by name"
            )
        self.backends = [make_backend(backend, **options) for _ in self.levels]

    def _sort_limits(self, backend: str | Sequence[str] | Backend, options: dict[str, Any]) -> None:
        """Hard boxes, hard rows, ranked groups, and the limits that shorten driver steps."""
        hard = [limit for limit in self.limits if limit.priority is None]
        # The acceleration box yields to the position and velocity boxes: applied after them.
        self._boxes = sorted(
            (limit for limit in hard if isinstance(limit, BoxLimit)),
            key=lambda limit: isinstance(limit, AccelerationLimit),
        )
        # A static solve looks for a configuration, not a motion: the acceleration box (a
        # bound between control ticks) has no meaning there.
        self._static_boxes = [b for b in self._boxes if not isinstance(b, AccelerationLimit)]
        self._rows = [limit for limit in hard if isinstance(limit, InequalityLimit)]
        self._clip = any(isinstance(limit, ConfigurationLimit) for limit in hard)
        priorities = sorted({limit.priority for limit in self.limits if limit.priority is not None})
        if priorities and isinstance(backend, Backend):
            raise InvalidInput(
                f"a Backend instance ({backend.name!r}) keeps one QP's state: it cannot also "
                f"serve the levels of the limits ranked at priorities {priorities}; pass the "
                "back-end by name"
            )
        # (priority, index of the first task level at or below it, its limits, its back-end)
        self._ranked = [
            (
                p,
                sum(level < p for level in self.levels),
                [limit for limit in self.limits if limit.priority == p],
                make_backend(backend, **options),
            )
            for p in priorities
        ]
        # Limits whose nonlinear check shortens a driver's steps: those no task outranks.
        self._admitting = self._rows + [
            limit
            for _, index, limits, _ in self._ranked
            if index == 0
            for limit in limits
            if isinstance(limit, InequalityLimit)
        ]
        self._wraps = [
            limit
            for limit in self.limits
            if isinstance(limit, ConfigurationLimit) and limit.turning.any()
        ]

    def _prepare_targets(self) -> None:
        level0 = self._assembly.levels[0]
        self._targets = [task for task in level0.tasks if _is_target(task)]
        self.has_targets = bool(self._targets)
        self.frame_tasks = [t for t in self._targets if isinstance(t, SingleFrameTask)]
        n = self.robot.dof
        # Level 0's rows when it is a least-squares level: its null space comes from their
        # QR, its unconstrained step from their Gram matrix (redik.qp.hierarchy).
        self._rows0 = level0.A if level0.least_squares else None
        self._rhs0 = level0.b
        self._curvature_rows = np.empty_like(level0.A)
        self._curvature_rhs = np.empty_like(level0.b)
        # Error and Jacobian buffers of the redik targets (a mink task's size may vary).
        self._target_buffers = {
            id(task): (np.empty(task.k), np.empty((task.k, n)))
            for task in self._targets
            if isinstance(task, ResidualTask)
        }
        # What measure asks of each target: its error buffer (None: a mink task) and its
        # pose_errors (None: judged by ‖W e‖), looked up once.
        # (target, its error buffer when it is redik's, its pose_errors when it has one)
        self._measured: list[tuple[Any, NDArray[np.float64] | None, Any]] = [
            (
                task,
                self._target_buffers[id(task)][0] if id(task) in self._target_buffers else None,
                getattr(task, "pose_errors", None) if isinstance(task, Task) else None,
            )
            for task in self._targets
        ]

    # ----------------------------------------------------------------------------------
    # Online control

    def step(self, q: NDArray[np.float64], dt: float | None = None) -> NDArray[np.float64]:
        r"""The joint step ``Δq`` of one control tick at ``q``.

        The lexicographic QP of the module docstring with every hard limit, motion limits
        included (:class:`~redik.limits.AccelerationLimit` bounds it around the velocity of
        the previous step). With ``step_damping = μ > 0`` level 0 is solved as damped least
        squares, :math:`\min ½‖AΔq − b‖² + ½λ‖Δq‖²`, :math:`λ = μ‖b‖²` (Sugihara, *Solvability-
        unconcerned inverse kinematics by the Levenberg–Marquardt method*, IEEE T-RO 2011):
        where a target leaves the workspace, the undamped step along the weakest singular
        pair :math:`(σ, u, v)` of :math:`A`, :math:`σ^{-1}u^\top b`, grows without bound;
        damped it is :math:`σ/(σ^2 + λ)\,u^\top b → 0`, while on a reachable path
        :math:`λ` vanishes quadratically with the error. Each step is reported to the limits
        (:meth:`~redik.limits.limit.Limit.advance`) until :meth:`reset`.

        Args:
            q: The configuration (``robot.nq``,).
            dt: The tick's duration (s); velocity and acceleration limits need it. Divide
                ``Δq`` by it for a velocity.

        Returns:
            ``Δq`` (``robot.dof``,), a tangent vector: apply it with :meth:`integrate`;
            ``q ⊕ Δq`` stays within the position limits.

        Raises:
            InvalidConfiguration: ``q`` has the wrong shape or non-finite entries.
            InvalidInput: ``dt`` is not a positive number, or a limit that needs it lacks it.
            InfeasibleProblem: the limits admit no step (a joint outside its range by more
                than its velocity limit recovers in ``dt``).
            BackendError: the back-end (every back-end of a chain) failed.
            TaskError: a foreign (mink) task or limit raised.
        """
        if self._plan is not None:
            dq = self._plan.step(q, dt)
            if dq is not None:
                return dq
        q = self.robot.check_q(q, "q")
        _check_dt(dt)
        self._update(q)
        dq = self._solve_step(q, dt, motion=True, error_damping=self.step_damping)
        for limit in self.limits:
            limit.advance(dq, dt)
        return dq

    def reset(self, velocity: NDArray[np.float64] | None = None) -> None:
        """Start a new motion from joint velocity ``velocity`` (None: at rest).

        Every limit and task forgets what earlier :meth:`step` calls recorded (an
        :class:`~redik.limits.AccelerationLimit` otherwise brakes the first step of a new
        run against the last velocity of the previous one) and the back-ends forget their
        warm starts, so a run repeats a fresh problem's bit for bit. Task targets are kept.

        Args:
            velocity: Joint velocity (``robot.dof``,; rad/s or m/s) the motion starts at.

        Raises:
            InvalidInput: ``velocity`` not finite or not of shape (``robot.dof``,).
        """
        if velocity is not None:
            velocity = real_array(velocity, "velocity")
            if velocity.shape != (self.robot.dof,) or not np.isfinite(velocity).all():
                raise InvalidInput(
                    f"velocity must be finite with shape ({self.robot.dof},) (robot.dof), "
                    f"got {velocity.tolist()!r}"
                )
        for limit in self.limits:
            limit.reset(velocity)
        for task in self.tasks:
            reset = getattr(task, "reset", None)  # mink tasks have no memory and no reset
            if reset is not None:
                reset(velocity)
        self.reset_backends()

    def reset_backends(self) -> None:
        """Make the back-ends forget their warm starts, and nothing else.

        A warm-started active set changes an answer by round-off only, but round-off grows
        over an iteration: a driver that resets them first repeats a fresh problem's answer
        bit for bit, whatever the problem solved before (the limits' motion is kept).
        """
        for backend in [*self.backends, *(backend for *_, backend in self._ranked)]:
            backend.reset()
        if self._plan is not None:
            self._plan.reset()

    # ----------------------------------------------------------------------------------
    # What a driver asks at a configuration

    def static_step(
        self,
        q: NDArray[np.float64],
        dt: float | None = None,
        *,
        lm_damping: float = 0.0,
        second_order: bool = False,
        max_step: float | None = None,
    ) -> NDArray[np.float64]:
        r"""The step ``Δq`` towards a static solution at ``q``: :meth:`step` without motion.

        Motion limits (:class:`~redik.limits.AccelerationLimit`, a bound between control
        ticks) are left out and nothing is recorded: the iterates of a driver are no control
        ticks.

        Args:
            q: The configuration (``robot.nq``,).
            dt: Passed to velocity limits (None without one).
            lm_damping: ``λ ≥ 0`` added to level 0's Hessian (Levenberg–Marquardt).
            second_order: Add level 1's curvature term: the reduced Hessian of the
                Lagrangian :math:`f_1 + λ^\top r_0` (sequential quadratic programming,
                Nocedal & Wright §18.1, null-space form §18.4), :math:`N^\top(H_1 + M)N`
                with :math:`M = \sum_i λ_i ∇^2 r_i` the curvature of level 0's rows weighted
                by level 1's multipliers (:mod:`redik.qp.curvature`); on a least-squares level
                0 only, and only while the model stays convex.
            max_step: Optional trust region, ``|Δq_i| ≤ max_step``.

        Returns:
            ``Δq`` (``robot.dof``,).
        """
        self._goto(q)
        if self._plan is not None and not (second_order and len(self.levels) > 1):
            dq = self._plan.static_step(q, dt, lm_damping, max_step)
            if dq is not None:
                return dq
        return self._solve_step(
            q, dt, lm_damping=lm_damping, second_order=second_order, max_step=max_step
        )

    def measure(self, q: NDArray[np.float64], pos_tol: float, rot_tol: float) -> Measurement:
        """Forward kinematics at ``q`` and what level 0's targets say of it.

        Args:
            q: The configuration (``robot.nq``,).
            pos_tol: Position tolerance (m) of frame tasks, and of ``‖W e‖`` of the other
                targets.
            rot_tol: Rotation tolerance (rad) of frame tasks.

        Returns:
            The :class:`Measurement` at ``q``.
        """
        self._goto(q)
        converged, squared = True, 0.0
        worst: list[float | None] = [None, None]
        for task, e, pose_errors in self._measured:
            if e is not None:
                task.error_into(self._state, e)
                weighted = np.multiply(task.cost, e, out=e)
            else:
                weighted = self._weighted_error(task)
            norm2 = float(weighted.dot(weighted))
            squared += norm2
            if pose_errors is None:
                converged = converged and math.sqrt(norm2) <= pos_tol
                continue
            errors = zip(pose_errors(self._state), (pos_tol, rot_tol), strict=True)
            for i, (value, tol) in enumerate(errors):
                if value is not None:
                    converged = converged and value <= tol
                    worst[i] = value if worst[i] is None else max(worst[i], value)
        admitted = all(limit.admits() for limit in self._admitting)
        return Measurement(converged, math.sqrt(squared), worst[0], worst[1], admitted)

    def target_rows(
        self, q: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        r"""Level 0's targets as least squares at ``q``: ``(A, b)`` with ``A = W J``, ``b = −W e``.

        The stacked cost-weighted Jacobians and errors of every target of level 0 (redik
        residual tasks and mink tasks), without the gains: :math:`\min ‖AΔq − b‖` is the
        Gauss–Newton step on :math:`\tfrac12\|W e\|^2`, whose slope along ``Δq`` is
        :math:`-2 b^\top A Δq`.

        Args:
            q: The configuration (``robot.nq``,).

        Returns:
            ``(A, b)``, fresh arrays (``m × robot.dof``, ``m``); ``m = 0`` without targets.
        """
        self._goto(q)
        rows, rhs = [], []
        for task in self._targets:
            e, J = self._error_and_jacobian(task)
            cost = _cost(task)
            rows.append(cost[:, None] * J)
            rhs.append(-cost * e)
        if not rows:
            return np.empty((0, self.robot.dof)), np.empty(0)
        return np.vstack(rows), np.concatenate(rhs)

    def step_bounds(
        self, q: NDArray[np.float64], dt: float | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The box the static limits put on ``Δq`` at ``q`` (position, velocity; ±inf else).

        Args:
            q: The configuration (``robot.nq``,).
            dt: Passed to velocity limits.

        Returns:
            ``(lb, ub)``, fresh arrays (``robot.dof``,).
        """
        lb, ub = np.full(self.robot.dof, -np.inf), np.full(self.robot.dof, np.inf)
        q_box = self.robot.scalar_values(q)
        for limit in self._static_boxes:
            limit.bounds_into(q_box, dt, lb, ub)
        return lb, ub

    def stationarity(self, q: NDArray[np.float64], dt: float | None = None) -> list[float]:
        r"""Per optimised level, the norm of its projected gradient at ``q``.

        The optimised levels are those below level 0's targets: levels 1… when level 0 has
        targets (:attr:`has_targets`), every level when it has none. With :math:`g_k` the
        gradient of level :math:`k`'s objective (the linear term :math:`c_k` of its QP),
        :math:`N_{k-1}` an orthonormal basis of the directions the levels above leave free
        and :math:`\mathcal{A}` the limits active at ``q`` (within :data:`ACTIVE_TOL`):

        .. math:: \|P_{T}(-g_k)\|, \qquad
                  T = \{N_{k-1} z : a_i^\top N_{k-1} z \le 0,\ i \in \mathcal{A}\},

        the projection onto the tangent cone, through its dual, a non-negative
        least-squares problem (Lawson & Hanson's NNLS, ``scipy.optimize.nnls``). Zero is the
        first-order (KKT) condition of level :math:`k` subject to the higher levels and the
        limits (Nocedal & Wright, Theorem 12.1).

        Args:
            q: The configuration (``robot.nq``,).
            dt: Passed to velocity limits.

        Returns:
            One value per optimised level (empty when there is none).
        """
        return [float(np.linalg.norm(d)) for d, _ in self._projected_gradients(q, dt)]

    def descent_steps(
        self, q: NDArray[np.float64], dt: float | None = None
    ) -> list[NDArray[np.float64]]:
        r"""Per optimised level, its projected steepest-descent (Cauchy) step at ``q``.

        :math:`d_k = N_{k-1} P_T(-N_{k-1}^\top g_k)` (the projection of :meth:`stationarity`)
        scaled to the minimiser of the level's quadratic model along it,
        :math:`t = \|d_k\|^2 / d_k^\top H_k d_k` (Rosen's gradient projection; Nocedal &
        Wright §16.7): a descent direction of level :math:`k` that keeps the levels above
        optimal to first order and the active limits, computed without a QP back-end.

        Args:
            q: The configuration (``robot.nq``,).
            dt: Passed to velocity limits.

        Returns:
            One step (``robot.dof``,) per optimised level.
        """
        steps = []
        for d, H in self._projected_gradients(q, dt):
            curvature = float(d @ H @ d)
            steps.append(d * (float(d @ d) / curvature) if curvature > 0.0 else d)
        return steps

    def _projected_gradients(
        self, q: NDArray[np.float64], dt: float | None
    ) -> list[tuple[NDArray[np.float64], NDArray[np.float64]]]:
        """``(d_k, H_k)`` per optimised level.

        The projected steepest-descent direction (:meth:`stationarity`'s projection, in ``Δq``) and
        the level's Hessian.
        """
        q = self.robot.check_q(q, "q")
        _check_dt(dt)
        self._goto(q)
        objectives = self._assembly.objectives(self._state, self._configuration)
        start = 1 if self.has_targets else 0
        if start == len(objectives):
            return []
        N = self._level0_kernel(objectives) if start else np.eye(self.robot.dof)
        active = self._active_rows(q, dt)
        ranked = self._ranked_active(q, dt)
        found = []
        for level in range(start, len(objectives)):
            H_k, c_k = objectives[level]
            rows = active + [G for index, G in ranked if index <= level]
            found.append((N @ _projected_descent(c_k, N, rows), H_k.copy()))
            if level < len(objectives) - 1 and N.shape[1]:
                N = N @ kernel_directions(N.T @ H_k @ N, self.rank_tol, self.damping)
        return found

    def objective_values(self, q: NDArray[np.float64]) -> list[float]:
        """Per optimised level (see :meth:`stationarity`), the value its tasks descend at ``q``.

        ``½‖W e‖²`` per residual task, mink's ``½‖cost ⊙ e‖²`` per mink task,
        ``−mean(cost²) w`` per :class:`~redik.tasks.ManipulabilityTask`
        (:meth:`~redik.tasks.task.Task.value`): what a driver compares to accept a step on
        the lower levels.

        Args:
            q: The configuration (``robot.nq``,).

        Returns:
            One value per optimised level.
        """
        self._goto(q)
        start = 1 if self.has_targets else 0
        return [
            level.value(self._state, self._configuration) for level in self._assembly.levels[start:]
        ]

    def feasible(self, q: NDArray[np.float64]) -> bool:
        """Whether ``q`` meets every inequality limit no task outranks (``h ≥ 0`` at ``Δq = 0``).

        A collision distance below its minimum, a ball joint outside its cone: a driver's
        steps keep the feasibility of their start, so an infeasible start can only end
        infeasible. The limits are the hard ones and those ranked above every task.

        Args:
            q: The configuration (``robot.nq``,).

        Returns:
            True without such limits.
        """
        if not self._admitting:
            return True
        self._goto(q)
        for limit in self._admitting:
            block = limit.inequalities(self._configuration, None)
            if block is not None and block[1].size and block[1].min() < -FEASIBILITY_TOL:
                return False
        return True

    def integrate(self, q: NDArray[np.float64], dq: NDArray[np.float64]) -> NDArray[np.float64]:
        """``q ⊕ Δq`` (``robot.integrate``), full-turn joints of periodic limits turned back.

        Args:
            q: The configuration (``robot.nq``,).
            dq: A step (``robot.dof``,).

        Returns:
            The new configuration.
        """
        return self._wrapped(self.robot.integrate(q, dq))

    def clip(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """``q`` into the joint limits a hard :class:`~redik.limits.ConfigurationLimit` holds.

        Args:
            q: The configuration (``robot.nq``,).

        Returns:
            ``q`` itself without such a limit, else a clipped (and wrapped) copy.
        """
        return self.robot.clip(self._wrapped(q)) if self._clip else q

    @property
    def limited(self) -> bool:
        """Whether a hard :class:`~redik.limits.ConfigurationLimit` holds the joint ranges."""
        return self._clip

    # ----------------------------------------------------------------------------------
    # The stages of a step

    def _update(self, q: NDArray[np.float64]) -> None:
        """Forward kinematics at ``q`` (and the mink configuration, when one is kept)."""
        self._state.update(q)
        if self._configuration is not None:
            self._configuration.update(self.robot.state.data.qpos)

    def _goto(self, q: NDArray[np.float64]) -> None:
        """:meth:`_update`, skipped when the state is at ``q`` already.

        A driver asks several questions at one configuration. The robot's whole ``qpos`` is compared
        too, so a forward kinematics run elsewhere on the robot's data (``robot.fk``) is noticed.
        """
        # Bytes compare in a fraction of np.array_equal's time; equal bytes are equal values.
        qpos = self.robot.state.data.qpos
        if q.tobytes() != self._at[0] or qpos.tobytes() != self._at[1]:
            self._update(q)
            self._at = (q.tobytes(), qpos.tobytes())

    def _solve_step(
        self,
        q: NDArray[np.float64],
        dt: float | None,
        *,
        motion: bool = False,
        lm_damping: float = 0.0,
        error_damping: float = 0.0,
        second_order: bool = False,
        max_step: float | None = None,
    ) -> NDArray[np.float64]:
        """The step at the current state (``q``): assemble, bound, solve, clip."""
        objectives = self._assembly.objectives(self._state, self._configuration)
        damping = self._level0_damping(lm_damping, error_damping)
        lb, ub = self._bounds(q, dt, motion, max_step)
        C, low, up = self._inequality_rows(dt)
        curvature = self._curvature(q, dt, objectives) if second_order else None
        dq = solve_lexicographic(
            objectives,
            self.backends,
            lb,
            ub,
            C,
            low,
            up,
            damping=damping,
            rank_tol=self.rank_tol,
            stats=self.stats,
            rows0=self._rows0,
            rhs0=self._rhs0,
            curvature1=curvature,
            ranked=self._ranked_groups(q, dt, motion),
        )
        if self._clip:
            # Into the (shrunk) box the solver was given: inside the limits, whatever its
            # tolerance.
            np.clip(dq, lb, ub, out=dq)
        return dq

    def _level0_damping(self, lm_damping: float, error_damping: float) -> float | list[float]:
        """The ``ε`` of each level; a Levenberg–Marquardt ``λ`` is added to level 0's Hessian."""
        if error_damping > 0.0:
            b0 = self._rhs0  # level 0's weighted residual rows, just built
            lm_damping += error_damping * float(b0 @ b0)
        if lm_damping <= 0.0:
            return self.damping
        self._assembly.levels[0].add_to_diagonal(lm_damping)
        return [self.damping + lm_damping] + [self.damping] * (len(self.levels) - 1)

    def _bounds(
        self, q: NDArray[np.float64], dt: float | None, motion: bool, max_step: float | None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | tuple[None, None]:
        """The box on ``Δq`` (None, None without one)."""
        boxes = self._boxes if motion else self._static_boxes
        if not boxes and max_step is None:
            return None, None
        lb, ub = self._lb, self._ub
        if boxes:
            q_box = self.robot.scalar_values(q)
            boxes[0].set_bounds(q_box, dt, lb, ub)
            for limit in boxes[1:]:
                limit.bounds_into(q_box, dt, lb, ub)
            if len(boxes) > 1 and (lb > ub).any():  # one position box is never empty
                self._raise_empty_box(q_box, dt)
        else:
            lb.fill(-np.inf)
            ub.fill(np.inf)
        if max_step is not None:
            np.maximum(lb, -max_step, out=lb)
            np.minimum(ub, max_step, out=ub)
        return lb, ub

    def _raise_empty_box(self, q_box: NDArray[np.float64], dt: float | None) -> None:
        bad = np.flatnonzero(self._lb > self._ub)
        names = [self.robot.dof_names[i] for i in bad]
        raise InfeasibleProblem(
            f"the limits admit no step for joints {names}: lower bounds "
            f"{self._lb[bad].tolist()} exceed upper bounds {self._ub[bad].tolist()} at q = "
            f"{q_box[bad].tolist()} (dt = {dt})"
        )

    def _inequality_rows(
        self, dt: float | None
    ) -> (
        tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]
        | tuple[None, None, None]
    ):
        """The hard rows ``C Δq ≤ u`` at the current state (None, None, None without)."""
        if not self._rows:
            return None, None, None
        evaluated = [limit.inequalities(self._configuration, dt) for limit in self._rows]
        blocks = [block for block in evaluated if block is not None]
        if not blocks:
            return None, None, None
        up = np.concatenate([h for _, h in blocks])
        return np.vstack([G for G, _ in blocks]), np.full_like(up, -np.inf), up

    def _ranked_groups(
        self, q: NDArray[np.float64], dt: float | None, motion: bool
    ) -> list[tuple[int, NDArray[np.float64], NDArray[np.float64], Backend]]:
        """``(k, G, h, backend)`` of every ranked group with rows at the current state."""
        groups = []
        for _, index, limits, backend in self._ranked:
            G, h = self._ranked_rows(limits, q, dt, motion)
            if G is not None and h is not None:
                groups.append((index, G, h, backend))
        return groups

    def _ranked_rows(
        self, limits: list[Limit], q: NDArray[np.float64], dt: float | None, motion: bool = False
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | tuple[None, None]:
        """``(G, h)`` of ranked ``limits`` at the current state.

        ``(G, h)`` of ranked ``limits`` at the current state, boxes as ``±Δq_i`` rows of their
        finite bounds; ``(None, None)`` when none is active. Acceleration limits count only in a
        ``motion``.
        """
        evaluated = []
        for limit in limits:
            if isinstance(limit, AccelerationLimit) and not motion:
                continue
            if isinstance(limit, BoxLimit):
                evaluated.append(_box_rows(limit, self.robot.scalar_values(q), dt))
            elif isinstance(limit, InequalityLimit):
                evaluated.append(limit.inequalities(self._configuration, dt))
        blocks = [block for block in evaluated if block is not None]
        if not blocks:
            return None, None
        return np.vstack([G for G, _ in blocks]), np.concatenate([h for _, h in blocks])

    # ----------------------------------------------------------------------------------
    # Level 0's targets, its null space and the curvature of its optimal set

    def _error_and_jacobian(
        self, task: BaseTask
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """A target's error and Jacobian (over ``robot.dof``) at the current state."""
        buffers = self._target_buffers.get(id(task))
        if buffers is not None and isinstance(task, ResidualTask):
            e, J = buffers
            task.residual_into(self._state, e, J)
            return e, J
        configuration = self._configuration
        e = np.atleast_1d(foreign_call(task, "compute_error", configuration))
        J = np.atleast_2d(foreign_call(task, "compute_jacobian", configuration))
        return e, J[:, self.robot.dof_indices]

    def _weighted_error(self, task: BaseTask) -> NDArray[np.float64]:
        """``W e`` of a target at the current state.

        ``W e`` of a target at the current state (mink's ``W = diag(cost)``: a component of zero
        cost, the height of a ``ComTask``, is no part of its target).
        """
        buffers = self._target_buffers.get(id(task))
        if buffers is not None and isinstance(task, ResidualTask):
            e = buffers[0]
            task.error_into(self._state, e)
        else:
            e = np.atleast_1d(foreign_call(task, "compute_error", self._configuration))
        weighted: NDArray[np.float64] = _cost(task) * e
        return weighted

    def _level0_kernel(
        self, objectives: Sequence[tuple[NDArray[np.float64], NDArray[np.float64]]]
    ) -> NDArray[np.float64]:
        """Orthonormal basis of level 0's null space at the current state."""
        N = None if self._rows0 is None else row_null_space(self._rows0, self.rank_tol)
        if N is None:
            N = kernel_directions(objectives[0][0], self.rank_tol, self.damping)
        return N

    def _curvature(
        self,
        q: NDArray[np.float64],
        dt: float | None,
        objectives: Sequence[tuple[NDArray[np.float64], NDArray[np.float64]]],
    ) -> Curvature | None:
        """Level 1's curvature term ``N ↦ NᵀMN`` at ``q``, or None where it does not apply.

        Level 1's curvature term ``N ↦ NᵀMN`` at ``q``, or None where it does not apply (not a
        least-squares level 0, or a single level).
        """
        if self._rows0 is None or len(objectives) < 2:
            return None
        c1 = objectives[1][1].copy()  # level 1's gradient at q, before anything moves
        lb, ub = self.step_bounds(q, dt)
        active = (lb >= -ACTIVE_TOL) | (ub <= ACTIVE_TOL)
        return lambda N: self._level1_curvature(q, c1, N, active)

    def _level1_curvature(
        self,
        q: NDArray[np.float64],
        c1: NDArray[np.float64],
        N: NDArray[np.float64],
        active: NDArray[np.bool_],
    ) -> NDArray[np.float64]:
        r"""``NᵀMN``, :math:`M = \sum_i λ_i ∇^2 r_i`, with the bounds ``active`` at ``q``.

        :math:`MN` is the derivative of :math:`A^\top λ` along each column of :math:`N`, by a
        forward difference of level 0's rows at :math:`q ⊕ hN_j` (one forward kinematics
        each; :math:`h` = :data:`~redik.qp.curvature.CURVATURE_STEP`); the multipliers and
        the face come from :func:`~redik.qp.curvature.bound_multipliers` and
        :func:`~redik.qp.curvature.on_free_face`. The state is back at ``q`` on return.
        """
        level0 = self._assembly.levels[0]
        A = level0.A  # the rows at q, built by the step that calls this
        multipliers = bound_multipliers(A, c1, active)
        gradient = A.T @ multipliers
        rows, rhs = self._curvature_rows, self._curvature_rhs
        MN = np.empty_like(N)
        for j in range(N.shape[1]):
            self._state.update(self.robot.integrate(q, CURVATURE_STEP * N[:, j]))
            level0.weighted_rows_into(self._state, rows, rhs)
            MN[:, j] = (rows.T @ multipliers - gradient) / CURVATURE_STEP
        self._state.update(q)
        M = N.T @ MN
        return on_free_face(0.5 * (M + M.T), N, active)

    # ----------------------------------------------------------------------------------
    # Active limits of the stationarity test

    def _active_rows(self, q: NDArray[np.float64], dt: float | None) -> list[NDArray[np.float64]]:
        """The hard limits active at ``q`` as rows ``a_i`` of ``a_i·Δq ≤ 0``."""
        active = []
        if self._static_boxes:
            lb, ub = self.step_bounds(q, dt)
            at_lower, at_upper = lb >= -ACTIVE_TOL, ub <= ACTIVE_TOL
            if at_lower.any() or at_upper.any():
                eye = np.eye(self.robot.dof)
                active += [-eye[at_lower], eye[at_upper]]
        for limit in self._rows:
            block = limit.inequalities(self._configuration, dt)
            if block is not None:
                G, h = block
                active.append(G[h <= ACTIVE_TOL])
        return active

    def _ranked_active(
        self, q: NDArray[np.float64], dt: float | None
    ) -> list[tuple[int, NDArray[np.float64]]]:
        """Ranked rows active at ``q``, each with the first level it binds.

        Ranked rows active at ``q`` with the index of the first level they bind (violated rows count
        as active: their bound is then the least violation the levels above left).
        """
        found = []
        for _, index, limits, _ in self._ranked:
            G, h = self._ranked_rows(limits, q, dt)
            if G is not None and h is not None:
                found.append((index, G[h <= ACTIVE_TOL]))
        return found

    def _wrapped(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """``q`` with the full-turn joints of periodic position limits turned into range."""
        for limit in self._wraps:
            q = limit.wrap(q)
        return q

    def __repr__(self) -> str:
        names = [type(task).__name__ for task in self.tasks]
        return (
            f"Problem({self.robot!r}, tasks={names}, levels={self.levels}, "
            f"backend={self.backends[0].name!r})"
        )


def _box_rows(
    limit: BoxLimit, q_box: NDArray[np.float64], dt: float | None
) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """A box limit's finite bounds as rows ``±Δq_i ≤ h``."""
    n = q_box.shape[0]
    lower, upper = np.full(n, -np.inf), np.full(n, np.inf)
    limit.bounds_into(q_box, dt, lower, upper)
    up, low = np.isfinite(upper), np.isfinite(lower)
    if not (up.any() or low.any()):
        return None
    eye = np.eye(n)
    return np.vstack([eye[up], -eye[low]]), np.concatenate([upper[up], -lower[low]])


def _projected_descent(
    c: NDArray[np.float64], N: NDArray[np.float64], active: list[NDArray[np.float64]]
) -> NDArray[np.float64]:
    """``P_T(−g)`` of :meth:`Problem.stationarity` for one level.

    ``P_T(−g)`` of :meth:`Problem.stationarity` for one level, in the coordinates of ``N`` (``g =
    Nᵀc``; empty without free direction).
    """
    g: NDArray[np.float64] = c @ N
    if N.shape[1] == 0:
        return g
    rows = np.vstack(active) @ N if active else np.empty((0, N.shape[1]))
    if rows.shape[0] == 0:
        return -g
    # P_T(−g) = argmin_{z: rows z ≤ 0} ½‖z + g‖² = −(g + rowsᵀλ) with λ the non-negative
    # least-squares solution of rowsᵀλ ≈ −g (its dual).
    multipliers, _ = nnls(rows.T, -g)
    descent: NDArray[np.float64] = -(g + rows.T @ multipliers)
    return descent
