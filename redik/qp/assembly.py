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
\mathcal{b}` in one product per level; other tasks add their own :math:`(H_i, c_i)`. The
solver adds a regularisation :math:`εI` (``damping``) to each level. With several levels
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

import numpy as np

from ..robot import Robot
from ..tasks.kinematics import KinematicState
from ..tasks.task import ResidualTask, Task


def task_priority(task) -> int:
    """A task's priority level; mink tasks, which have none, are level 0."""
    return int(getattr(task, "priority", 0))


class LevelAssembly:
    """The objective buffers of one priority level.

    Attributes:
        priority: The level's priority value.
        residual_tasks: ``(task, row slice)`` of the redik residual tasks, stacked in ``A``.
        other_tasks: redik tasks with their own objective, and mink tasks.
        A, b: The stacked weighted residual rows.
        H, c: The level's objective, rebuilt by :meth:`build`.
    """

    def __init__(self, priority: int, tasks: Sequence, n: int):
        self.priority = priority
        self.residual_tasks: list[tuple[ResidualTask, slice]] = []
        self.other_tasks: list = []
        rows = 0
        for task in tasks:
            if isinstance(task, ResidualTask):
                self.residual_tasks.append((task, slice(rows, rows + task.k)))
                rows += task.k
            else:
                self.other_tasks.append(task)
        self.A = np.zeros((rows, n))
        self.b = np.zeros(rows)
        self.H = np.zeros((n, n))
        self.c = np.zeros(n)

    @property
    def tasks(self) -> list:
        """Every task of the level."""
        return [task for task, _ in self.residual_tasks] + self.other_tasks

    def build(self, state: KinematicState, configuration, columns: np.ndarray) -> None:
        """Fill ``H`` and ``c`` at ``state`` (``configuration`` only for mink tasks)."""
        A, b, H, c = self.A, self.b, self.H, self.c
        for task, rows in self.residual_tasks:
            task.weighted_residual_into(state, A[rows], b[rows])
        np.dot(A.T, A, out=H)
        np.dot(A.T, b, out=c)
        np.negative(c, out=c)
        for task in self.other_tasks:
            if isinstance(task, Task):
                task.add_objective(state, H, c)
            else:
                add_mink_objective(task, configuration, columns, H, c)


def add_mink_objective(task, configuration, columns: np.ndarray, H: np.ndarray, c: np.ndarray):
    """Add a mink task's objective, restricted to the chain's velocity ``columns``."""
    residual = task.compute_qp_residual(configuration)
    if residual is None:
        H_task, c_task = task.compute_qp_objective(configuration)
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

    Attributes:
        levels: One :class:`LevelAssembly` per distinct priority, highest (0) first.
        needs_configuration: True when a mink task needs a ``mink.Configuration``.
    """

    def __init__(self, robot: Robot, tasks: Sequence):
        for task in tasks:
            if isinstance(task, Task):
                task.bind(robot)
        priorities = sorted({task_priority(task) for task in tasks})
        self.levels = [
            LevelAssembly(p, [t for t in tasks if task_priority(t) == p], robot.dof)
            for p in priorities
        ]
        self.needs_configuration = any(not isinstance(task, Task) for task in tasks)

    def objectives(
        self, state: KinematicState, configuration=None
    ) -> list[tuple[np.ndarray, np.ndarray]]:
        """``(H_k, c_k)`` per level at ``state`` (views of the level buffers)."""
        columns = state.robot.dof_indices
        for level in self.levels:
            level.build(state, configuration, columns)
        return [(level.H, level.c) for level in self.levels]
