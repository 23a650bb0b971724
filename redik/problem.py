r"""The optimisation driver: a robot, a stack of tasks and limits, one QP per step.

``problem.step(q, dt)`` returns the joint step :math:`Δq` for online control at a fixed
rate; ``problem.solve(q0)`` iterates :math:`q \leftarrow q + Δq` until the highest-priority
tasks converge. Each step runs forward kinematics once, fills preallocated per-level
objectives (:mod:`redik.qp.assembly`), intersects the box limits, and solves the levels
lexicographically (:mod:`redik.qp.hierarchy`) with the chosen back-end
(:mod:`redik.qp.backends`).

**Limits are never left.** The position box is shrunk by the back-end's tolerance and
:math:`q + Δq` is then clipped into the joint limits, so every configuration ``step`` leads
to and ``solve`` returns lies within them (:mod:`redik.limits.position_limit`).

**Whole models.** On a robot with ball or free joints (a floating base), ``q`` has
``robot.nq`` entries and ``Δq`` ``robot.dof`` (the tangent space): ``solve`` steps by
``robot.integrate(q, αΔq)`` (``mj_integratePos``) and joint-space tasks measure
``q ⊖ r`` by ``mj_differentiatePos``; pose tasks on several frames (two hands, the feet)
at any priorities (:mod:`redik.robot`). Limits linearised at ``q`` (collision distances)
are re-checked at the end of a step, which ``solve`` shortens until they hold.

mink tasks and limits may be mixed in; a ``mink.Configuration`` is then kept in sync with
``q`` (one more forward kinematics per step, paid only when one is present).
"""

from __future__ import annotations

from collections.abc import Sequence

import mink
import numpy as np

from .exceptions import InfeasibleProblem, InvalidInput
from .limits import BoxLimit, InequalityLimit, Limit, MinkLimit, PositionLimit
from .qp.assembly import Assembly
from .qp.backends import Backend, make_backend
from .qp.hierarchy import solve_lexicographic
from .result import IKResult
from .robot import Robot
from .tasks.frame_task import FrameTask
from .tasks.joint_space_task import JointSpaceTask
from .tasks.kinematics import KinematicState
from .tasks.task import ResidualTask, Task

_MIN_STEP_FRACTION = 1.0 / 64.0
"""Smallest fraction of a QP step ``solve`` tries before calling the iterate stalled."""

_MU_MIN, _MU_MAX = 1e-9, 1e6
"""Bounds of the adaptive Levenberg–Marquardt scale of ``solve``."""


class Problem:
    """Differential IK as a (hierarchical) QP over the joints ``robot`` moves.

    Args:
        robot: The robot; ``Δq`` has ``robot.dof`` entries (its tangent coordinates), a
            configuration ``q`` has ``robot.nq`` (see :mod:`redik.robot`).
        tasks: redik tasks and/or mink tasks (``mink.FrameTask``, ``mink.ComTask``…). Tasks
            of equal ``priority`` are weighted and summed; priorities are strict.
        limits: redik or mink limits; None is ``[PositionLimit()]``, ``[]`` is none.
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
        tasks = list(tasks)
        if not tasks:
            raise InvalidInput("a Problem needs at least one task")
        for task in tasks:
            if not hasattr(task, "compute_qp_objective"):
                raise InvalidInput(f"{task!r} is not a task (no compute_qp_objective)")
        if not (np.isfinite(damping) and damping >= 0.0):
            raise InvalidInput(f"damping must be finite and >= 0, got {damping}")
        if not (np.isfinite(step_damping) and step_damping >= 0.0):
            raise InvalidInput(f"step_damping must be finite and >= 0, got {step_damping}")
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
        tolerance = max(b.tolerance for b in self.backends)

        limits = [PositionLimit()] if limits is None else list(limits)
        self.limits: list[Limit] = []
        for limit in limits:
            if not isinstance(limit, Limit):
                if not hasattr(limit, "compute_qp_inequalities"):
                    raise InvalidInput(f"{limit!r} is not a limit")
                limit = MinkLimit(limit)
            self.limits.append(limit.bind(robot, tolerance))
        self._boxes = [limit for limit in self.limits if isinstance(limit, BoxLimit)]
        self._rows = [limit for limit in self.limits if isinstance(limit, InequalityLimit)]
        self._clip = any(isinstance(limit, PositionLimit) for limit in self.limits)
        self._bounded = bool(self._boxes)

        self.stats: dict[str, int] = {}
        self._shape = (robot.nq,)
        self._state = KinematicState.for_robot(robot)
        self._configuration = None
        if self._assembly.needs_configuration or any(r.needs_configuration for r in self._rows):
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
        Keep such a regulator's gain low (0.02 on that circle: no reversal) or put it at
        level 0 with a small weight.

        Raises:
            InfeasibleProblem: the limits admit no step (e.g. a joint outside its range
                by more than its velocity limit allows to recover in ``dt``).
            BackendError: the back-end (every back-end of a chain) failed.
        """
        q = np.asarray(q, dtype=float)
        if q.shape != self._shape or not np.isfinite(q).all():
            q = self.robot.check_q(q)  # raises with the full message
        if dt is not None and not (np.isfinite(dt) and dt > 0.0):
            raise InvalidInput(f"dt must be a positive number of seconds, got {dt}")
        self._update(q)
        return self._step(q, dt, error_damping=self.step_damping)

    def _update(self, q: np.ndarray) -> None:
        self._state.update(q)
        if self._configuration is not None:
            self._configuration.update(self.robot.data.qpos)

    def _step(
        self,
        q: np.ndarray,
        dt: float | None,
        max_step: float | None = None,
        lm_damping: float = 0.0,
        error_damping: float = 0.0,
    ):
        objectives = self._assembly.objectives(self._state, self._configuration)
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
        if self._boxes:
            q_box = self.robot.scalar_values(q)
            self._boxes[0].set_bounds(q_box, dt, lb, ub)
            for limit in self._boxes[1:]:
                limit.bounds_into(q_box, dt, lb, ub)
        if max_step is not None:
            np.maximum(lb, -max_step, out=lb)
            np.minimum(ub, max_step, out=ub)
        # One position box is never empty (bind shrinks it by at most a quarter range).
        if len(self._boxes) > 1 and (lb > ub).any():
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
        bounded = self._bounded or max_step is not None
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
        )
        if self._clip:
            # Into the (shrunk) box the solver was given: inside the limits, whatever its
            # tolerance.
            np.maximum(dq, lb, out=dq)
            np.minimum(dq, ub, out=dq)
        return dq

    # ----------------------------------------------------------------------------------
    # Iterative solve

    def solve(
        self,
        q0: np.ndarray,
        pos_tol: float = 1e-6,
        rot_tol: float = 1e-5,
        max_iter: int = 100,
        *,
        q_tol: float = 1e-12,
        max_step: float | None = None,
        dt: float | None = None,
        lm_damping: float = 0.1,
    ) -> IKResult:
        """Iterate ``q ← q + αΔq`` from ``q0`` until the priority-0 tasks converge.

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
        ``rot_tol`` (rad) — position and rotation errors of :mod:`redik.conventions` —
        and every other level-0 task that has a target (a mink task, say) with
        ``‖e‖ ≤ pos_tol``. Joint-space regularisers (posture, joint-limit avoidance,
        damping) and gradient tasks have no target and are not waited for, nor are
        lower levels: they shape the solution. With frame tasks on several frames (two
        hands, the feet) the reported position and rotation errors are the largest. With
        no target at level 0, the solve converges when the step taken vanishes
        (``‖αΔq‖ < q_tol``).

        Args:
            q0: Initial chain configuration.
            pos_tol, rot_tol: Tolerances.
            max_iter: Iteration budget.
            q_tol: Stop as ``"stalled"`` when the step taken, ``‖αΔq‖``, falls below it
                before converging.
            max_step: Optional trust region, ``|Δq_i| ≤ max_step`` per iteration.
            dt: Passed to the limits (velocity limits need it).
            lm_damping: Initial Levenberg–Marquardt scale ``μ`` (≥ 0).

        Returns:
            :class:`~redik.result.IKResult` with ``method="qp"`` and the history.
        """
        q = self.robot.check_q(q0, "q0").copy()
        if max_iter < 0:
            raise InvalidInput(f"max_iter must be >= 0, got {max_iter}")
        if max_step is not None and not max_step > 0.0:
            raise InvalidInput(f"max_step must be > 0, got {max_step}")
        if not (np.isfinite(lm_damping) and lm_damping >= 0.0):
            raise InvalidInput(f"lm_damping must be finite and >= 0, got {lm_damping}")
        if self._clip:
            q = self.robot.clip(q)
        history = [q.copy()]
        self._update(q)
        converged, error, position_error, rotation_error = self._level0_errors(pos_tol, rot_tol)
        errors = [error]
        status = "converged" if converged and self._targets else "max_iterations"
        iterations = 0
        mu = lm_damping
        while status == "max_iterations" and iterations < max_iter:
            dq = self._step(q, dt, max_step, mu * error * error if self._targets else 0.0)
            # Backtracking on the level-0 error: far from the target a full Gauss–Newton
            # step overshoots (into the limits, or into a two-point cycle). Scaling the
            # whole lexicographic Δq keeps every level's direction; q + αΔq stays in the
            # box for α ≤ 1. Without a level-0 target there is nothing to backtrack on.
            # Limits linearised at q (collision distances) also reject a step that breaks
            # them at its end (redik.limits.limit.InequalityLimit.admits).
            alpha = 1.0
            while True:
                trial = self.robot.integrate(q, alpha * dq)
                self._update(trial)
                result = self._level0_errors(pos_tol, rot_tol)
                admitted = all(limit.admits() for limit in self._rows)
                if admitted and (not self._targets or result[1] < error or result[0]):
                    break
                if alpha <= _MIN_STEP_FRACTION:
                    break
                alpha *= 0.5
            if not admitted or (self._targets and not (result[1] < error or result[0])):
                self._update(q)  # no descent along Δq: q is a (constrained) stationary point
                status = "stalled"
                break
            # A full step trusted the model: damp less; a cut step: damp more (Nielsen 1999).
            if mu > 0.0:
                mu = max(mu * 0.5, _MU_MIN) if alpha == 1.0 else min(mu * 8.0, _MU_MAX)
            q = trial
            iterations += 1
            history.append(q.copy())
            converged, error, position_error, rotation_error = result
            errors.append(error)
            if converged and self._targets:
                status = "converged"
            elif alpha * float(np.linalg.norm(dq)) < q_tol:
                # Without level-0 targets, a vanishing step is convergence.
                status = "stalled" if self._targets else "converged"
        return IKResult(
            q=q,
            success=status == "converged",
            status=status,
            iterations=iterations,
            error=error,
            position_error=position_error,
            rotation_error=rotation_error,
            history=np.array(history),
            error_history=np.array(errors),
            method="qp",
            message=self._message(status, position_error, rotation_error, error),
        )

    def _level0_errors(self, pos_tol: float, rot_tol: float):
        converged = True
        squared = 0.0
        position_error = rotation_error = None
        for task in self._targets:
            if isinstance(task, ResidualTask):
                e, _ = task.error_and_jacobian(self._state)
            else:
                e = task.compute_error(self._configuration)
            squared += float(e @ e)
            if isinstance(task, FrameTask):
                p_err, r_err = task.pose_errors(self._state)
                if p_err is not None:
                    converged &= p_err <= pos_tol
                    position_error = p_err if position_error is None else max(position_error, p_err)
                if r_err is not None:
                    converged &= r_err <= rot_tol
                    rotation_error = r_err if rotation_error is None else max(rotation_error, r_err)
            else:
                converged &= float(np.linalg.norm(e)) <= pos_tol
        return bool(converged), float(np.sqrt(squared)), position_error, rotation_error

    @staticmethod
    def _message(status, position_error, rotation_error, error) -> str:
        if status == "converged":
            return ""
        parts = []
        if position_error is not None:
            parts.append(f"position error {position_error:.3g} m")
        if rotation_error is not None:
            parts.append(f"rotation error {rotation_error:.3g} rad")
        if not parts:
            parts.append(f"|e| = {error:.3g}")
        reason = (
            "no step lowers the level-0 error"
            if status == "stalled"
            else "the iteration budget ran out"
        )
        return f"{reason} with {', '.join(parts)} (limits may block the target)"

    def __repr__(self) -> str:
        names = [type(task).__name__ for task in self.tasks]
        return (
            f"Problem({self.robot!r}, tasks={names}, levels={self.levels}, "
            f"backend={self.backends[0].name!r})"
        )
