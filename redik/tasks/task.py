r"""The task contract: what a task asks of the joint step ``Δq`` in one QP.

Every task contributes a convex quadratic to the objective of its priority level,

.. math::

    \tfrac12 \Delta q^\top H \Delta q + c^\top \Delta q ,

and the tasks of one level are summed (:mod:`redik.qp.assembly`). Most tasks are
**residual tasks** (:class:`ResidualTask`): a task error :math:`e(q) \in \mathbb{R}^k` with
Jacobian :math:`J(q) = \partial e / \partial q` (``k × n``), a cost :math:`w` (weight
matrix :math:`W = \mathrm{diag}(w)`) and a gain :math:`\alpha \in [0, 1]`, entering as the
first-order task
dynamics :math:`J \Delta q = -\alpha e` in the least-squares sense:

.. math::

    \tfrac12 \| W (J \Delta q + \alpha e) \|^2
    \quad\Longrightarrow\quad
    H = J^\top W^2 J, \qquad c = \alpha J^\top W^2 e .

This is mink's task protocol (``mink.Task``: ``compute_error``, ``compute_jacobian``,
``cost`` = :math:`w`, ``gain``), so a redik task can be handed to ``mink.solve_ik`` and a
mink task to :class:`redik.Problem`. Costs multiply the residual, as mink's do: the
objective scales with :math:`w^2`. A cost is a scalar or one value per error component
(``cost=``, or ``position_cost=`` and ``orientation_cost=`` on a
:class:`~redik.tasks.FrameTask`; :meth:`ResidualTask.set_cost`).

Tasks that are not least squares (:class:`ManipulabilityTask`) implement
:meth:`Task.add_objective` directly.

A task names frames, not ids; :meth:`Task.bind` resolves them against a
:class:`redik.Robot` (a :class:`redik.Problem` binds its tasks). Errors and Jacobians follow
:mod:`redik.core.conventions`.
"""

from __future__ import annotations

import abc
from typing import TYPE_CHECKING

import numpy as np
from mink.tasks import BaseTask, Objective
from mink.tasks import Task as MinkTask
from numpy.typing import ArrayLike, NDArray

from redik.core.exceptions import InvalidInput
from redik.core.validate import integer, non_negative, real_array
from redik.kinematics.robot import Robot
from redik.tasks.kinematics import KinematicState

if TYPE_CHECKING:
    from mink import Configuration

MAX_COST = 1e6
"""Largest task cost accepted. A cost enters the Hessian squared: beyond ``1e6`` (``w² =
1e12``) a cost-1 task beside it is within a few digits of double precision's rounding
(``ε ≈ 2.2e-16``), and the Hessian's condition number is past what the active-set back-ends'
factorisations hold. Strict precedence is what priorities are for."""


def as_cost(cost: object, size: int, name: str) -> NDArray[np.float64]:
    """A finite cost in ``[0, MAX_COST]``, scalar or per component, as a (``size``,) array."""
    array = np.atleast_1d(real_array(cost, name))
    if array.ndim != 1 or array.shape[0] not in (1, size):
        raise InvalidInput(f"{name} must be a scalar or have shape ({size},), got {array.shape}")
    if not np.all((array >= 0.0) & (array <= MAX_COST)):  # NaN fails too
        raise InvalidInput(f"{name} must be in [0, {MAX_COST:g}], got {array.tolist()}")
    return np.broadcast_to(array, (size,)).copy()


def as_gain(gain: float) -> float:
    """A task gain in [0, 1] (1 = dead-beat, smaller = low-pass)."""
    if isinstance(gain, bool) or not isinstance(gain, int | float | np.integer | np.floating):
        raise InvalidInput(f"gain must be a number in [0, 1], got {gain!r}")
    if not 0.0 <= gain <= 1.0:
        raise InvalidInput(f"gain must be in [0, 1], got {gain}")
    return float(gain)


def as_priority(priority: int) -> int:
    """A priority level: an integer >= 0, 0 being the highest."""
    return integer(priority, "priority (0 is highest)")


class Task(BaseTask):
    """Base class of redik tasks: a priority, a robot binding and a QP contribution.

    Attributes:
        priority: Level in the hierarchy, 0 (highest) first. Tasks of equal priority are
            weighted by their costs and summed; a lower level never degrades a higher one.
        robot: The robot the task is bound to, or None before :meth:`bind`.
    """

    def __init__(self, priority: int = 0):
        self.priority = as_priority(priority)
        self.robot: Robot | None = None

    def bind(self, robot: Robot) -> Task:
        """Resolve frames and sizes against ``robot``; returns the task. Subclasses extend it."""
        self.robot = robot
        return self

    def reset(self, velocity: NDArray[np.float64] | None = None) -> None:
        """Forget what earlier steps of a :class:`redik.Problem` left in the task.

        The next step starts a new motion with joint velocity ``velocity`` (``robot.dof``,; None: at
        rest).

        Called by :meth:`redik.Problem.reset` at the start of each run of a loop driver
        (:func:`redik.apps.sim.simulate`). The target (``set_target``) is the caller's and
        is kept. redik's tasks are memoryless: their objective is a function of ``q`` and
        the target alone, so this default does nothing; a task with memory (a filtered
        target, an integral term) overrides it.
        """

    def _require_robot(self) -> Robot:
        if self.robot is None:
            raise InvalidInput(
                f"{type(self).__name__} is not bound to a robot: call task.bind(robot) before "
                "using it outside a redik.Problem (e.g. in mink.solve_ik)"
            )
        return self.robot

    def _state(self, configuration: Configuration) -> KinematicState:
        return KinematicState.for_configuration(self._require_robot(), configuration)

    @abc.abstractmethod
    def add_objective(
        self, state: KinematicState, H: NDArray[np.float64], c: NDArray[np.float64]
    ) -> None:
        """Add this task's ``(H, c)`` (``n × n``, ``n``) at ``state`` into ``H`` and ``c``."""

    def objective_value(self, state: KinematicState) -> float:
        """The value the task descends at ``state``, whose gradient its ``c`` follows.

        A driver compares it between two configurations to accept a step on a lower level
        (:func:`redik.solve_problem`). This default, 0, suits a task without one: its level
        is then judged by its projected gradient alone.
        """
        return 0.0

    def compute_qp_objective(self, configuration: Configuration) -> Objective:
        """The pair ``(H, c)`` over the model's ``nv`` velocity columns (mink's protocol)."""
        state = self._state(configuration)
        H = np.zeros((state.n_columns, state.n_columns))
        c = np.zeros(state.n_columns)
        self.add_objective(state, H, c)
        return Objective(H, c)


class ResidualTask(Task, MinkTask):
    r"""A task with an error :math:`e(q)` (``k``,) and its Jacobian :math:`J = ∂e/∂q`.

    Subclasses implement :meth:`residual_into` (error and Jacobian into buffers); the
    weighted least-squares objective of the module docstring follows.

    Attributes:
        k: Dimension of the error.
        cost: The cost :math:`w` (``k``,), the attribute mink reads too.
        gain: The gain :math:`α`.
        lm_damping: mink's Levenberg–Marquardt scale :math:`λ ≥ 0` (0 for most tasks): the
            task adds :math:`μ I` to its Hessian, :math:`μ = λ \|α W e\|^2`, which grows
            with the error and so damps the step towards an infeasible target (mink's
            ``Task``). Fixed at construction; a task with :math:`λ > 0` is assembled by its
            own :meth:`add_objective`.
        version: Incremented whenever the cost, gain or target changes.
    """

    k: int

    def __init__(
        self,
        cost: ArrayLike,
        gain: float,
        priority: int,
        size: int | None = None,
        *,
        lm_damping: float = 0.0,
    ):
        Task.__init__(self, priority)
        self.version = 0
        self.gain = gain
        self._lm_damping = non_negative(lm_damping, "lm_damping")
        self._cost_spec = cost
        self.cost = np.empty(0)
        if size is not None:
            self._set_size(size)

    @property
    def lm_damping(self) -> float:
        """The Levenberg–Marquardt scale ``λ`` of mink (read-only: see the class docstring)."""
        return self._lm_damping

    @lm_damping.setter
    def lm_damping(self, value: float) -> None:
        raise InvalidInput(
            f"{type(self).__name__}.lm_damping is fixed at construction (a task with λ > 0 "
            f"assembles its own objective); got {value!r}: build a new task"
        )

    @property
    def gain(self) -> float:
        """The gain ``α ∈ [0, 1]``."""
        return self._gain

    @gain.setter
    def gain(self, gain: float) -> None:
        self._gain = as_gain(gain)
        self.version += 1

    def _set_size(self, size: int) -> None:
        self.k = size
        self.cost = as_cost(self._cost_spec, size, f"{type(self).__name__} cost")
        self.version += 1

    def set_cost(self, cost: ArrayLike) -> None:
        """Replace the cost (scalar or per component).

        Use it rather than editing ``cost`` in place: cached products are refreshed through
        :attr:`version`.
        """
        self.cost[:] = as_cost(cost, self.k, f"{type(self).__name__} cost")
        self.version += 1

    @abc.abstractmethod
    def residual_into(
        self, state: KinematicState, e: NDArray[np.float64], J: NDArray[np.float64]
    ) -> None:
        """Write the error (``k``,) into ``e`` and its Jacobian (``k × n``) into ``J``."""

    def error_into(self, state: KinematicState, e: NDArray[np.float64]) -> None:
        """Write the error (``k``,) alone into ``e`` (a subclass skips the Jacobian if it can)."""
        J = getattr(self, "_error_scratch", None)
        if J is None or J.shape[1] != state.n_columns:
            J = self._error_scratch = np.empty((self.k, state.n_columns))
        self.residual_into(state, e, J)

    def weighted_residual_into(
        self, state: KinematicState, A: NDArray[np.float64], b: NDArray[np.float64]
    ) -> None:
        """Write ``A = W J`` and ``b = −α W e``, the rows of ``½‖A Δq − b‖²`` (hot path)."""
        self.residual_into(state, b, A)
        A *= self.cost[:, None]
        b *= self.cost
        b *= -self.gain

    def add_objective(
        self, state: KinematicState, H: NDArray[np.float64], c: NDArray[np.float64]
    ) -> None:
        """Add this task's ``(H, c)`` at ``state`` into ``H`` and ``c``."""
        A = np.empty((self.k, state.n_columns))
        b = np.empty(self.k)
        self.weighted_residual_into(state, A, b)
        H += A.T @ A
        c -= A.T @ b
        if self._lm_damping > 0.0:
            H.flat[:: H.shape[0] + 1] += self._lm_damping * float(b @ b)

    def objective_value(self, state: KinematicState) -> float:
        """``½‖W e‖²`` at ``state``; the objective's gradient at ``Δq = 0`` is ``α`` times its."""
        e, _ = self.error_and_jacobian(state)
        weighted = self.cost * e
        return 0.5 * float(weighted @ weighted)

    def error_and_jacobian(
        self, state: KinematicState
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Fresh arrays ``(e, J)`` at ``state``."""
        e = np.empty(self.k)
        J = np.empty((self.k, state.n_columns))
        self.residual_into(state, e, J)
        return e, J

    def compute_error(self, configuration: Configuration) -> NDArray[np.float64]:
        """The error :math:`e(q)` at a ``mink.Configuration`` (mink's protocol)."""
        return self.error_and_jacobian(self._state(configuration))[0]

    def compute_jacobian(self, configuration: Configuration) -> NDArray[np.float64]:
        """The Jacobian :math:`J(q)` over the model's ``nv`` columns (mink's protocol)."""
        return self.error_and_jacobian(self._state(configuration))[1]

    def compute_qp_objective(self, configuration: Configuration) -> Objective:
        """The pair ``(H, c)`` over the model's ``nv`` columns (mink's protocol)."""
        return Task.compute_qp_objective(self, configuration)

    def compute_qp_residual(
        self, configuration: Configuration
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
        """The weighted residual mink stacks, ``(W J, −α W e, μ)`` (mink's protocol).

        mink protocol: ``(W J, −α W e, μ)``, the weighted residual mink stacks and its
        Levenberg–Marquardt term ``μ = λ ‖α W e‖²``.
        """
        state = self._state(configuration)
        A = np.empty((self.k, state.n_columns))
        b = np.empty(self.k)
        self.weighted_residual_into(state, A, b)
        return A, b, self._lm_damping * float(b @ b)
