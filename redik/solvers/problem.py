r"""The optimisation driver: a robot, a stack of tasks and limits, one QP per step.

``problem.step(q, dt)`` returns the joint step :math:`Δq` for online control at a fixed
rate; ``problem.solve(q0)`` iterates :math:`q \leftarrow q + Δq` until the highest-priority
tasks converge. Each step runs forward kinematics once, fills preallocated per-level
objectives (:mod:`redik.qp.assembly`), intersects the box limits, and solves the levels
lexicographically (:mod:`redik.qp.hierarchy`) with the chosen back-end
(:mod:`redik.qp.backends`).

**Limits are never left.** The position box is shrunk by the back-end's tolerance and
:math:`q + Δq` is then clipped into the joint limits, so every configuration ``step`` leads
to and ``solve`` returns lies within them (:mod:`redik.limits.configuration_limit`). The default
limits also hold every limited ball joint in its cone (:mod:`redik.limits.ball_joint_limit`).
A ``ConfigurationLimit(periodic=True)`` leaves joints whose range spans a full turn unboxed and
``solve`` turns each iterate back into their range by multiples of 2π (same pose).

**Whole models.** On a robot with ball or free joints (a floating base), ``q`` has
``robot.nq`` entries and ``Δq`` ``robot.dof`` (the tangent space): ``solve`` steps by
``robot.integrate(q, αΔq)`` (``mj_integratePos``) and joint-space tasks measure
``q ⊖ r`` by ``mj_differentiatePos``; pose tasks on several frames (two hands, the feet)
at any priorities (:mod:`redik.kinematics.robot`). Limits linearised at ``q`` (collision distances)
are re-checked at the end of a step, which ``solve`` shortens until they hold.

mink tasks and limits may be mixed in; a ``mink.Configuration`` is then kept in sync with
``q`` (one more forward kinematics per step, paid only when one is present).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import mink
import numpy as np
from scipy.optimize import nnls

from redik.core.exceptions import InfeasibleProblem, InvalidInput
from redik.core.result import IKResult, Status
from redik.core.validate import fraction, integer, non_negative, positive, real_array
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
from redik.qp.hierarchy import kernel_directions, row_null_space, solve_lexicographic
from redik.tasks.joint_space_task import JointSpaceTask
from redik.tasks.kinematics import KinematicState
from redik.tasks.single_frame_task import SingleFrameTask
from redik.tasks.task import ResidualTask, Task

_MIN_STEP_FRACTION = 1.0 / 64.0
"""Smallest fraction of a QP step ``solve`` tries before calling the iterate stalled."""

_MU_MIN, _MU_MAX = 1e-9, 1e6
"""Bounds of the adaptive Levenberg–Marquardt scale of ``solve``."""


_CURVATURE_STEP = 1e-6
"""Forward-difference step (rad or m) of :meth:`Problem._level1_curvature`."""

_ACTIVE_TOL = 1e-9
"""A limit whose bound on ``Δq`` is within this of 0 is active (stationarity test)."""


@dataclasses.dataclass
class QPResult(IKResult):
    """:class:`~redik.core.result.IKResult` of :meth:`Problem.solve`, with the lower levels'
    optimality.

    Attributes:
        stationarity: Per lower level (priority order, level 0 excluded), the norm of its
            objective's gradient projected onto the directions the higher levels and the
            active limits leave free, at ``q`` (:meth:`Problem.stationarity`); empty with one
            level.
        stationary: True when every value is within ``stationarity_tol``: ``q`` is a
            (first-order) optimum of the lower levels subject to the higher ones and the
            limits, not merely a point where level 0 converged.
    """

    stationarity: list[float] = dataclasses.field(default_factory=list)
    stationary: bool = True


def _is_real(value) -> bool:
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)


def _joint_vector(robot: Robot, q, name: str) -> np.ndarray:
    """``robot.check_q``: a non-numeric (string, complex, object, ragged) ``q`` is an
    :class:`InvalidConfiguration` there too."""
    return robot.check_q(q, name)


def _check_dt(dt) -> None:
    if dt is not None:
        positive(dt, "dt", unit="s")


def _as_list(items, name: str, marker: str) -> list:
    """``items`` as a list; one object having ``marker`` (a task, a limit) is the list of it."""
    if hasattr(items, marker) or isinstance(items, Limit):
        return [items]
    try:
        if isinstance(items, str | bytes):
            raise TypeError
        return list(items)
    except TypeError:  # None, a number, a 0-d array
        raise InvalidInput(f"{name} must be a list (or a single one), got {items!r}") from None


class Problem:
    """Differential IK as a (hierarchical) QP over the joints ``robot`` moves.

    Args:
        robot: The robot; ``Δq`` has ``robot.dof`` entries (its tangent coordinates), a
            configuration ``q`` has ``robot.nq`` (see :mod:`redik.kinematics.robot`).
        tasks: redik tasks and/or mink tasks (``mink.FrameTask``, ``mink.ComTask``…). Tasks
            of equal ``priority`` are weighted and summed; priorities are strict. A single
            task is accepted as the list of it, ``Problem(robot, FrameTask("ee", target=T))``.
        limits: redik or mink limits; None is the robot's own ranges, ``[ConfigurationLimit()]``
            plus a :class:`~redik.limits.BallJointLimit` when it moves limited ball joints
            (whose cones no box holds); ``[]`` is none; a single limit is the list of it.
            A limit is hard at every level unless given ``priority=k``: it then ranks just
            above the tasks of priority ``k`` — those above may break it, those from ``k``
            down may not (:mod:`redik.limits.limit`).
        backend: A back-end name, a list of names (a fallback chain) or a
            :class:`~redik.qp.backends.Backend` (see :func:`~redik.qp.backends.make_backend`);
            an instance serves one priority level only, since back-ends keep per-QP state
            (a workspace, a warm start): with several levels, pass a name.
        damping: Regularisation ``ε`` added to each level's Hessian (default 1e-6: keeps
            active-set solvers out of trouble, changes a converged solution by nothing).
        rank_tol: Relative eigenvalue threshold of the null space between levels.
        backend_options: Settings passed to the back-end.
        step_damping: Levenberg–Marquardt scale ``μ`` of :meth:`step` (≥ 0; default 0,
            undamped): level 0's Hessian gets ``λ = μ‖b₀‖²``, ``b₀ = −αWe`` its weighted
            task error (see :meth:`step`). ``solve`` has its own adaptive ``lm_damping``.

    Attributes:
        levels: The priority values, highest first.
        stats: Counters; ``"skipped_levels"``: lower levels whose back-end failed
            (:mod:`redik.qp.hierarchy`).
    """

    def __init__(
        self,
        robot: Robot,
        tasks: Sequence,
        limits: Sequence | None = None,
        backend: str | Sequence[str] | Backend = "daqp",
        *,
        damping: float = 1e-6,
        rank_tol: float = 1e-10,
        backend_options: dict | None = None,
        step_damping: float = 0.0,
    ):
        if not isinstance(robot, Robot):
            raise InvalidInput(f"robot must be a redik.Robot, got {type(robot).__name__}")
        tasks = _as_list(tasks, "tasks", "compute_qp_objective")
        if not tasks:
            raise InvalidInput("a Problem needs at least one task")
        for task in tasks:
            if not hasattr(task, "compute_qp_objective"):
                raise InvalidInput(f"{task!r} is not a task (no compute_qp_objective)")
        non_negative(damping, "damping")
        non_negative(step_damping, "step_damping")
        if not _is_real(rank_tol) or not (np.isfinite(rank_tol) and 0.0 <= rank_tol < 1.0):
            raise InvalidInput(f"rank_tol must be in [0, 1), got {rank_tol!r}")
        if backend_options is not None and not isinstance(backend_options, dict):
            raise InvalidInput(f"backend_options must be a dict, got {backend_options!r}")
        self.robot = robot
        self.step_damping = float(step_damping)
        self.tasks = tasks
        self.damping = float(damping)
        self.rank_tol = float(rank_tol)
        self._assembly = Assembly(robot, tasks, self.damping)
        self.levels = [level.priority for level in self._assembly.levels]
        options = backend_options or {}
        if isinstance(backend, Backend) and (len(self.levels) > 1 or options):
            raise InvalidInput(
                f"a Backend instance ({backend.name!r}) keeps one QP's state and its own "
                f"settings: it cannot serve {len(self.levels)} priority levels or take "
                "backend_options; pass the back-end by name"
            )
        self.backends = [make_backend(backend, **options) for _ in self.levels]
        level0 = self._assembly.levels[0]
        # Level 0's rows when it is a least-squares level: its null space comes from their
        # QR, its unconstrained step from their Gram matrix (redik.qp.hierarchy).
        self._rows0 = level0.A if level0.least_squares else None
        self._rhs0 = level0.b
        self._curvature_rows = np.empty_like(level0.A)
        self._curvature_residual = np.empty_like(level0.b)
        tolerance = max(b.tolerance for b in self.backends)

        if limits is None:
            limits = [ConfigurationLimit()] + (
                [BallJointLimit()] if limited_ball_joints(robot) else []
            )
        else:
            limits = _as_list(limits, "limits", "compute_qp_inequalities")
        self.limits: list[Limit] = []
        for limit in limits:
            if not isinstance(limit, Limit):
                if not hasattr(limit, "compute_qp_inequalities"):
                    raise InvalidInput(f"{limit!r} is not a limit")
                limit = MinkLimit(limit)
            self.limits.append(limit.bind(robot, tolerance))
        hard = [limit for limit in self.limits if limit.priority is None]
        # The acceleration box yields to the position and velocity boxes: applied after them.
        self._boxes = sorted(
            (limit for limit in hard if isinstance(limit, BoxLimit)),
            key=lambda limit: isinstance(limit, AccelerationLimit),
        )
        # solve() and stationarity() look for a static configuration, not a motion: the
        # acceleration box (a bound between control ticks) has no meaning there.
        self._static_boxes = [
            limit for limit in self._boxes if not isinstance(limit, AccelerationLimit)
        ]
        self._rows = [limit for limit in hard if isinstance(limit, InequalityLimit)]
        self._clip = any(isinstance(limit, ConfigurationLimit) for limit in hard)
        # Ranked limits (priority=k): one slack level per priority, just above the tasks of
        # that priority (redik.limits.limit); (priority, index of the first task level at or
        # below it, its limits, its back-end).
        priorities = sorted({limit.priority for limit in self.limits} - {None})
        if priorities and isinstance(backend, Backend):
            raise InvalidInput(
                f"a Backend instance ({backend.name!r}) keeps one QP's state: it cannot also "
                f"serve the levels of the limits ranked at priorities {priorities}; pass the "
                "back-end by name"
            )
        self._ranked = [
            (
                p,
                sum(level < p for level in self.levels),
                [limit for limit in self.limits if limit.priority == p],
                make_backend(backend, **options),
            )
            for p in priorities
        ]
        # Limits whose nonlinear check shortens the steps of solve(): those no task outranks.
        # A limit ranked below a task must let that task's steps through.
        self._admitting = self._rows + [
            limit
            for _, index, limits, _ in self._ranked
            if index == 0
            for limit in limits
            if isinstance(limit, InequalityLimit)
        ]
        # Position limits that turn full-turn joints back into range (periodic=True).
        self._wraps = [
            limit
            for limit in self.limits
            if isinstance(limit, ConfigurationLimit) and limit.turning.any()
        ]

        self.stats: dict[str, int] = {}
        self._state = KinematicState.for_robot(robot)
        self._configuration = None
        if self._assembly.needs_configuration or any(
            getattr(limit, "needs_configuration", False) for limit in self.limits
        ):
            self._configuration = mink.Configuration(robot.model)
        self._lb = np.full(robot.dof, -np.inf)
        self._ub = np.full(robot.dof, np.inf)
        # What "converged" waits for: the level-0 tasks with a target. Joint-space
        # regularisers and gradient tasks have none.
        self._targets = [
            task
            for task in self._assembly.levels[0].tasks
            if not isinstance(task, JointSpaceTask)
            and (isinstance(task, ResidualTask) or not isinstance(task, Task))
        ]
        # (task, e, J, is a frame task): error buffers of the residual tasks, filled in place.
        self._target_buffers = [
            (
                task,
                np.empty(task.k),
                np.empty((task.k, self._state.n_columns)),
                isinstance(task, SingleFrameTask),
            )
            if isinstance(task, ResidualTask)
            else (task, None, None, False)
            for task in self._targets
        ]

    # ----------------------------------------------------------------------------------
    # Online control

    def step(self, q: np.ndarray, dt: float | None = None) -> np.ndarray:
        r"""The joint step ``Δq`` at ``q`` (``q ⊕ Δq`` stays within the position limits).

        ``Δq`` is a tangent vector (``robot.dof``,): apply it with
        ``robot.integrate(q, Δq)`` (``q + Δq`` when ``robot.flat``). ``dt`` (seconds) is
        needed by velocity limits; divide ``Δq`` by it for a velocity.

        With ``step_damping = μ > 0`` level 0 is solved as damped least squares,
        :math:`\min ½‖AΔq − b‖² + ½λ‖Δq‖²` with :math:`λ = μ‖b‖²` (Levenberg–Marquardt
        with Sugihara's error-dependent choice, *Solvability-unconcerned inverse kinematics
        by the Levenberg–Marquardt method*, IEEE T-RO 2011; :math:`A = WJ`,
        :math:`b = −αWe` the stacked level-0 rows). Why a tracking loop needs it: when the
        target leaves the workspace the arm stretches to a fold of its reach, where
        :math:`J` loses rank in the direction of the error. There the Gauss–Newton step
        :math:`σ^{-1} u^\top b` along the weakest singular pair :math:`(σ, u, v)` grows
        without bound as :math:`σ → 0` and jumps across the fold; the velocity box clips it
        to a vertex and the next tick jumps back — a two-tick cycle at the velocity limit.
        Damped, that component is :math:`σ/(σ² + λ)\, u^\top b → 0`; in one dimension,
        with reach :math:`r(θ) ≈ r^* − ½κ(θ − θ^*)²`, the fold is a stable, non-oscillating
        fixed point once :math:`λ ≥ κ‖e‖` (Gauss–Newton neglects exactly this
        :math:`Σ e_i ∇² e_i` term: Nocedal & Wright §10.3). On a reachable path the error
        of one tick is small and :math:`λ = μ‖b‖²` vanishes quadratically: tracking is
        unchanged. Lower levels still move in the null space of level 0's rows
        (the λ shift is discounted, :mod:`redik.qp.hierarchy`).

        Measured (``tests/test_problem.py``; Panda from q₂ = 0 along a circle whose top is
        39 mm out of reach, 100 Hz, 2 rad/s): undamped, 441 velocity reversals of more than
        1 rad/s; ``μ = 10``, none, and the same 38.8 mm miss. Limits of the remedy: the
        quadratic law under-damps a small gap (a fold missed by 8 mm: reversals drop from
        188 to 6, the miss grows from 8 to 12 mm); and damping does not make a *lower*
        level smooth — near the fold the null space of :math:`A` turns by
        :math:`O(‖δA‖/σ)` per tick, so a posture regulator at priority 1 that saturates the
        velocity box (gain 1) still reverses there, and the arm may leave the fold on the
        other branch of the elbow and stall at a joint limit (there: 90 mm at the end).
        Keep such a regulator's gain low (0.02 on that circle: no reversal), put it at
        level 0 with a small cost, or bound the acceleration: with
        :class:`~redik.limits.AccelerationLimit` (20 rad/s²) on that circle, a posture of gain
        1 at priority 1 makes 1 two-tick reversal instead of 214, |q̈| ≤ 20 rad/s² instead of
        400, and the miss is the 39 mm gap again, not 90 mm
        (``examples/acceleration_limit_posture_chatter.py``).

        **State between calls.** :meth:`step` reports each step it returns to the limits
        (:meth:`~redik.limits.limit.Limit.advance`): an
        :class:`~redik.limits.AccelerationLimit` bounds the next step around the velocity of
        this one, so consecutive calls form one motion. That recorded velocity is the only
        state that changes a later step's answer; it persists until :meth:`reset` (a new
        motion), which the loop drivers (:func:`redik.apps.sim.simulate`) call at the start
        of each run, and is neither read nor changed by :meth:`solve`. The back-ends' warm
        starts also persist (they change an answer by round-off only) until :meth:`reset`;
        task targets are the caller's (``set_target``) and are kept; :attr:`stats` counts
        across calls.

        Raises:
            InfeasibleProblem: the limits admit no step (e.g. a joint outside its range
                by more than its velocity limit allows to recover in ``dt``).
            BackendError: the back-end (every back-end of a chain) failed.
        """
        q = _joint_vector(self.robot, q, "q")
        _check_dt(dt)
        self._update(q)
        dq = self._step(q, dt, error_damping=self.step_damping, motion=True)
        for limit in self.limits:
            limit.advance(dq, dt)
        return dq

    def reset(self, velocity: np.ndarray | None = None) -> None:
        """Start a new motion: every limit and task forgets what earlier :meth:`step` calls
        recorded, and the next step starts from joint velocity ``velocity`` (``robot.dof``,
        rad/s or m/s; None: at rest).

        Call it whenever the robot does not continue the motion of the previous step: a new
        run from a new start, a stop, a jump of ``q``. :func:`redik.apps.sim.simulate` calls
        it at the start of each run (the arm starts at rest). Without it, an
        :class:`~redik.limits.AccelerationLimit` brakes the first step of a new run against
        the last velocity of the previous one. The back-ends forget their warm starts too,
        so the run repeats a fresh problem's bit for bit. Task targets are kept.

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
        for backend in [*self.backends, *(backend for *_, backend in self._ranked)]:
            backend.reset()

    def _update(self, q: np.ndarray) -> None:
        self._state.update(q)
        if self._configuration is not None:
            self._configuration.update(self.robot.state.data.qpos)

    def _step(
        self,
        q: np.ndarray,
        dt: float | None,
        max_step: float | None = None,
        lm_damping: float = 0.0,
        error_damping: float = 0.0,
        objectives: list | None = None,
        kernel0: np.ndarray | None = None,
        second_order: bool = False,
        motion: bool = False,
    ):
        """The step at the current state (``q``); ``objectives`` and ``kernel0`` (level 0's
        null space), when given, are this state's (:meth:`_stationarity` just built them)
        and are not rebuilt. ``second_order`` adds level 1's curvature term
        (:meth:`_level1_curvature`) where level 0 is a least-squares level. ``motion``
        (:meth:`step`) applies the acceleration limits, which :meth:`solve` leaves out."""
        if objectives is None:
            objectives = self._assembly.objectives(self._state, self._configuration)
        curvature1 = None
        if second_order and self._rows0 is not None and len(objectives) > 1:
            c1 = objectives[1][1].copy()  # level 1's gradient at q, before anything moves
            curvature1 = lambda N: self._level1_curvature(q, c1, N)  # noqa: E731
        if error_damping > 0.0:
            b0 = self._assembly.levels[0].b  # level 0's weighted residual rows, just built
            lm_damping += error_damping * float(b0 @ b0)
        damping: float | list[float] = self.damping
        if lm_damping > 0.0:
            # Levenberg–Marquardt on level 0 only; the arrays are rebuilt every step.
            H0 = objectives[0][0]
            H0.flat[:: H0.shape[0] + 1] += lm_damping
            damping = [self.damping + lm_damping] + [self.damping] * (len(objectives) - 1)
        lb, ub = self._lb, self._ub
        boxes = self._boxes if motion else self._static_boxes
        if boxes:
            q_box = self.robot.scalar_values(q)
            boxes[0].set_bounds(q_box, dt, lb, ub)
            for limit in boxes[1:]:
                limit.bounds_into(q_box, dt, lb, ub)
        if max_step is not None:
            np.maximum(lb, -max_step, out=lb)
            np.minimum(ub, max_step, out=ub)
        # One position box is never empty (bind shrinks it by at most a quarter range).
        if len(boxes) > 1 and (lb > ub).any():
            bad = np.flatnonzero(lb > ub)
            names = [self.robot.dof_names[i] for i in bad]
            raise InfeasibleProblem(
                f"the limits admit no step for joints {names}: lower bounds "
                f"{lb[bad].tolist()} exceed upper bounds {ub[bad].tolist()} at q = "
                f"{q_box[bad].tolist()} (dt = {dt})"
            )
        C = low = up = None
        if self._rows:
            source = self._configuration
            blocks = [limit.inequalities(source, dt) for limit in self._rows]
            blocks = [block for block in blocks if block is not None]
            if blocks:
                C = np.vstack([G for G, _ in blocks])
                up = np.concatenate([h for _, h in blocks])
                low = np.full_like(up, -np.inf)
        ranked = [
            (index, *self._ranked_rows(limits, q_box if boxes else None, q, dt, motion), backend)
            for _, index, limits, backend in self._ranked
        ]
        ranked = [(index, G, h, backend) for index, G, h, backend in ranked if G is not None]
        bounded = bool(boxes) or max_step is not None
        dq = solve_lexicographic(
            objectives,
            self.backends,
            lb if bounded else None,
            ub if bounded else None,
            C,
            low,
            up,
            damping=damping,
            rank_tol=self.rank_tol,
            stats=self.stats,
            rows0=self._rows0,
            rhs0=self._rhs0,
            kernel0=kernel0,
            curvature1=curvature1,
            ranked=ranked,
        )
        if self._clip:
            # Into the (shrunk) box the solver was given: inside the limits, whatever its
            # tolerance.
            np.maximum(dq, lb, out=dq)
            np.minimum(dq, ub, out=dq)
        return dq

    def _ranked_rows(
        self, limits: list[Limit], q_box, q: np.ndarray, dt: float | None, motion: bool = False
    ):
        """``(G, h)``: the rows ``G Δq ≤ h`` of ranked ``limits`` at the current state, boxes
        as ``±Δq_i`` rows of their finite bounds; ``(None, None)`` when none is active.
        Acceleration limits count only in a ``motion`` (:meth:`step`)."""
        blocks = []
        for limit in limits:
            if isinstance(limit, AccelerationLimit) and not motion:
                continue
            if isinstance(limit, BoxLimit):
                if q_box is None:
                    q_box = self.robot.scalar_values(q)
                lower, upper = np.full(self.robot.dof, -np.inf), np.full(self.robot.dof, np.inf)
                limit.bounds_into(q_box, dt, lower, upper)
                eye = np.eye(self.robot.dof)
                up, low = np.isfinite(upper), np.isfinite(lower)
                if up.any() or low.any():
                    blocks.append(
                        (np.vstack([eye[up], -eye[low]]), np.concatenate([upper[up], -lower[low]]))
                    )
            else:
                block = limit.inequalities(self._configuration, dt)
                if block is not None:
                    blocks.append(block)
        if not blocks:
            return None, None
        return np.vstack([G for G, _ in blocks]), np.concatenate([h for _, h in blocks])

    def _level1_curvature(self, q: np.ndarray, c1: np.ndarray, N: np.ndarray) -> np.ndarray:
        r"""``NᵀMN`` with :math:`M = \sum_i λ_i ∇^2 r_i`: the curvature of level 0's rows
        :math:`r(q)` (Jacobian :math:`A`, the stacked weighted residual rows) weighted by
        level 1's least-squares multipliers :math:`λ = \arg\min ‖c_1 + A^\top λ‖`.

        Level 1 moves along the null space of :math:`A`, which turns with :math:`q`: the
        optimal set of level 0 is a curved manifold, and a step along its tangent leaves it
        at second order, which level 0 corrects at the next iteration — moving level 1 off
        its optimum. Level 1's own Hessian ignores this, and the lower level then converges
        only linearly. :math:`N^\top(H_1 + M)N` is the reduced Hessian of the Lagrangian
        :math:`f_1 + λ^\top r`, whose Newton step converges quadratically (sequential
        quadratic programming, Nocedal & Wright §18.1; the null-space form, §18.4).
        :math:`MN` is the derivative of :math:`A^\top λ` along each column of :math:`N`, by a
        forward difference of the rows at :math:`q ⊕ hN_j` (one forward kinematics each;
        :math:`h` = :data:`_CURVATURE_STEP`); the state is back at ``q`` on return.
        """
        level0 = self._assembly.levels[0]
        A = level0.A
        try:
            multipliers = -np.linalg.solve(A @ A.T, A @ c1)
        except np.linalg.LinAlgError:
            multipliers = -np.linalg.lstsq(A.T, c1)[0]
        rows, residual = self._curvature_rows, self._curvature_residual
        gradient = A.T @ multipliers
        MN = np.empty_like(N)
        for j in range(N.shape[1]):
            self._state.update(self.robot.integrate(q, _CURVATURE_STEP * N[:, j]))
            level0.weighted_rows_into(self._state, rows, residual)
            MN[:, j] = (rows.T @ multipliers - gradient) / _CURVATURE_STEP
        self._state.update(q)
        curvature = N.T @ MN
        return 0.5 * (curvature + curvature.T)

    # ----------------------------------------------------------------------------------
    # Iterative solve

    def solve(
        self,
        q0: np.ndarray,
        pos_tol: float = 1e-6,
        rot_tol: float = 1e-5,
        max_iterations: int = 100,
        *,
        q_tol: float = 1e-12,
        max_step: float | None = None,
        dt: float | None = None,
        lm_damping: float = 0.1,
        stationarity_tol: float | None = 1e-8,
        patience: int | None = None,
        progress: float = 0.5,
        plateau: float | None = None,
    ) -> QPResult:
        r"""Iterate ``q ← q + αΔq`` from ``q0`` until the priority-0 tasks converge and the
        lower levels are stationary.

        Level 0 is solved as damped least squares: its Hessian gets ``λ = μ‖e‖²`` (``e`` the
        level-0 error; Levenberg–Marquardt with Sugihara's 2011 choice, as ``solve_pose``'s
        ``"dls"``), so far from the target the step is short and gradient-like and near it
        λ → 0 leaves Gauss–Newton's quadratic convergence. ``μ`` starts at ``lm_damping``,
        halves after a full step and grows ×8 after a cut one; the lower levels still move
        only in the null space of level 0's residual. ``lm_damping=0`` keeps ``μ = 0``:
        undamped Gauss–Newton steps, still backtracked.

        ``Δq`` is the lexicographic QP step of :meth:`step`; ``α ∈ {1, ½, ¼, …, 1/64}`` is
        the first fraction that lowers the level-0 error (backtracking, as in damped
        Gauss–Newton: Nocedal & Wright §10.3); a step is taken only when it lowers that
        error or meets the tolerances, so the iteration cannot cycle. No fraction lowering
        it means a (constrained) stationary point: ``"stalled"``.

        Converged means: every frame task of level 0 within ``pos_tol`` (m) and
        ``rot_tol`` (rad) — position and rotation errors of :mod:`redik.core.conventions` —
        and every other level-0 task that has a target (a mink task) with
        ``‖W e‖ ≤ pos_tol``, ``W = diag(cost)`` its cost-weighted error — what its QP
        term asks for: a component of zero cost (the height of a ``mink.ComTask`` with
        cost ``[1, 1, 0]``) is not waited for, and the backtracking measures the same
        weighted error. Joint-space regularisers (posture, joint-limit avoidance,
        damping) and gradient tasks have no target and are not waited for. With frame tasks
        on several frames (two hands, the feet) the reported position and rotation errors
        are the largest. With no target at level 0, the solve converges when the step taken
        vanishes (``‖αΔq‖ < q_tol``).

        **Lower levels are finished, not abandoned.** Stopping as soon as level 0 converges
        leaves the lower levels wherever the iteration happened to be: a posture task at
        priority 1 is then only partly served. With ``stationarity_tol`` set and several
        levels, the iteration goes on after level 0 converges — a step is then accepted
        when level 0 stays converged — until every lower level is stationary
        (:meth:`stationarity` ≤ ``stationarity_tol``): the first-order condition of

        .. math:: \min_q f_k(q) \quad\text{s.t.}\quad e_0(q) = 0,\ \dots,
                  \ q \in \mathcal{Q},

        i.e. ``q`` is the constrained optimum of the lower levels (Nocedal & Wright
        §12.3; the lexicographic form of Kanoun et al. 2011). Should the budget run out
        first, the result keeps ``success`` (level 0 is met) with ``stationary=False``.
        ``stationarity_tol=None`` stops at level-0 convergence.

        **Level 1 takes Newton steps on the manifold.** Where level 0 is a least-squares
        level (residual tasks only), level 1's reduced Hessian gets the curvature of level
        0's optimal set, :math:`N^\top(\sum_i λ_i ∇^2 r_i)N` (:meth:`_level1_curvature`:
        one forward kinematics per free direction), whenever the sum stays convex: the
        step is then sequential quadratic programming's, and the lower level converges
        quadratically instead of linearly (``specs/panda_reach.py``, joint-limit avoidance
        below the pose: 17.1 → 6.0 iterations per target on average, the slowest from the
        100-iteration cap, not stationary, to 10). Levels below 1 keep their own Hessians.

        **Motion limits are left out.** The iterates are not control ticks but steps towards
        a static solution: an :class:`~redik.limits.AccelerationLimit` (a bound on the
        change of velocity from one tick to the next) has no meaning between them, and
        applied with the velocity :meth:`step` last recorded it would make the answer
        depend on what ran before and cap every iterate near that velocity. ``solve``
        ignores it and neither reads nor changes its state (a :meth:`step` after ``solve``
        continues the motion of the steps before it); :meth:`stationarity` likewise.
        Position, velocity and the other limits apply.

        Args:
            q0: Initial chain configuration.
            pos_tol, rot_tol: Tolerances.
            max_iterations: Iteration budget.
            q_tol: Stop as ``"stalled"`` when the step taken, ``‖αΔq‖``, falls below it
                before converging.
            max_step: Optional trust region, ``|Δq_i| ≤ max_step`` per iteration.
            dt: Passed to the limits (velocity limits need it; acceleration limits are
                left out, above).
            lm_damping: Initial Levenberg–Marquardt scale ``μ`` (≥ 0).
            stationarity_tol: Bound on each lower level's projected gradient (units of
                that gradient: ``α w² (q − r)`` for a posture task), or None.
            patience, progress: Early stop for restarts: before level 0 converges, an
                iterate whose ``‖e‖²`` fell by less than the fraction ``progress`` over the
                last ``patience`` iterations is ``"stalled"`` (slow progress near a
                singularity or a limit rarely ends well; a restart is cheaper). None (the
                default) waits for the budget.
            plateau: Early stop for restarts, after one iteration: before level 0
                converges, a step that lowered ``‖e‖²`` by less than this fraction ends the
                attempt as ``"stalled"`` — the iterate has reached a plateau, typically a
                constrained stationary point of the error against a limit, which
                ``patience`` would only recognise ``patience`` iterations later. None (the
                default): no such stop.

        Returns:
            :class:`QPResult` with ``method="qp"``, the history and the lower levels'
            stationarity at ``q``.
        """
        q = _joint_vector(self.robot, q0, "q0").copy()
        for name, value in (("pos_tol", pos_tol), ("rot_tol", rot_tol), ("q_tol", q_tol)):
            non_negative(value, name)
        if stationarity_tol is not None:
            positive(stationarity_tol, "stationarity_tol")
        integer(max_iterations, "max_iterations")
        _check_dt(dt)
        if max_step is not None:
            positive(max_step, "max_step", allow_inf=True)
        non_negative(lm_damping, "lm_damping")
        integer(patience, "patience", 1, allow_none=True)
        # ‖e‖² must fall to this fraction in `patience` iterations
        required = 1.0 - fraction(progress, "progress")
        if plateau is not None and not (_is_real(plateau) and 0.0 < plateau < 1.0):
            raise InvalidInput(f"plateau must be in (0, 1) or None, got {plateau!r}")
        flat = 1.0 - (plateau or 0.0)  # ‖e‖² must fall below this fraction in one iteration
        if self._clip:
            q = self.robot.clip(self._wrapped(q))
        finish_lower = stationarity_tol is not None and len(self.levels) > 1 and self._targets
        history = [q.copy()]
        self._update(q)
        converged, error, position_error, rotation_error = self._level0_errors(pos_tol, rot_tol)
        errors = [error]
        stationarity: list[float] = []
        stationarity_at_q = False  # `stationarity` is that of the current q
        iterations = 0
        mu = lm_damping
        status = Status.MAX_ITERATIONS
        while True:
            # The state is at q here. Once level 0 converged, the objectives that measure
            # the lower levels' stationarity are also those of the next step: built once.
            objectives = kernel0 = None
            if converged and self._targets:
                if not finish_lower:
                    status = Status.CONVERGED
                    break
                objectives = self._assembly.objectives(self._state, self._configuration)
                kernel0 = self._kernel0(objectives)
                stationarity = self._stationarity(q, dt, objectives, kernel0)
                stationarity_at_q = True
                if max(stationarity) <= stationarity_tol:
                    status = Status.CONVERGED
                    break
            if iterations >= max_iterations:
                status = Status.CONVERGED if converged and self._targets else Status.MAX_ITERATIONS
                break
            dq = self._step(
                q,
                dt,
                max_step,
                mu * error * error if self._targets else 0.0,
                0.0,
                objectives,
                kernel0,
                second_order=True,
            )
            # Backtracking on the level-0 error: far from the target a full Gauss–Newton
            # step overshoots (into the limits, or into a two-point cycle). Scaling the
            # whole lexicographic Δq keeps every level's direction; q + αΔq stays in the
            # box for α ≤ 1. Without a level-0 target there is nothing to backtrack on.
            # Once converged, a step must keep level 0 converged (the lower levels move).
            # Limits linearised at q (collision distances) also reject a step that breaks
            # them at its end (redik.limits.limit.InequalityLimit.admits).
            alpha = 1.0
            while True:
                trial = self._wrapped(self.robot.integrate(q, alpha * dq))
                self._update(trial)
                result = self._level0_errors(pos_tol, rot_tol)
                admitted = all(limit.admits() for limit in self._admitting)
                accepted = admitted and (
                    not self._targets
                    or (result[0] if converged else (result[1] < error or result[0]))
                )
                if accepted or alpha <= _MIN_STEP_FRACTION:
                    break
                alpha *= 0.5
            if not accepted:
                self._update(q)  # no acceptable step along Δq: a (constrained) stationary point
                status = Status.CONVERGED if converged and self._targets else Status.STALLED
                break
            # A full step trusted the model: damp less; a cut step: damp more (Nielsen 1999).
            if mu > 0.0:
                mu = max(mu * 0.5, _MU_MIN) if alpha == 1.0 else min(mu * 8.0, _MU_MAX)
            q = trial
            stationarity_at_q = False
            iterations += 1
            history.append(q.copy())
            converged, error, position_error, rotation_error = result
            errors.append(error)
            if (
                patience is not None
                and not converged
                and iterations >= patience
                and error * error > required * errors[-1 - patience] ** 2
            ):
                status = Status.STALLED
                break
            if plateau is not None and not converged and error * error > flat * errors[-2] ** 2:
                status = Status.STALLED
                break
            if alpha * math.sqrt(float(dq @ dq)) < q_tol:
                # Without level-0 targets, a vanishing step converges.
                status = Status.CONVERGED if converged or not self._targets else Status.STALLED
                break
        if finish_lower and not stationarity_at_q:
            stationarity = self._stationarity(q, dt)
        stationary = not stationarity or max(stationarity) <= (stationarity_tol or np.inf)
        message = self._message(status, position_error, rotation_error, error)
        if status is Status.CONVERGED and not stationary:
            message = (
                f"level 0 converged; lower levels not stationary within {stationarity_tol:g} "
                f"(projected gradients {[float(f'{v:.3g}') for v in stationarity]})"
            )
        return QPResult(
            q=q,
            success=status is Status.CONVERGED,
            status=status,
            iterations=iterations,
            error=error,
            position_error=position_error,
            rotation_error=rotation_error,
            history=np.array(history),
            error_history=np.array(errors),
            method="qp",
            message=message,
            stationarity=stationarity,
            stationary=bool(stationary),
        )

    def _wrapped(self, q: np.ndarray) -> np.ndarray:
        """``q`` with the full-turn joints of periodic position limits turned into range."""
        for limit in self._wraps:
            q = limit.wrap(q)
        return q

    def stationarity(self, q: np.ndarray, dt: float | None = None) -> list[float]:
        r"""Per lower level, the norm of its projected gradient at ``q``.

        With :math:`g_k` the gradient of level :math:`k`'s objective at ``q`` (the linear
        term :math:`c_k` of its QP), :math:`N_{k-1}` an orthonormal basis of the directions
        the levels above leave free (the null spaces of their Hessians, as in
        :mod:`redik.qp.hierarchy`) and :math:`\mathcal{A}` the limits active at ``q``
        (bounds on ``Δq`` within 1e-9 of zero), the value is

        .. math:: \|P_{T}(-g_k)\|, \qquad
                  T = \{N_{k-1} z : a_i^\top N_{k-1} z \le 0,\ i \in \mathcal{A}\},

        the projection onto the tangent cone, computed through its dual, a non-negative
        least-squares problem (Lawson & Hanson's NNLS, ``scipy.optimize.nnls``). Zero is the
        first-order (KKT) condition of level :math:`k` subject to the higher levels and the
        limits (Nocedal & Wright, Theorem 12.1).
        """
        q = _joint_vector(self.robot, q, "q")
        _check_dt(dt)
        return self._stationarity(q, dt)

    def _kernel0(self, objectives) -> np.ndarray:
        """Orthonormal basis of level 0's null space at the state ``objectives`` were built
        at: from a QR of its rows when it is a least-squares level, else from its Hessian
        (:mod:`redik.qp.hierarchy`)."""
        N = None if self._rows0 is None else row_null_space(self._rows0, self.rank_tol)
        if N is None:
            N = kernel_directions(objectives[0][0], self.rank_tol, self.damping)
        return N

    def _stationarity(
        self, q: np.ndarray, dt: float | None, objectives=None, kernel0=None
    ) -> list[float]:
        """:meth:`stationarity`; with ``objectives`` (built at ``q``, the current state) and
        ``kernel0`` (:meth:`_kernel0` of them) nothing is recomputed."""
        if objectives is None:
            self._update(q)
            objectives = self._assembly.objectives(self._state, self._configuration)
        n = self.robot.dof
        # Active limits as rows a_i of a_i·Δq ≤ 0.
        active = []
        if self._static_boxes:
            lb, ub = np.full(n, -np.inf), np.full(n, np.inf)
            q_box = self.robot.scalar_values(q)
            for limit in self._static_boxes:
                limit.bounds_into(q_box, dt, lb, ub)
            at_lower, at_upper = lb >= -_ACTIVE_TOL, ub <= _ACTIVE_TOL
            if at_lower.any() or at_upper.any():
                eye = np.eye(n)
                active += [-eye[at_lower], eye[at_upper]]
        for limit in self._rows:
            block = limit.inequalities(self._configuration, dt)
            if block is not None:
                G, h = block
                active.append(G[h <= _ACTIVE_TOL])
        # A ranked limit binds the levels from its own down (violated rows count as active:
        # their bound on Δq is then the least violation the levels above left).
        ranked_active = []
        for _, index, limits, _ in self._ranked:
            G, h = self._ranked_rows(limits, None, q, dt)
            if G is not None:
                ranked_active.append((index, G[h <= _ACTIVE_TOL]))
        N = self._kernel0(objectives) if kernel0 is None else kernel0
        values = []
        last = len(objectives) - 1
        for level, (H_k, c_k) in enumerate(objectives[1:], start=1):
            if N.shape[1] == 0:
                values.append(0.0)
                continue
            rows_of_level = active + [G for index, G in ranked_active if index <= level]
            A = np.vstack(rows_of_level) if rows_of_level else None
            g = c_k @ N
            rows = None if A is None else A @ N
            if rows is None or rows.shape[0] == 0:
                values.append(math.sqrt(float(g @ g)))
            else:
                # P_T(−g) = argmin_{z: rows z ≤ 0} ½‖z + g‖² = −(g + rowsᵀλ) with λ the
                # non-negative least-squares solution of rowsᵀλ ≈ −g (its dual).
                multipliers, _ = nnls(rows.T, -g)
                values.append(float(np.linalg.norm(g + rows.T @ multipliers)))
            if level < last:
                HN = N.T @ H_k @ N
                N = N @ kernel_directions(HN, self.rank_tol, self.damping)
        return values

    def _level0_errors(self, pos_tol: float, rot_tol: float):
        converged = True
        squared = 0.0
        position_error = rotation_error = None
        for task, e, J, is_frame in self._target_buffers:
            if J is not None:
                task.residual_into(self._state, e, J)
            else:
                # A mink task asks for its cost-weighted error (mink's W = diag(cost)): a
                # component of zero cost (the height of a ComTask) is no part of its target.
                e = task.cost * task.compute_error(self._configuration)
            norm_squared = float(e @ e)
            squared += norm_squared
            if is_frame:
                p_err, r_err = task.pose_errors(self._state)
                if p_err is not None:
                    converged = converged and p_err <= pos_tol
                    position_error = p_err if position_error is None else max(position_error, p_err)
                if r_err is not None:
                    converged = converged and r_err <= rot_tol
                    rotation_error = r_err if rotation_error is None else max(rotation_error, r_err)
            else:
                converged = converged and math.sqrt(norm_squared) <= pos_tol
        return bool(converged), math.sqrt(squared), position_error, rotation_error

    @staticmethod
    def _message(status, position_error, rotation_error, error) -> str:
        if status is Status.CONVERGED:
            return ""
        parts = []
        if position_error is not None:
            parts.append(f"position error {position_error:.3g} m")
        if rotation_error is not None:
            parts.append(f"rotation error {rotation_error:.3g} rad")
        if not parts:
            parts.append(f"|e| = {error:.3g}")
        reason = (
            "the level-0 error stopped falling"
            if status is Status.STALLED
            else "the iteration budget ran out"
        )
        return f"{reason} with {', '.join(parts)} (limits may block the target)"

    def __repr__(self) -> str:
        names = [type(task).__name__ for task in self.tasks]
        return (
            f"Problem({self.robot!r}, tasks={names}, levels={self.levels}, "
            f"backend={self.backends[0].name!r})"
        )
