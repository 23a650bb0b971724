r"""Assembly: tasks and limits → one QP per priority level, in preallocated buffers.

At the chain configuration :math:`q` redik computes the joint step :math:`Δq` from

.. math::

    \begin{aligned}
    \min_{Δq}\;& \tfrac12 Δq^\top H Δq + c^\top Δq \\
    \text{s.t.}\;& G Δq \le h, \qquad A Δq = b
    \end{aligned}

**Objective.** Tasks of equal priority are weighted and summed. A residual task
:math:`i` (:mod:`redik.tasks.task`) contributes :math:`\tfrac12 \|W_i (J_i Δq + α_i e_i)\|^2`;
stacking :math:`\mathcal{A} = [W_i J_i]_i` and :math:`\mathcal{b} = [-α_i W_i e_i]_i`
gives :math:`H = \mathcal{A}^\top \mathcal{A}` and :math:`c = -\mathcal{A}^\top
\mathcal{b}` in one product per level; joint-space tasks (posture, joint-limit avoidance,
damping) add a diagonal, and other tasks their own :math:`(H_i, c_i)`. Each level's
Hessian is regularised by :math:`εI` (``damping``). With several levels
the priorities are strict (:mod:`redik.qp.hierarchy`); with one, this is mink's
``solve_ik`` objective.

**Constraints.** :math:`G Δq \le h` collects the limits (:mod:`redik.limits.limit`):
box limits intersected into bounds :math:`l_b \le Δq \le u_b`, general rows as given.
:math:`A Δq = b` carries the optimal sets of the higher levels when priorities are
strict — redik expresses them by the equivalent null-space parameterisation.

Kinematics are computed once per step (:class:`~redik.tasks.kinematics.KinematicState`);
all per-level arrays are allocated once, when the problem is built.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from mink.tasks import BaseTask
from numpy.typing import NDArray

from redik.kinematics.robot import Robot
from redik.tasks.foreign import foreign_call
from redik.tasks.joint_space_task import JointSpaceTask
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import ResidualTask, Task

if TYPE_CHECKING:
    from mink import Configuration


def task_priority(task: BaseTask) -> int:
    """A task's priority level; mink tasks, which have none, are level 0."""
    return int(getattr(task, "priority", 0))


class LevelAssembly:
    """The objective buffers of one priority level.

    Attributes:
        priority: The level's priority value.
        residual_tasks: The redik residual tasks, their rows stacked in ``A``, ``b``.
        joint_tasks: The joint-space tasks, added as a diagonal
            (:mod:`redik.tasks.joint_space_task`).
        other_tasks: redik tasks with their own objective, and mink tasks.
        A, b: The stacked weighted residual rows.
        flat: The robot's ``flat`` (``q ⊖ r = q − r``: a joint-space task's gradient is then
            one fused product for the level).
        H, c: The level's objective, rebuilt by :meth:`build`.
    """

    def __init__(
        self, priority: int, tasks: Sequence[BaseTask], n: int, damping: float, flat: bool
    ) -> None:
        self.priority = priority
        self.damping = damping
        self.flat = flat
        self.residual_tasks: list[ResidualTask] = []
        self.joint_tasks: list[JointSpaceTask] = []
        self.other_tasks: list[BaseTask] = []
        rows: list[int] = []
        for task in tasks:
            if isinstance(task, JointSpaceTask):
                self.joint_tasks.append(task)
            elif isinstance(task, ResidualTask) and not task.lm_damping:
                # (A task with mink's lm_damping adds μI to H itself: an "other" task.)
                self.residual_tasks.append(task)
                rows.append(task.k)
            else:
                self.other_tasks.append(task)
        self.A = np.zeros((sum(rows), n))
        self.b = np.zeros(sum(rows))
        offsets = np.concatenate([[0], np.cumsum(rows)]).astype(int)
        self._blocks = [
            (task, self.A[start:stop], self.b[start:stop])
            for task, start, stop in zip(
                self.residual_tasks, offsets[:-1], offsets[1:], strict=True
            )
        ]
        self.H = np.zeros((n, n))
        self.c = np.zeros(n)
        self._diagonal = self.H.reshape(n * n)[:: n + 1]  # a view: H's diagonal
        self._joint_versions: list[tuple[int, int]] = []
        self._joint_ready = False
        # The version of the joint-space sums H's diagonal was last filled from (-1: H was
        # changed since, e.g. by a damping term, and must be refilled).
        self._terms_version = 0
        self._hessian_version = -1
        # The joint-space sums (ε + Σw²d², Σαw²d², Σαw²d² ⊙ r), rows of one array.
        self._joint_terms = np.zeros((3, n))
        self._joint_hessian, self._joint_factor, self._joint_offset = self._joint_terms
        self._joint_hessian[:] = damping
        self._joint_buffer = np.zeros(n)
        self._joint_factors: list[tuple[JointSpaceTask, NDArray[np.float64]]] = []
        self.least_squares = not self.joint_tasks and not self.other_tasks
        """True when ``H = AᵀA + εI``: ``A`` then factors the level (its null space)."""

    @property
    def tasks(self) -> list[BaseTask]:
        """Every task of the level."""
        return self.residual_tasks + self.joint_tasks + self.other_tasks

    def _refresh_joint_terms(self) -> None:
        """Re-sum the joint-space terms when a task's target, cost or gain changed.

        The sums are the tasks' ``w²d²`` (+ damping), ``α w²d²`` and, on a flat robot,
        ``α w²d² r`` (else each task's ``α w²d²``, kept for :meth:`_joint_gradient`); each
        re-sum bumps the level's terms version, which :meth:`build` compares with the one
        ``H`` was filled from.
        """
        versions = [(id(task), task.version) for task in self.joint_tasks]
        if versions == self._joint_versions and self._joint_ready:
            return
        self._joint_hessian[:] = self.damping
        self._joint_factor[:] = 0.0
        self._joint_offset[:] = 0.0
        self._joint_factors.clear()
        for task in self.joint_tasks:
            hessian, factor = task.diagonal_terms()
            self._joint_hessian += hessian
            self._joint_factor += factor
            if self.flat:
                self._joint_offset += factor * task.reference
            elif factor.any():
                self._joint_factors.append((task, factor))
        self._joint_versions = versions
        self._joint_ready = True
        self._terms_version += 1

    def joint_terms(self) -> NDArray[np.float64]:
        """The joint-space sums, refreshed when a task's target, cost or gain changed.

        Returns:
            The level's own array (3 × n), rows ``ε + Σ w²d²`` (the Hessian's diagonal),
            ``Σ α w²d²`` and, on a flat robot, ``Σ α w²d² ⊙ r``: the gradient is then
            ``Σ α w²d² ⊙ q − Σ α w²d² ⊙ r`` (else :meth:`joint_gradient_into`).
        """
        self._refresh_joint_terms()
        return self._joint_terms

    def joint_differences(self) -> list[tuple[NDArray[np.float64], NDArray[np.float64]]]:
        """On a robot that is not flat, each joint-space task's ``(r, α w²d²)`` (refreshed).

        The gradient is then ``Σ α w²d² ⊙ (q ⊖ r)`` over them (:meth:`joint_gradient_into`);
        tasks whose factor is zero are left out.
        """
        self._refresh_joint_terms()
        return [(task.reference, factor) for task, factor in self._joint_factors]

    def joint_gradient_into(self, state: KinematicState, c: NDArray[np.float64]) -> None:
        """Write the joint-space tasks' gradient ``Σ α w²d² ⊙ (q ⊖ r)`` at ``state`` into ``c``.

        Args:
            state: The kinematic state (its ``q``).
            c: Written (n,).
        """
        self._joint_gradient(state, c, fresh=True)

    def build(
        self,
        state: KinematicState,
        configuration: Configuration | None,
        columns: NDArray[np.intp],
    ) -> None:
        """Fill ``H`` (regularised by ``damping``) and ``c`` at ``state``.

        ``configuration`` is the ``mink.Configuration`` mink tasks read (else None).
        """
        H, c = self.H, self.c
        self._refresh_joint_terms()
        if self._blocks:
            for task, A, b in self._blocks:
                task.weighted_residual_into(state, A, b)
            At = self.A.T
            np.dot(At, self.A, out=H)
            np.dot(At, self.b, out=c)
            np.negative(c, out=c)
            self._diagonal += self._joint_hessian
            self._joint_gradient(state, c, fresh=False)
        else:
            # No residual rows: H is the diagonal alone, which does not depend on q —
            # refilled only when the sums changed or H was (a posture level then costs two
            # vector operations).
            if self._hessian_version != self._terms_version or self.other_tasks:
                H.fill(0.0)
                self._diagonal += self._joint_hessian
                self._hessian_version = self._terms_version
            self._joint_gradient(state, c, fresh=True)
        self._add_other_tasks(state, configuration, columns)

    def add_to_diagonal(self, value: float) -> None:
        """Add ``value`` to the diagonal of ``H`` until the next :meth:`build`.

        Add ``value`` to the diagonal of ``H`` (a Levenberg–Marquardt term) until the next
        :meth:`build`, which refills it.
        """
        self._diagonal += value
        self._hessian_version = -1

    def value(self, state: KinematicState, configuration: Configuration | None) -> float:
        """The value the level's tasks descend at ``state``.

        The sum of their :meth:`~redik.tasks.task.Task.objective_value` (mink tasks: ``½‖cost ⊙
        e‖²``).
        """
        total = 0.0
        for task in self.tasks:
            if isinstance(task, Task):
                total += task.objective_value(state)
            else:
                total += mink_task_value(task, configuration)
        return total

    def weighted_rows_into(
        self, state: KinematicState, A: NDArray[np.float64], b: NDArray[np.float64]
    ) -> None:
        """Write the stacked weighted residual rows at ``state`` into ``A``, ``b``.

        The stacked weighted residual rows at ``state`` into ``A``, ``b`` (of the shapes of
        :attr:`A`, :attr:`b`) rather than the level's own buffers.
        """
        start = 0
        for task, rows, _ in self._blocks:
            stop = start + rows.shape[0]
            task.weighted_residual_into(state, A[start:stop], b[start:stop])
            start = stop

    def _joint_gradient(self, state: KinematicState, c: NDArray[np.float64], fresh: bool) -> None:
        """Joint-space tasks: ``c += Σ α w²d² ⊙ (q ⊖ r)`` (``c =`` when ``fresh``)."""
        if not self.joint_tasks:
            if fresh:
                c.fill(0.0)
            return
        if self.flat:  # the offsets of the last refresh assume it
            if fresh:
                np.multiply(self._joint_factor, state.q, out=c)
            else:
                np.multiply(self._joint_factor, state.q, out=self._joint_buffer)
                c += self._joint_buffer
            c -= self._joint_offset
            return
        # Across ball and free joints q ⊖ r is no difference of vectors: one per task, with
        # the factors of the last refresh.
        if fresh:
            c.fill(0.0)
        for task, factor in self._joint_factors:
            np.multiply(
                factor, state.robot.difference(task.reference, state.q), out=self._joint_buffer
            )
            c += self._joint_buffer

    def _add_other_tasks(
        self,
        state: KinematicState,
        configuration: Configuration | None,
        columns: NDArray[np.intp],
    ) -> None:
        H, c = self.H, self.c
        for task in self.other_tasks:
            if isinstance(task, Task):
                task.add_objective(state, H, c)
            else:
                add_mink_objective(task, configuration, columns, H, c)


def mink_task_value(task: BaseTask, configuration: Configuration | None) -> float:
    """``½‖cost ⊙ e‖²`` of a mink task at ``configuration`` (0 for a task without an error)."""
    if not hasattr(task, "compute_error"):
        return 0.0
    error = foreign_call(task, "compute_error", configuration)
    weighted = np.asarray(getattr(task, "cost", 1.0)) * error
    return 0.5 * float(weighted @ weighted)


def add_mink_objective(
    task: BaseTask,
    configuration: Configuration | None,
    columns: NDArray[np.intp],
    H: NDArray[np.float64],
    c: NDArray[np.float64],
) -> None:
    """Add a mink task's objective, restricted to the chain's velocity ``columns``."""
    residual = None
    if hasattr(task, "compute_qp_residual"):
        residual = foreign_call(task, "compute_qp_residual", configuration)
    if residual is None:
        H_task, c_task = foreign_call(task, "compute_qp_objective", configuration)
        H += H_task[np.ix_(columns, columns)]
        c += c_task[columns]
        return
    weighted_jacobian, weighted_error, mu = residual
    A = weighted_jacobian[:, columns]
    H += A.T @ A
    c -= A.T @ weighted_error
    if mu:
        H.flat[:: H.shape[0] + 1] += mu


class Assembly:
    """Groups tasks into priority levels and builds their objectives each step.

    Args:
        robot: The robot; ``Δq`` has ``robot.dof`` entries.
        tasks: redik tasks (bound here) and mink tasks, in any order.
        damping: The regularisation ``ε`` added to every level's Hessian diagonal.

    Attributes:
        levels: One :class:`LevelAssembly` per distinct priority, highest (0) first.
        needs_configuration: True when a mink task needs a ``mink.Configuration``.
    """

    def __init__(self, robot: Robot, tasks: Sequence[BaseTask], damping: float) -> None:
        for task in tasks:
            if isinstance(task, Task):
                task.bind(robot)
        priorities = sorted({task_priority(task) for task in tasks})
        self.levels = [
            LevelAssembly(
                p, [t for t in tasks if task_priority(t) == p], robot.dof, damping, robot.flat
            )
            for p in priorities
        ]
        self.needs_configuration = any(not isinstance(task, Task) for task in tasks)

    def objectives(
        self, state: KinematicState, configuration: Configuration | None = None
    ) -> list[tuple[NDArray[np.float64], NDArray[np.float64]]]:
        """``(H_k + εI, c_k)`` per level at ``state`` (the level buffers themselves)."""
        columns = state.robot.dof_indices
        for level in self.levels:
            level.build(state, configuration, columns)
        return [(level.H, level.c) for level in self.levels]
