r"""The compiled step of a :class:`~redik.qp.Problem`: one plan, built once, for a common stack.

:func:`compiled_plan` builds a :class:`CompiledPlan` when every task and limit of a problem
is one it supports, and :meth:`Problem.step <redik.qp.Problem.step>` then runs it:

- tasks :class:`~redik.tasks.FrameTask` and :class:`~redik.tasks.PositionTask` (without
  ``lm_damping``), :class:`~redik.tasks.PostureTask`,
  :class:`~redik.tasks.JointLimitAvoidanceTask` and :class:`~redik.tasks.DampingTask`, on
  one priority level, or on two where level 0 holds frame tasks only (a least-squares level
  with fewer rows than the robot has tangent coordinates);
- hard limits :class:`~redik.limits.ConfigurationLimit`, :class:`~redik.limits.VelocityLimit`
  and :class:`~redik.limits.CollisionAvoidanceLimit`;
- the back-end ``"daqp"`` (the default) or ``"quadprog"``, exact active-set solvers, and no
  ``step_damping``.

Anything else — mink tasks and limits, other redik tasks, three levels, ranked or
acceleration limits, other back-ends — keeps the general path, chosen once per problem, so
what a problem does not use costs its step nothing.

**A step** (:meth:`CompiledPlan.step`):

1. ``q`` and ``dt`` are taken as they are when they are a float array and a float (else the
   general path's checks convert them or raise its exact errors); the targets, costs and
   gains that changed are copied into the plan's table; one forward kinematics
   (``mj_kinematics``, ``mj_comPos``); collision rows (:mod:`redik.qp.compiled.collision`).
2. One compiled call (:mod:`redik.qp.compiled.step`) builds every level's :math:`H`,
   :math:`c` from the frame Jacobians taken from ``cdof`` (:mod:`redik.qp.compiled.frames`),
   the box, and level 0's unconstrained minimiser, which is the solution when it is feasible
   (:mod:`redik.qp.compiled.level0`). When a bound binds, redik's compiled primal active-set
   method solves the box QP (:mod:`redik.qp.compiled.box_qp`). With two levels, level 1 is
   then solved in level 0's null space — in closed form along a single free direction, else
   by the reduced level's minimiser (:mod:`redik.qp.compiled.lower_level`).
3. Where rows bind (collision rows on level 0, the reduced rows of level 1) the call returns
   and DAQP, called directly (:mod:`redik.qp.compiled.workspaces`), solves that QP; a second
   call goes on from there.

Every answer is the general path's up to round-off (``tests/test_compiled_plan.py`` holds
the two paths to 1e-9). A state the plan does not settle — an empty box, a Hessian that is
not positive definite, rank-deficient level-0 rows, a failed DAQP solve, a task without a
target — makes :meth:`CompiledPlan.step` return None, and the general path then answers or
raises its own error.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import cast

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.robot import Robot
from redik.kinematics.robot.coordinates import JointCoordinates
from redik.limits import CollisionAvoidanceLimit, ConfigurationLimit, Limit, VelocityLimit
from redik.qp.assembly import LevelAssembly
from redik.qp.backends import Backend, DaqpBackend, QpsolversBackend
from redik.qp.compiled import step as kernel
from redik.qp.compiled.collision import CollisionRows
from redik.qp.compiled.frames import FRAME_KINDS, POSE, POSITION, pack_chains
from redik.qp.compiled.joint_gradient import joint_gradients
from redik.qp.compiled.workspaces import BackendSolves, DaqpWorkspaces
from redik.tasks import (
    DampingTask,
    FrameTask,
    JointLimitAvoidanceTask,
    KinematicState,
    PositionTask,
    PostureTask,
)
from redik.tasks.single_frame_task import SingleFrameTask
from redik.tasks.task import ResidualTask

SUPPORTED_TASKS = (FrameTask, PositionTask, PostureTask, JointLimitAvoidanceTask, DampingTask)
"""The task types a plan assembles (exact types: a subclass may change the residual)."""

SUPPORTED_LIMITS = (ConfigurationLimit, VelocityLimit, CollisionAvoidanceLimit)
"""The limit types a plan imposes, when hard (no ``priority``)."""

_FLOAT = np.dtype(np.float64)

_NOT_SEEN = object()
"""What a pose task's target is compared with before the plan has copied one (None, no target,
must not match it)."""


def compiled_plan(
    robot: Robot,
    state: KinematicState,
    levels: Sequence[LevelAssembly],
    limits: Sequence[Limit],
    backends: Sequence[Backend],
    *,
    damping: float,
    rank_tol: float,
    step_damping: float,
) -> CompiledPlan | None:
    """The compiled plan of a problem, or None when it has something a plan does not support.

    Args:
        robot: The problem's robot.
        state: Its kinematic state (the plan runs its forward kinematics).
        levels: Its priority levels (:class:`~redik.qp.assembly.LevelAssembly`), bound.
        limits: Its limits, bound.
        backends: Its back-ends, one per level.
        damping: The regularisation ``ε`` of every level.
        rank_tol: The null space's relative threshold.
        step_damping: The Levenberg–Marquardt scale of its steps (a plan needs 0).

    Returns:
        The plan (module docstring), or None.
    """
    if not (
        step_damping == 0.0
        and all(_exact(backend) for backend in backends)
        and _plain_levels(levels, robot.dof)
        and all(type(limit) in SUPPORTED_LIMITS and limit.priority is None for limit in limits)
    ):
        return None
    return CompiledPlan(robot, state, levels, limits, backends, damping, rank_tol)


def _exact(backend: Backend) -> bool:
    """Whether ``backend`` is an exact active-set solver: daqp, or quadprog by qpsolvers."""
    if isinstance(backend, QpsolversBackend):
        return backend.solver == "quadprog"
    return type(backend) is DaqpBackend


def _plain_levels(levels: Sequence[LevelAssembly], n: int) -> bool:
    """One or two levels of supported tasks; level 0 of two a wide least-squares level."""
    if not 1 <= len(levels) <= 2:
        return False
    for level in levels:
        if level.other_tasks or any(type(task) not in SUPPORTED_TASKS for task in level.tasks):
            return False
    return len(levels) == 1 or (levels[0].least_squares and levels[0].A.shape[0] < n)


def _level_rows(levels: Sequence[LevelAssembly]) -> list[tuple[int, ResidualTask]]:
    """Each frame task's first row within its own level's rows (what a level's kernel indexes)."""
    rows: list[tuple[int, ResidualTask]] = []
    for level in levels:
        row = 0
        for task in level.residual_tasks:
            rows.append((row, task))
            row += task.k
    return rows


def _frame_body(model: mujoco.MjModel, kind: str, index: int) -> int:
    """The body a frame (site, body or geom ``index``) is fixed to."""
    if kind == "site":
        return int(model.site_bodyid[index])
    if kind == "geom":
        return int(model.geom_bodyid[index])
    return index


class CompiledPlan:
    """The compiled step of a problem (module docstring); built by :func:`compiled_plan`.

    Args:
        robot: The problem's robot.
        state: Its kinematic state.
        levels: Its priority levels.
        limits: Its limits (supported and hard).
        backends: Its back-ends (DAQP's settings are read from the first DAQP one).
        damping: The regularisation ``ε`` of every level.
        rank_tol: The null space's relative threshold.
    """

    def __init__(
        self,
        robot: Robot,
        state: KinematicState,
        levels: Sequence[LevelAssembly],
        limits: Sequence[Limit],
        backends: Sequence[Backend],
        damping: float,
        rank_tol: float,
    ) -> None:
        model, n = robot.model, robot.dof
        self._robot, self._state, self._n = robot, state, n
        self._levels = list(levels)
        column_of = np.full(model.nv, -1, dtype=np.int64)
        column_of[robot.dof_indices] = np.arange(n)
        self._collisions = [
            CollisionRows(limit, robot, column_of)
            for limit in limits
            if isinstance(limit, CollisionAvoidanceLimit)
        ]
        self._build_table(robot, column_of, limits)
        self._build_work(limits, backends, damping, rank_tol)
        self._watch_tasks()
        data = robot.state.data
        poses = (data.xpos, data.xmat, data.site_xpos, data.site_xmat, data.geom_xpos,
                 data.geom_xmat)  # fmt: skip
        self._kinematics = (poses, data.cdof, data.subtree_com)
        self._q = np.zeros(robot.nq)
        self._flat = robot.flat
        # Two entries, so that a plan of one level never compiles level 1's kernels.
        self._kernel = kernel.solve_step if len(levels) == 1 else kernel.solve_two_level_step
        self._row_qps: DaqpWorkspaces | BackendSolves = BackendSolves(backends)
        first = backends[0]
        if isinstance(first, DaqpBackend) and all(
            isinstance(backend, DaqpBackend) for backend in backends
        ):
            self._row_qps = DaqpWorkspaces(first.settings)

    def _build_table(
        self, robot: Robot, column_of: NDArray[np.int64], limits: Sequence[Limit]
    ) -> None:
        """The int buffer (:mod:`redik.qp.compiled.step`): sizes, flags, frames, coordinates."""
        model, n = robot.model, robot.dof
        # A plan's residual tasks are frame and position tasks (_plain_levels).
        tasks = cast(
            list[SingleFrameTask], [task for level in self._levels for task in level.residual_tasks]
        )
        bodies = [_frame_body(model, task.frame.kind, task.frame.id) for task in tasks]
        chains, columns, lengths = pack_chains(model, bodies, column_of)
        coordinates = JointCoordinates.of(model, robot.joint_ids)
        level0 = self._levels[0]
        header = np.zeros(kernel.HEADER, dtype=np.int64)
        header[kernel.H_N], header[kernel.H_LEVELS], header[kernel.H_FRAMES] = (
            n,
            len(self._levels),
            len(tasks),
        )
        header[kernel.H_ROWS] = sum(level.A.shape[0] for level in self._levels)
        header[kernel.H_COLLISION_ROWS] = sum(rows.size for rows in self._collisions)
        header[kernel.H_FREE] = n - level0.A.shape[0] if len(self._levels) == 2 else 0
        header[kernel.H_WIDTH] = chains.shape[1]
        header[kernel.H_QUATERNIONS] = len(coordinates.quaternion_q)
        header[kernel.H_POSITION] = any(isinstance(x, ConfigurationLimit) for x in limits)
        header[kernel.H_VELOCITY] = any(isinstance(x, VelocityLimit) for x in limits)
        header[kernel.H_FLAT] = robot.flat
        header[kernel.H_LEAST_SQUARES] = len(self._levels) == 2 and level0.least_squares
        self._table = np.zeros(kernel.buffer_sizes(header)[0], dtype=np.int64)
        self._table[: kernel.HEADER] = header
        self._work_size = kernel.write_offsets(self._table)
        level_table, frames, chain_table, column_table, scalar_q, quaternions = kernel.int_views(
            self._table
        )
        f = r = 0
        for index, level in enumerate(self._levels):
            rows = level.A.shape[0]
            level_table[index] = f, f + len(level.residual_tasks), r, r + rows
            f, r = f + len(level.residual_tasks), r + rows
        first_row = {id(task): r for r, task in _level_rows(self._levels)}
        for f, (task, body) in enumerate(zip(tasks, bodies, strict=True)):
            kind = POSE if type(task) is FrameTask else POSITION
            frames[f] = (FRAME_KINDS[task.frame.kind], task.frame.id, model.body_rootid[body],
                         lengths[f], kind, first_row[id(task)])  # fmt: skip
        chain_table[:], column_table[:] = chains, columns
        scalar_q[:] = -1
        scalar_q[coordinates.scalar_dofs] = coordinates.scalar_q
        quaternions[:] = coordinates.quaternion_q
        # Where q ⊖ r is a difference of coordinates (hinges, slides, free positions), and
        # where it is a rotation vector (ball and free orientations: quaternion, tangent).
        self._linear_q = np.full(n, -1, dtype=np.int64)
        self._linear_q[coordinates.scalar_dofs] = coordinates.scalar_q
        for q_at, dof_at in zip(coordinates.free_q, coordinates.free_dofs, strict=True):
            self._linear_q[dof_at : dof_at + 3] = q_at + np.arange(3)
        self._rotations = np.array(
            list(zip(coordinates.quaternion_q, coordinates.quaternion_dofs, strict=True)),
            dtype=np.int64,
        ).reshape(-1, 2)
        self._frame_kinds = frames[:, 4].tolist()
        self._tasks = tasks

    def _build_work(
        self, limits: Sequence[Limit], backends: Sequence[Backend], damping: float, rank_tol: float
    ) -> None:
        """The float buffer (:mod:`redik.qp.compiled.step`) and the views Python writes."""
        self._work = np.zeros(self._work_size)
        (self._targets, self._joint, self._gradients, _, _, self._H, self._c, box, self._lb,
         self._ub, self._x, self._C, self._u, self._N, self._Hz, self._cz, self._z, self._rows,
         self._rows_lower, self._rows_upper, self._settings) = kernel.float_views(
            self._work, self._table
        )  # fmt: skip
        box[0], box[1], box[2] = -np.inf, np.inf, np.inf
        for limit in limits:  # several boxes of a kind intersect (level0 module docstring)
            if isinstance(limit, ConfigurationLimit):
                np.maximum(box[0], limit.lower, out=box[0])
                np.minimum(box[1], limit.upper, out=box[1])
            elif isinstance(limit, VelocityLimit):
                np.minimum(box[2], limit.max_velocity, out=box[2])
        self._clip = any(isinstance(limit, ConfigurationLimit) for limit in limits)
        self._velocity = any(isinstance(limit, VelocityLimit) for limit in limits)
        daqp = [backend for backend in backends if isinstance(backend, DaqpBackend)]
        primal_tol = float(daqp[0].settings.get("primal_tol", 0.0)) if daqp else 0.0
        self._settings[:] = damping, rank_tol, 0.0, math.inf, 0.0, primal_tol

    def _watch_tasks(self) -> None:
        """What :meth:`_refresh` compares each step: targets, versions, joint-space sums."""
        self._target_rows = [self._targets[f, :12].reshape(3, 4) for f in range(len(self._tasks))]
        self._poses: list[tuple[int, SingleFrameTask]] = [
            (f, task) for f, task in enumerate(self._tasks) if type(task) is FrameTask
        ]
        self._positions = [
            (f, task) for f, task in enumerate(self._tasks) if type(task) is not FrameTask
        ]
        self._seen: list[object] = [_NOT_SEEN] * len(self._tasks)
        self._versions = [-1] * len(self._tasks)
        self._joint_tasks = [task for level in self._levels for task in level.joint_tasks]
        count = len(self._joint_tasks)
        self._references = np.zeros((count, self._robot.nq))
        self._factors = np.zeros((count, self._n))
        self._level_of = np.zeros(count, dtype=np.int64)
        self._differences = 0
        self._joint_versions: list[int] | None = None

    # ----------------------------------------------------------------------------------

    def step(self, q: NDArray[np.float64], dt: float | None) -> NDArray[np.float64] | None:
        """:meth:`Problem.step <redik.qp.Problem.step>` at ``q``, or None for the general path.

        Args:
            q: The configuration (``robot.nq``,).
            dt: The tick's duration (s), or None.

        Returns:
            ``Δq`` (a fresh array), or None when the general path must answer (module
            docstring).
        """
        duration = self._duration(dt)
        if duration < 0.0:
            return None
        if not (type(q) is np.ndarray and q.dtype is _FLOAT and q.shape == self._q.shape):
            q = self._robot.check_q(q, "q")
        self._q[:] = q
        self._settings[2:4] = 0.0, math.inf
        if not self._refresh():
            return None
        self._state.update(self._q)
        return self._solve_all(duration)

    def static_step(
        self, q: NDArray[np.float64], dt: float | None, lm_damping: float, max_step: float | None
    ) -> NDArray[np.float64] | None:
        """:meth:`Problem.static_step <redik.qp.Problem.static_step>` without its curvature term.

        The kinematic state must be at ``q`` already (the problem's own check).

        Args:
            q: The configuration (``robot.nq``,), valid.
            dt: Passed to velocity limits (None without one).
            lm_damping: ``λ ≥ 0`` added to level 0's Hessian.
            max_step: Optional trust region, ``|Δq_i| ≤ max_step``.

        Returns:
            ``Δq`` (a fresh array), or None when the general path must answer.
        """
        duration = self._duration(dt)
        if duration < 0.0:
            return None
        self._q[:] = q
        self._settings[2:4] = lm_damping, math.inf if max_step is None else max_step
        if not self._refresh():
            return None
        return self._solve_all(duration)

    def _solve_all(self, duration: float) -> NDArray[np.float64] | None:
        """The stages of a step at the current kinematics (module docstring)."""
        if not self._flat:
            joint_gradients(
                self._q, self._references, self._factors, self._level_of, self._differences,
                self._linear_q, self._rotations, self._gradients,
            )  # fmt: skip
        m = self._collision_rows() if self._collisions else 0
        status = self._solve(kernel.START, duration, m)
        if status == kernel.LEVEL0_QP:
            if not self._level0_qp(m):
                return None
            status = self._solve(kernel.AFTER_LEVEL0_QP, duration, m)
        if status == kernel.REDUCED_QP:
            if not self._reduced_qp(m):
                return None
            status = self._solve(kernel.AFTER_REDUCED_QP, duration, m)
        return self._x.copy() if status == kernel.DONE else None

    def reset(self) -> None:
        """Forget DAQP's workspaces and warm starts."""
        self._row_qps.reset()

    def _solve(self, stage: int, dt: float, m: int) -> int:
        poses, cdof, subtree_com = self._kinematics
        status: int = self._kernel(
            stage, self._q, dt, m, poses, cdof, subtree_com, self._table, self._work
        )
        return status

    def _duration(self, dt: object) -> float:
        """``dt`` as a float (0 for None), or −1 when the general path must check or refuse it."""
        if dt is None:
            return -1.0 if self._velocity else 0.0
        if isinstance(dt, float | int) and not isinstance(dt, bool) and 0.0 < dt < math.inf:
            return float(dt)
        return -1.0

    def _refresh(self) -> bool:
        """Copy the targets, scales and joint-space sums that changed into the buffers.

        A pose target is copied when the task's ``target`` is a new object (``set_target``
        makes one), a position target (3 floats) every time, the scales when ``version``
        moved, the joint-space sums when a joint-space task's ``version`` did.

        Returns:
            False when a task has no target (the general path raises it).
        """
        for f, task in self._poses:
            target = task.target
            if target is not self._seen[f]:
                if target is None:
                    return False
                self._target_rows[f][:] = target[:3]
                self._seen[f] = target
            if task.version != self._versions[f]:
                np.negative(task.cost, out=self._targets[f, 12:18])
                np.multiply(task.cost, -task.gain, out=self._targets[f, 18:24])
                self._versions[f] = task.version
        for f, task in self._positions:
            if task.target is None:
                return False
            self._target_rows[f][:, 3] = task.target
            if task.version != self._versions[f]:
                self._targets[f, 12:15] = task.cost
                self._targets[f, 18] = -task.gain
                self._versions[f] = task.version
        versions = [task.version for task in self._joint_tasks]
        if versions != self._joint_versions:
            self._pack_joint_terms()
            self._joint_versions = versions
        return True

    def _pack_joint_terms(self) -> None:
        """Copy the levels' joint-space sums; on a robot that is not flat, the tasks' terms.

        Each joint-space task's ``(r, α w²d²)`` and level (:mod:`.joint_gradient`).
        """
        for index, level in enumerate(self._levels):
            self._joint[index] = level.joint_terms()
        if self._flat:
            return
        t = 0
        for index, level in enumerate(self._levels):
            for reference, factor in level.joint_differences():
                self._references[t], self._factors[t], self._level_of[t] = reference, factor, index
                t += 1
        self._differences = t

    def _collision_rows(self) -> int:
        """Write the active collision rows into ``C``, ``u``; return their number."""
        m = 0
        for collision in self._collisions:
            m += collision.rows_into(self._C[m:], self._u[m:])
        return m

    def _level0_qp(self, m: int) -> bool:
        """Level 0's QP with its rows, by DAQP; False when DAQP fails (the general path raises).

        The kernel has written its bounds (box, then rows) into ``rows_lower``, ``rows_upper``.
        """
        k = self._n + m
        solution = self._row_qps.solve(
            (0, m), self._H[0], self._c[0], self._rows_upper[:k], self._rows_lower[:k],
            self._C[:m],
        )  # fmt: skip
        if solution is None:
            return False
        self._x[:] = solution
        return True

    def _reduced_qp(self, m: int) -> bool:
        """Level 1's reduced QP with its rows, by DAQP; False when it fails.

        The general path then answers: on a degenerate reduced QP (rows pinned at zero width)
        whether a back-end succeeds can turn on round-off, and the general path's own attempt
        decides, skipping the level as it does.
        """
        k = self._n + m
        z = self._row_qps.solve(
            (1, m), self._Hz, self._cz, self._rows_upper[:k], self._rows_lower[:k],
            self._rows[:k],
        )  # fmt: skip
        if z is None:
            return False
        self._z[:] = z
        return True
