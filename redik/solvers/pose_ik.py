r"""Inverse kinematics of a :class:`~redik.kinematics.robot.Robot` to a pose target in SE(3).

:func:`solve_pose` validates its inputs once, then runs one of the iterations below in a
tight loop on preallocated buffers (one :meth:`Robot.kinematics` call — FK and world
Jacobian — per trial; ``"dls"`` entirely in compiled code), restarting from random
configurations when an attempt fails. Success is always decided by a fresh FK of the
returned ``q``: MuJoCo's, or for ``"dls"`` the compiled chain's (equal to MuJoCo's to 1e-12,
``tests/test_batch_kernel.py``; MuJoCo's again when ``q`` was shifted into the limits).
:func:`solve_all` collects the distinct solutions found from many starts. Frames, twist
order ``(v, ω)`` and Jacobian references are those of :mod:`redik.core.conventions`.

Methods
    ``"newton"``
        Modern Robotics' *IKinBody* (Lynch & Park §6.2.2): the body error twist
        ``V_b = log(T_sb⁻¹ T_sd)`` and ``q ← q + J_b⁺ V_b``. With ``form="space"`` it is the
        space form (*IKinSpace*), ``V_s = Ad_{T_sb} V_b`` and ``q ← q + J_s⁺ V_s``.
        Stopping rule (``stop``): ``"pose"`` (default) stops when ``‖p_d − p‖ ≤ pos_tol`` and
        ``angle(Rᵀ R_d) ≤ rot_tol`` — the success test of every method, so Newton stops as
        soon as the result is certain to succeed; ``"twist"`` is the book's rule
        (Algorithm IKinBody/IKinSpace): ``‖ω‖ ≤ ε_ω = rot_tol`` and ``‖v‖ ≤ ε_v = pos_tol`` of
        the error twist ``(v, ω)`` of the form in use. The two differ only in the linear
        part: ``Rᵀ(p_d − p) = (G(θ)/θ) v_b`` (MR §3.3.3, the exponential of se(3)), whose
        singular values are 1 (along the rotation axis) and ``2 sin(θ/2)/θ ≤ 1``, so
        ``‖p_d − p‖ ≤ ‖v_b‖``. The body twist rule is thus the stricter, by up to
        ``θ / (2 sin(θ/2)) ≤ π/2`` across the axis of the rotation error ``θ``: it mixes the
        rotation error into the position test, and ``‖v_s‖`` also grows with the distance
        of the frame from the world origin. The default is the pose rule because
        ``pos_tol`` and ``rot_tol`` then mean the same thing for every method; success is
        decided by the pose test with either rule.
    ``"transpose"``
        Gradient descent on ``½‖e‖²``, ``q ← q + α Jᵀ e``. ``step="armijo"`` (default)
        starts each line search at Buss's step ``α₀ = ⟨e, JJᵀe⟩ / ‖JJᵀe‖²`` (the minimiser
        along ``Jᵀe`` of the linearised error) and backtracks until the Armijo condition
        holds, so ``‖e‖`` never increases; a number is a constant ``α``.
    ``"hybrid"``
        Transpose (Armijo) steps while ``‖e‖ > switch_error`` (default 0.1), where the
        gradient is robust, then Newton steps ``q ← q + J⁺ e`` for quadratic terminal
        convergence; an increasing Newton step falls back to a gradient step.
    ``"dls"`` (default)
        Damped least squares / Levenberg–Marquardt (Wampler 1986; Nakamura & Hanafusa 1986;
        damping after Sugihara 2011):

        .. math:: Δq = J^T (J J^T + λ I)^{-1} e, \qquad λ = μ\,‖e‖^2 + λ_{min},

        with ``(JᵀJ + λI)⁻¹Jᵀe`` when ``n < 6``. A trial is accepted only when it lowers
        ``‖e‖`` (then ``μ`` shrinks), otherwise it is rejected and ``μ`` grows; an attempt
        that stops making progress ends early and a restart takes over, from the nearest
        in pose of ``candidates`` random configurations. The attempts and restarts run in
        the compiled kernel of :mod:`redik.kinematics.dls` — the same code as
        :func:`redik.solvers.batch.solve_batch` — on the robot's chain compiled once per frame.
    ``"qp"``
        Dispatched to :func:`redik.solvers.pose_qp.solve_pose_qp` (the QP core).

Error
    ``"transpose"``, ``"hybrid"`` and ``"dls"`` drive the world-frame error
    ``e = (p_d − p, log(R_d Rᵀ))`` whose Jacobian is MuJoCo's world Jacobian (``"world"``
    in :mod:`redik.core.conventions`) and whose two halves are exactly the reported position and
    rotation errors; ``"newton"`` drives the body (or space) twist. ``error_history`` holds
    ``‖e‖`` of the method's own error; ``result.error`` is always ``‖log(T⁻¹ T_d)‖``.

Limits
    With ``respect_limits=True`` every iterate stays inside the joint limits and random
    restarts are drawn inside them, so the returned ``q`` is inside the limits. ``"dls"``
    stops a joint that would leave its range at the limit and re-solves for the others
    (a clamping loop); a limited revolute joint whose range spans a full turn is wrapped by
    2π instead; the other methods project (``q ← clip(q + Δq)``). An attempt stuck against
    a limit ends early and a restart takes over. With ``respect_limits=False`` the
    iterations are the textbook ones and the limits are not part of success (the message
    says when ``q`` is outside). In both cases a revolute joint outside its range is
    finally shifted by a multiple of 2π when that brings it inside (the pose is unchanged).

Success
    Decided from the pose of the returned ``q``: ``‖p_d − p‖ ≤ pos_tol``,
    ``angle(Rᵀ R_d) ≤ rot_tol`` and, with ``respect_limits``, ``lower ≤ q ≤ upper``.
    A target farther from the first joint than the chain can reach, or one at which every
    attempt stops at the same non-zero error with a vanishing gradient ``Jᵀe``, is
    ``"unreachable"``; other failures are ``"max_iterations"`` (or ``"diverged"`` when
    every attempt hit a NaN). ``q`` is then the closest configuration found.
"""

from __future__ import annotations

import math
import secrets
from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np

from redik.core._validate import positive
from redik.core.exceptions import InvalidInput
from redik.core.result import IKResult
from redik.kinematics import dls as kernel
from redik.kinematics.chain import Chain
from redik.kinematics.dls import BatchOptions
from redik.kinematics.robot import Frame, Robot
from redik.lie import (
    adjoint,
    apply_inverse_v,
    as_pose,
    inverse,
    pose_errors,
    se3_log,
    so3_log,
    world_jacobian_to,
    wrap_angle,
)
from redik.solvers.iterative import armijo_backtrack

METHODS = ("newton", "transpose", "hybrid", "dls", "qp")
"""The methods of :func:`solve_pose`."""

MAX_ITER = {"newton": 100, "transpose": 2000, "hybrid": 200, "dls": 60, "qp": 200}
"""Default iteration budget per attempt, by method."""

RESTARTS = {"newton": 20, "transpose": 5, "hybrid": 20, "dls": 200, "qp": 20}
"""Default number of random restarts after the first attempt, by method."""

_DLS_OPTIONS = {
    name: getattr(BatchOptions, name)
    for name in ("damping", "min_damping", "max_damping", "patience", "progress", "candidates")
}
_NEWTON_OPTIONS = {"form": "body", "step": 1.0, "stop": "pose"}
_TRANSPOSE_OPTIONS = {"step": "armijo"}
_HYBRID_OPTIONS = {"switch_error": 0.1}
_OPTIONS = {
    "dls": _DLS_OPTIONS,
    "newton": _NEWTON_OPTIONS,
    "transpose": _TRANSPOSE_OPTIONS,
    "hybrid": _HYBRID_OPTIONS,
}

_ARMIJO_TRIALS = 30


# --------------------------------------------------------------------------------------
# Public API


def solve_pose(
    robot: Robot,
    T_target: np.ndarray,
    q0: np.ndarray | None = None,
    method: str = "dls",
    pos_tol: float = 1e-6,
    rot_tol: float = 1e-5,
    max_iter: int | None = None,
    restarts: int | None = None,
    respect_limits: bool = True,
    seed: int | np.random.Generator | None = None,
    frame: str | Frame | None = None,
    strict: bool = False,
    **method_options: object,
) -> IKResult:
    """Joint values that put ``frame`` at ``T_target`` (see the module docstring).

    Args:
        robot: The robot. A whole-model robot (:mod:`redik.kinematics.robot`) is solved on its chain
            to ``frame`` (``robot.chain``), every other joint held at its value in ``q0``;
            ``q`` and ``history`` are then the whole robot's.
        T_target: Desired pose ``T_sd`` of ``frame`` in the world (4 × 4).
        q0: First initial guess; default ``robot.home``.
        method: One of :data:`METHODS`.
        pos_tol: Position tolerance (m) on ``‖p_d − p‖``.
        rot_tol: Rotation tolerance (rad) on ``angle(Rᵀ R_d)``.
        max_iter: Iterations per attempt; default :data:`MAX_ITER` for the method.
        restarts: Random restarts after the first attempt; default :data:`RESTARTS`.
        respect_limits: Keep every iterate inside the joint limits (see the module docstring).
        seed: Seed (or generator) of the random restarts, for reproducible results.
        frame: Site or body to place; default the end-effector.
        strict: Refuse a near-rotation target instead of projecting it onto SO(3) with a
            warning (the tolerance policy of :mod:`redik.lie`).
        **method_options: ``"dls"``: ``damping`` (initial μ), ``min_damping`` (λ_min),
            ``max_damping``, ``patience`` and ``progress`` (an attempt ends as stalled when
            ``‖e‖²`` fell by less than the fraction ``progress`` in ``patience`` iterations);
            ``"newton"``: ``form`` ("body" or "space"), ``step``, ``stop`` ("pose" or the
            textbook's "twist", see the module docstring);
            ``"transpose"``: ``step`` ("armijo" or a number); ``"hybrid"``: ``switch_error``;
            ``"qp"``: passed on to :func:`redik.solvers.pose_qp.solve_pose_qp`.

    Returns:
        An :class:`~redik.core.result.IKResult`; ``restarts`` counts the attempts after the first,
        ``history`` is that of the returned attempt.

    Raises:
        InvalidPose: ``T_target`` is not a finite rigid transform (or not numbers at all).
        InvalidConfiguration: ``q0`` has the wrong length or is not finite.
        InvalidInput: unknown method or option, a non-positive tolerance or budget, or a
            ``frame`` that no joint of the chain moves (such as ``"world"``).
        UnknownFrame: ``frame`` names no site or body.
    """
    T_target = as_pose(T_target, "T_target", strict=strict)
    if not robot.is_chain:
        return _solve_on_chain(
            robot, T_target, q0, method=method, pos_tol=pos_tol, rot_tol=rot_tol,
            max_iter=max_iter, restarts=restarts, respect_limits=respect_limits, seed=seed,
            frame=frame, **method_options,
        )  # fmt: skip
    q_start = robot.home.copy() if q0 is None else robot.check_q(q0, "q0").copy()
    if not isinstance(method, str) or method not in METHODS:
        raise InvalidInput(f"method must be one of {METHODS}, got {method!r}")
    if not isinstance(respect_limits, bool | np.bool_):
        raise InvalidInput(f"respect_limits must be True or False, got {respect_limits!r}")
    _check_seed(seed)
    pos_tol, rot_tol = (
        positive(pos_tol, "pos_tol", unit="m"),
        positive(rot_tol, "rot_tol", unit="rad"),
    )
    max_iter = _count(MAX_ITER[method] if max_iter is None else max_iter, "max_iter", 1)
    restarts = _count(RESTARTS[method] if restarts is None else restarts, "restarts", 0)
    resolved = robot.frame(frame)
    frame_solver = _FrameSolver.of(robot, resolved)  # refuses a frame no joint moves

    if method == "qp":
        from redik.solvers.pose_qp import (
            solve_pose_qp,  # on use: the other methods need no QP stack
        )

        return solve_pose_qp(
            robot, T_target, q_start, pos_tol=pos_tol, rot_tol=rot_tol, max_iter=max_iter,
            respect_limits=respect_limits, frame=frame, restarts=restarts, seed=seed,
            **method_options,
        )  # fmt: skip

    if method_options:
        unknown = sorted(set(method_options) - set(_OPTIONS[method]))
        if unknown:
            raise InvalidInput(
                f"unknown option(s) {unknown} for method {method!r}; "
                f"it takes {sorted(_OPTIONS[method])}"
            )
    if method == "dls":
        return frame_solver.solve_dls(
            T_target, q_start, pos_tol, rot_tol, max_iter, restarts, respect_limits, seed,
            method_options,
        )  # fmt: skip
    options = {**_OPTIONS[method], **method_options}
    problem = _Problem(robot, resolved, T_target, pos_tol, rot_tol, respect_limits)
    q_start = problem.project(q_start)
    iterate = _ITERATIONS[method](options)
    attempts = [iterate(problem, q_start, max_iter)]
    reach = 0.0
    if attempts[0].status != "converged":
        reach = frame_solver.reach_excess(problem.p_d)
        if reach > 0.0:
            restarts = min(restarts, 2)  # a closest q is all there is to find
        rng = np.random.default_rng(seed)
        for _ in range(restarts):
            attempts.append(iterate(problem, problem.project(robot.random_q(rng)), max_iter))
            if attempts[-1].status == "converged":
                break
    return _finish(problem, _Outcome.of(attempts, robot.lower, robot.upper), method, reach)


def _solve_on_chain(
    robot: Robot, T_target: np.ndarray, q0: np.ndarray | None, frame, **options
) -> IKResult:
    """:func:`solve_pose` for a whole-model robot: on its chain to ``frame``, the other
    joints held at ``q0`` (default ``home``); ``q`` and ``history`` are the robot's."""
    q_whole = robot.home.copy() if q0 is None else robot.check_q(q0, "q0").copy()
    chain = _chain_of(robot, frame, q_whole)
    q_chain = chain.q_of()
    result = solve_pose(chain, T_target, q_chain, **options)
    result.q = robot.embed(chain, result.q, q_whole)
    result.history = np.array([robot.embed(chain, row, q_whole) for row in result.history])
    return result


def _chain_of(robot: Robot, frame, q_whole: np.ndarray) -> Robot:
    """``robot.chain(frame, q_whole)``, kept in ``robot.solver_cache`` while the joints it
    holds keep their values: its compiled solver (:class:`_FrameSolver`) bakes them in, and
    rebuilding both per call made a ``dls`` solve 17× slower than on the chain itself
    (2.2 ms vs 0.13 ms, left arm of ``tests/test_whole_model.py``'s torso; 0.40 ms kept)."""
    resolved = robot.frame(frame)
    qpos = robot.full_qpos(q_whole)
    key = ("pose_ik chain", resolved)
    cached = robot.solver_cache.get(key)
    if cached is not None:
        chain, held = cached
        if np.array_equal(np.delete(qpos, chain.qpos_indices), held):
            chain.data.qpos[:] = qpos
            return chain
    chain = robot.chain(resolved, q_whole)
    robot.solver_cache[key] = (chain, np.delete(qpos, chain.qpos_indices))
    return chain


def solve_all(
    robot: Robot,
    T_target: np.ndarray,
    n_starts: int = 100,
    seed: int | np.random.Generator | None = None,
    method: str = "dls",
    pos_tol: float = 1e-6,
    rot_tol: float = 1e-5,
    max_iter: int | None = None,
    respect_limits: bool = True,
    frame: str | Frame | None = None,
    cluster_tol: float = 1e-3,
    strict: bool = False,
    q0: np.ndarray | None = None,
    **method_options: object,
) -> list[IKResult]:
    """The distinct solutions reached from ``n_starts`` starts: ``q0`` if given, then random.

    ``method="analytic"`` returns instead every solution of the robot's closed-form solver
    (:func:`redik.solvers.analytic.solver_for`: a bundled family, the subproblem
    decomposition, or for a general 6R arm the Raghavan–Roth elimination), exact to rounding
    and complete, with no starts; ``n_starts``, ``seed``, tolerances and ``cluster_tol`` do
    not apply, and a robot with no closed form raises its ``ModelError``/``InvalidInput``.

    Each start is solved by :func:`solve_pose` without restarts; the successful results are
    clustered: two solutions are the same when every joint differs by at most
    ``cluster_tol`` (radians or metres), comparing angles modulo 2π for revolute joints
    without limits or whose range spans more than 2π. A redundant arm has a continuum of
    solutions: the list then samples it.

    On a whole-model robot (:mod:`redik.kinematics.robot`) the solutions are those of its chain to
    ``frame``, every other joint held at its value in ``q0`` (default ``robot.home``) — as
    :func:`solve_pose` holds them — and each ``q`` is the whole robot's.

    Returns:
        The successful results, one per cluster (the most accurate), ordered by
        ``‖log(T⁻¹ T_d)‖`` — empty when no start converged.
    """
    if not robot.is_chain:  # the chain to the frame, the other joints at q0 (else home)
        q_whole = robot.home.copy() if q0 is None else robot.check_q(q0, "q0").copy()
        chain = _chain_of(robot, frame, q_whole)
        results = solve_all(
            chain, T_target, n_starts, seed, method, pos_tol, rot_tol, max_iter,
            respect_limits, None, cluster_tol, strict,
            None if q0 is None else chain.q_of(), **method_options,
        )  # fmt: skip
        for result in results:
            result.q = robot.embed(chain, result.q, q_whole)
            result.history = np.array([robot.embed(chain, row, q_whole) for row in result.history])
        return results
    T_target = as_pose(T_target, "T_target", strict=strict)  # once, not per start
    if method == "analytic":
        return _closed_form_solutions(robot, T_target, respect_limits, frame, method_options)
    n_starts = _count(n_starts, "n_starts", 1)
    cluster_tol = positive(cluster_tol, "cluster_tol")
    first = None if q0 is None else robot.check_q(q0, "q0")
    rng = np.random.default_rng(seed)
    periodic = robot.revolute & ((robot.upper - robot.lower) >= 2.0 * np.pi)
    solutions: list[IKResult] = []
    for start in range(n_starts):
        q_start = first if start == 0 and first is not None else robot.random_q(rng)
        result = solve_pose(
            robot, T_target, q_start, method=method, pos_tol=pos_tol,
            rot_tol=rot_tol, max_iter=max_iter, restarts=0, respect_limits=respect_limits,
            frame=frame, **method_options,
        )  # fmt: skip
        if not result.success:
            continue
        for index, known in enumerate(solutions):
            difference = result.q - known.q
            difference[periodic] = np.abs(wrap_angle(difference[periodic]))
            if np.max(np.abs(difference)) <= cluster_tol:
                if result.error < known.error:
                    solutions[index] = result
                break
        else:
            solutions.append(result)
    return sorted(solutions, key=lambda r: r.error)


def _closed_form_solutions(
    robot: Robot,
    T_target: np.ndarray,
    respect_limits: bool,
    frame: str | Frame | None,
    options: dict[str, object],
) -> list[IKResult]:
    """:func:`solve_all` with ``method="analytic"``: every solution of the robot's
    closed-form solver (:func:`redik.solvers.analytic.solver_for`, kept in
    ``robot.solver_cache``), as results ordered by error like the numeric ones; ``message``
    carries the solver's family and the solution's label (and singularity, if any)."""
    from redik.solvers.analytic import solver_for  # on use: the numeric path needs none

    if options:
        raise InvalidInput(f"method 'analytic' takes no options, got {sorted(options)}")
    if frame is not None and robot.frame(frame) != robot.frame(None):
        raise InvalidInput(
            "method 'analytic' solves for the end-effector the closed-form solver was built "
            f"for, not {frame!r}"
        )
    solver = robot.solver_cache.get("analytic")
    if solver is None:
        solver = robot.solver_cache["analytic"] = solver_for(robot)
    solutions = solver(T_target, limits="robot" if respect_limits else None)
    method = f"analytic:{solver.family}"
    results = []
    for solution in solutions:
        q = np.array(solution, dtype=float)
        T = robot.fk(q)
        position_error, rotation_error = pose_errors(T, T_target)
        note = f"{solution.label}" + (
            f" (singular: {solution.singular})" if solution.singular else ""
        )
        results.append(
            IKResult(
                q=q,
                success=True,
                status="converged",
                iterations=0,
                error=float(np.linalg.norm(se3_log(inverse(T) @ T_target))),
                position_error=position_error,
                rotation_error=rotation_error,
                history=q[None].copy(),
                restarts=0,
                method=method,
                message=note,
            )
        )
    return sorted(results, key=lambda r: r.error)


# --------------------------------------------------------------------------------------
# The problem and one attempt


class _Problem:
    """A validated solve: target, tolerances and limits."""

    def __init__(
        self,
        robot: Robot,
        frame: Frame,
        T_target: np.ndarray,
        pos_tol: float,
        rot_tol: float,
        respect_limits: bool,
    ) -> None:
        self.robot = robot
        self.frame = frame
        self.T_target = T_target
        self.p_d = T_target[:3, 3].copy()
        self.R_d = T_target[:3, :3].copy()
        self.pos_tol = pos_tol
        self.rot_tol = rot_tol
        self.respect_limits = respect_limits
        self.lower = robot.lower
        self.upper = robot.upper
        self.n = robot.dof

    def project(self, q: np.ndarray) -> np.ndarray:
        """``q`` clipped into the limits when they are respected (a new array)."""
        return (
            np.clip(q, self.lower, self.upper) if self.respect_limits else np.array(q, dtype=float)
        )

    def world_error(self, T: np.ndarray, e: np.ndarray) -> tuple[float, float]:
        """Fill ``e = (p_d − p, log(R_d Rᵀ))``; return the position and rotation errors."""
        np.subtract(self.p_d, T[:3, 3], out=e[:3])
        e[3:] = so3_log(self.R_d @ T[:3, :3].T)
        return math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]), math.sqrt(
            e[3] * e[3] + e[4] * e[4] + e[5] * e[5]
        )

    def within(self, position_error: float, rotation_error: float) -> bool:
        return position_error <= self.pos_tol and rotation_error <= self.rot_tol


@dataclass
class _Attempt:
    """The outcome of one attempt from one start."""

    q: np.ndarray
    status: str  # "converged", "stalled", "max_iterations" or "diverged"
    history: list[np.ndarray]
    errors: list[float]
    error_sq: float  # ‖e‖² of the world error at q, to pick the closest attempt
    J: np.ndarray  # world Jacobian at q
    e: np.ndarray  # world error at q


Iteration = Callable[[_Problem, np.ndarray, int], _Attempt]


def _stationarity(attempt: _Attempt, lower: np.ndarray, upper: np.ndarray) -> float:
    """``‖Jᵀe‖`` without the components that push against an active joint limit."""
    g = attempt.J.T @ attempt.e
    g[(attempt.q <= lower) & (g < 0.0)] = 0.0
    g[(attempt.q >= upper) & (g > 0.0)] = 0.0
    return float(np.linalg.norm(g))


@dataclass
class _Outcome:
    """What :func:`_finish` needs from all the attempts of a solve."""

    q: np.ndarray  # of the returned attempt: the converged one, else the closest
    history: np.ndarray  # the returned attempt's iterates
    errors: np.ndarray  # and its ‖e‖
    iterations: int  # over every attempt
    attempts: int
    same_stationary_point: bool
    all_diverged: bool
    e: np.ndarray  # world error at q (by FK of q)
    position_error: float  # at q
    rotation_error: float

    @classmethod
    def of(cls, attempts: list[_Attempt], lower: np.ndarray, upper: np.ndarray) -> _Outcome:
        best = attempts[-1]
        if best.status != "converged":
            best = min(attempts, key=lambda attempt: attempt.error_sq)
        errors = np.sqrt([a.error_sq for a in attempts])
        gradients = np.array([_stationarity(a, lower, upper) for a in attempts])
        return cls(
            q=best.q,
            history=np.array(best.history),
            errors=np.array(best.errors),
            iterations=sum(len(attempt.history) - 1 for attempt in attempts),
            attempts=len(attempts),
            same_stationary_point=_same_stationary_point(
                len(attempts), errors.min(), errors.max(), bool(np.all(gradients <= 1e-4 * errors))
            ),
            all_diverged=all(attempt.status == "diverged" for attempt in attempts),
            e=best.e,
            position_error=float(np.linalg.norm(best.e[:3])),
            rotation_error=float(np.linalg.norm(best.e[3:])),
        )


# --------------------------------------------------------------------------------------
# Damped least squares (Levenberg–Marquardt), in the compiled kernel


class _FrameSolver:
    """What every solve placing one frame of one robot reuses, built on first use and kept
    in the robot's :attr:`~redik.kinematics.robot.Robot.solver_cache`: the joints that move the
    frame,
    its reach, and for ``"dls"`` the compiled chain, the kernel's settings arrays (validated
    by :class:`BatchOptions` once per combination of options) and the kernel's output
    buffers. A ``"dls"`` solve then validates its arguments once, makes one compiled call
    and allocates only its result."""

    def __init__(self, robot: Robot, frame: Frame) -> None:
        self.robot = robot
        self.frame = frame
        self.columns = _moving_columns(robot, frame)
        if self.columns.size == 0:
            raise InvalidInput(
                f"no joint of {robot.name!r} moves frame {frame.name!r} (the chain joints are "
                f"{list(robot.joint_names)}), so no q can place it; name a site or body "
                f"below one of them"
            )
        self.every_joint = self.columns.size == robot.dof
        self.origin, self.reach = _reach(robot, frame, self.columns)
        self._kernel_arrays: tuple | None = None
        self._buffers: tuple[np.ndarray, ...] = ()
        self._settings: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}

    @classmethod
    def of(cls, robot: Robot, frame: Frame) -> _FrameSolver:
        """The robot's solver for ``frame``, built on first use.

        Raises:
            InvalidInput: no joint of the robot's chain moves ``frame``.
        """
        key = ("pose_ik", frame)
        solver = robot.solver_cache.get(key)
        if solver is None:
            solver = robot.solver_cache[key] = cls(robot, frame)
        return solver  # type: ignore[return-value]

    def reach_excess(self, p_d: np.ndarray) -> float:
        """How far (m) ``p_d`` lies beyond the chain's reach (0 inside; see :func:`_reach`)."""
        if not math.isfinite(self.reach):
            return 0.0
        excess = math.dist(p_d.tolist(), self.origin) - self.reach
        return excess if excess > 1e-9 * max(1.0, self.reach) else 0.0

    def solve_dls(
        self,
        T_target: np.ndarray,
        q_start: np.ndarray,
        pos_tol: float,
        rot_tol: float,
        max_iter: int,
        restarts: int,
        respect_limits: bool,
        seed: int | np.random.Generator | None,
        options: dict,
    ) -> IKResult:
        """Every attempt in :func:`redik.kinematics.dls.solve_one`; the joints that do not move
        the frame stay at ``q_start``. Success is decided by the kernel's FK of the returned
        ``q`` (tested equal to MuJoCo's, ``tests/test_batch_kernel.py``); MuJoCo's only when
        ``q`` was shifted by 2π into the limits afterwards."""
        robot = self.robot
        arrays, (history, errors, q_chain, e) = self._compiled(max_iter)
        floats, counts = self._kernel_settings(
            pos_tol, rot_tol, max_iter, restarts, respect_limits, options
        )
        reach = self.reach_excess(T_target[:3, 3])
        if reach > 0.0:
            floats = floats.copy()
            floats[kernel.REACH] = reach
        if respect_limits and not self.every_joint:
            q_start = np.clip(q_start, robot.lower, robot.upper)  # the kernel clips its own
        start = q_start if self.every_joint else q_start[self.columns]
        status, iterations, used, length, summary = kernel.solve_one(
            arrays, T_target, start, _kernel_key(seed), floats, counts, q_chain, history,
            errors, e,
        )  # fmt: skip
        error_min, error_max, stationary, diverged, position_error, rotation_error, inside = summary
        if self.every_joint:
            q = q_chain.copy()
            path = history[1, :length].copy()
        else:
            q = q_start.copy()
            q[self.columns] = q_chain
            path = np.repeat(q[None], length, axis=0)
            path[:, self.columns] = history[1, :length]
        if not respect_limits:
            shifted = _shift_into_limits(robot, q)
            if shifted is not q:
                q, e = shifted, np.empty(6)
                problem = _Problem(robot, self.frame, T_target, pos_tol, rot_tol, False)
                T = np.eye(4)
                robot.kinematics(q, self.frame, T)
                position_error, rotation_error = problem.world_error(T, e)
            inside = robot.within_limits(q)
        success = (
            position_error <= pos_tol
            and rotation_error <= rot_tol
            and (inside or not respect_limits)
        )
        status, message = _verdict(
            success, inside, position_error, rotation_error, reach,
            _same_stationary_point(used + 1, error_min, error_max, stationary), diverged,
            used + 1, iterations,
        )  # fmt: skip
        return IKResult(
            q=q,
            success=success,
            status=status,
            iterations=iterations,
            error=_body_twist_norm(e),
            position_error=position_error,
            rotation_error=rotation_error,
            history=path,
            error_history=errors[1, :length].copy(),
            restarts=used,
            method="dls",
            message=message,
        )

    def _compiled(self, max_iter: int) -> tuple[tuple, tuple[np.ndarray, ...]]:
        """The kernel's chain arrays (compiled on first use) and output buffers
        ``(history, errors, q, e)``, the history long enough for ``max_iter``."""
        if self._kernel_arrays is None:
            chain = Chain.from_robot(self.robot, self.frame)
            self._kernel_arrays = chain.kernel_arrays()
        if not self._buffers or self._buffers[1].shape[1] < max_iter + 1:
            n = self.columns.size
            self._buffers = (
                np.empty((2, max_iter + 1, n)), np.empty((2, max_iter + 1)), np.empty(n),
                np.empty(6),
            )  # fmt: skip
        return self._kernel_arrays, self._buffers

    def _kernel_settings(
        self,
        pos_tol: float,
        rot_tol: float,
        max_iter: int,
        restarts: int,
        bounded: bool,
        options: dict,
    ) -> tuple[np.ndarray, np.ndarray]:
        """The kernel's settings arrays for these arguments, validated once."""
        key = (pos_tol, rot_tol, max_iter, restarts, bounded)
        if options:
            key += tuple(sorted(options.items()))
        settings = self._settings.get(key)
        if settings is None:
            if len(self._settings) >= 64:
                self._settings.clear()
            settings = BatchOptions(
                pos_tol=pos_tol, rot_tol=rot_tol, max_iterations=max_iter, restarts=restarts,
                **{**_DLS_OPTIONS, **options},
            ).kernel_settings(bounded)  # fmt: skip
            self._settings[key] = settings
        return settings


def _kernel_key(seed: int | np.random.Generator | None) -> np.uint64:
    """The kernel generator's 64-bit state from ``seed`` (reproducible for an int)."""
    if isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
        return np.uint64(int(seed) % 2**64)
    if seed is None:
        return np.uint64(secrets.randbits(64))
    return np.uint64(np.random.default_rng(seed).integers(2**63))


# --------------------------------------------------------------------------------------
# Newton–Raphson (Modern Robotics IKinBody / IKinSpace)


def _newton(options: dict) -> Iteration:
    form = options["form"]
    if form not in ("body", "space"):
        raise InvalidInput(f"form must be 'body' or 'space', got {form!r}")
    step = positive(options["step"], "step")
    stop = options["stop"]
    if stop not in ("pose", "twist"):
        raise InvalidInput(f"stop must be 'pose' or 'twist' (Modern Robotics' rule), got {stop!r}")

    def twist_and_jacobian(
        T: np.ndarray, J: np.ndarray, T_target: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        V_b = se3_log(inverse(T) @ T_target)  # body error twist, (v, ω)
        J_form = world_jacobian_to(form, J, T[:3, :3], T[:3, 3])
        return (V_b if form == "body" else adjoint(T) @ V_b), J_form

    def done(problem: _Problem, T: np.ndarray, V: np.ndarray) -> bool:
        if stop == "twist":  # ‖v‖ ≤ ε_v and ‖ω‖ ≤ ε_ω, V = (v, ω)
            return problem.within(float(np.linalg.norm(V[:3])), float(np.linalg.norm(V[3:])))
        return problem.within(*pose_errors(T, problem.T_target))

    def iterate(problem: _Problem, q: np.ndarray, max_iter: int) -> _Attempt:
        robot, frame, n = problem.robot, problem.frame, problem.n
        T, J, e = np.eye(4), np.empty((6, n)), np.empty(6)
        robot.kinematics(q, frame, T, J)
        V, J_form = twist_and_jacobian(T, J, problem.T_target)
        history, errors = [q.copy()], [float(np.linalg.norm(V))]
        status = "max_iterations"
        for _ in range(max_iter):
            if done(problem, T, V):
                status = "converged"
                break
            q_next = problem.project(q + step * (np.linalg.pinv(J_form) @ V))
            if not np.all(np.isfinite(q_next)):
                status = "diverged"
                break
            q = q_next
            robot.kinematics(q, frame, T, J)
            V, J_form = twist_and_jacobian(T, J, problem.T_target)
            history.append(q.copy())
            errors.append(float(np.linalg.norm(V)))
        else:
            if done(problem, T, V):
                status = "converged"
        problem.world_error(T, e)
        return _Attempt(q, status, history, errors, float(e @ e), J, e)

    return iterate


# --------------------------------------------------------------------------------------
# Jacobian transpose, and the transpose-then-Newton hybrid


def _transpose_step(
    problem: _Problem,
    q: np.ndarray,
    J: np.ndarray,
    e: np.ndarray,
    E: float,
    step: float | str,
    trial: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> tuple[np.ndarray, float] | None:
    """One gradient step ``q + α Jᵀe`` evaluated into ``trial = (T, J, e)``.

    Armijo (:func:`redik.solvers.iterative.armijo_backtrack`): start from Buss's
    ``α₀ = ⟨e, JJᵀe⟩/‖JJᵀe‖²`` and halve until ``‖e(q + αg)‖² ≤ ‖e‖² − 2cα‖g‖²``.
    Returns ``(q_new, ‖e_new‖²)``, or None when no trial decreases the error (or every
    trial is non-finite).
    """
    T_trial, J_trial, e_trial = trial
    g = J.T @ e
    slope = float(g @ g)
    last = [q]

    def squared_error_at(alpha: float) -> float:
        last[0] = problem.project(q + alpha * g)
        problem.robot.kinematics(last[0], problem.frame, T_trial, J_trial)
        problem.world_error(T_trial, e_trial)
        return float(e_trial @ e_trial)

    if step != "armijo":
        E_new = squared_error_at(step)
        return (last[0], E_new) if math.isfinite(E_new) else None
    Jg = J @ g
    curvature = float(Jg @ Jg)
    # The merit ‖e‖² = 2F has the slope ∇(‖e‖²)ᵀg = −2‖g‖² along g = Jᵀe.
    alpha, _ = armijo_backtrack(
        squared_error_at,
        E,
        -2.0 * slope,
        slope / curvature if curvature > 0.0 else 1.0,
        trials=_ARMIJO_TRIALS,
    )
    return None if alpha is None else (last[0], float(e_trial @ e_trial))


def _transpose(options: dict) -> Iteration:
    step = options["step"]
    if step != "armijo":
        step = positive(step, "step")

    def iterate(problem: _Problem, q: np.ndarray, max_iter: int) -> _Attempt:
        return _gradient_then_newton(problem, q, max_iter, step, switch_error=0.0)

    return iterate


def _hybrid(options: dict) -> Iteration:
    switch_error = positive(options["switch_error"], "switch_error")

    def iterate(problem: _Problem, q: np.ndarray, max_iter: int) -> _Attempt:
        return _gradient_then_newton(problem, q, max_iter, "armijo", switch_error)

    return iterate


def _gradient_then_newton(
    problem: _Problem, q: np.ndarray, max_iter: int, step: float | str, switch_error: float
) -> _Attempt:
    """Gradient steps while ``‖e‖ > switch_error``, Newton steps ``J⁺e`` below it."""
    robot, frame, n = problem.robot, problem.frame, problem.n
    T, J, e = np.eye(4), np.empty((6, n)), np.empty(6)
    trial = (np.eye(4), np.empty((6, n)), np.empty(6))
    robot.kinematics(q, frame, T, J)
    errors_now = problem.world_error(T, e)
    E = float(e @ e)
    history, errors = [q.copy()], [math.sqrt(E)]
    status = "max_iterations"
    for _ in range(max_iter):
        if problem.within(*errors_now):
            status = "converged"
            break
        stepped = None
        if E < switch_error**2:
            q_new = problem.project(q + np.linalg.pinv(J) @ e)
            T_new, J_new, e_new = trial
            robot.kinematics(q_new, frame, T_new, J_new)
            problem.world_error(T_new, e_new)
            E_new = float(e_new @ e_new)
            if E_new < E:
                stepped = q_new, E_new
        if stepped is None:
            stepped = _transpose_step(problem, q, J, e, E, step, trial)
        if stepped is None or not math.isfinite(stepped[1]):
            status = "stalled" if stepped is None else "diverged"
            break
        q, E = stepped
        (T, J, e), trial = trial, (T, J, e)
        errors_now = (float(np.linalg.norm(e[:3])), float(np.linalg.norm(e[3:])))
        history.append(q.copy())
        errors.append(math.sqrt(E))
    else:
        if problem.within(*errors_now):
            status = "converged"
    return _Attempt(q, status, history, errors, E, J, e)


_ITERATIONS: dict[str, Callable[[dict], Iteration]] = {
    "newton": _newton,
    "transpose": _transpose,
    "hybrid": _hybrid,
}


# --------------------------------------------------------------------------------------
# Finishing: success by the FK of the returned q, and the unreachable diagnosis


def _finish(problem: _Problem, outcome: _Outcome, method: str, reach: float) -> IKResult:
    robot = problem.robot
    q, e = _shift_into_limits(robot, outcome.q), outcome.e
    position_error, rotation_error = outcome.position_error, outcome.rotation_error
    if q is not outcome.q:
        T, e = np.eye(4), np.empty(6)
        robot.kinematics(q, problem.frame, T)
        position_error, rotation_error = problem.world_error(T, e)
    inside = robot.within_limits(q)
    success = problem.within(position_error, rotation_error) and (
        inside or not problem.respect_limits
    )
    status, message = _verdict(
        success, inside, position_error, rotation_error, reach,
        outcome.same_stationary_point, outcome.all_diverged, outcome.attempts,
        outcome.iterations,
    )  # fmt: skip
    return IKResult(
        q=q.copy(),
        success=success,
        status=status,
        iterations=outcome.iterations,
        error=_body_twist_norm(e),
        position_error=position_error,
        rotation_error=rotation_error,
        history=outcome.history,
        error_history=outcome.errors,
        restarts=outcome.attempts - 1,
        method=method,
        message=message,
    )


def _verdict(
    success: bool,
    inside: bool,
    position_error: float,
    rotation_error: float,
    reach: float,
    same_stationary_point: bool,
    all_diverged: bool,
    attempts: int,
    iterations: int,
) -> tuple[str, str]:
    """``(status, message)`` of a solve from what its attempts found (module docstring)."""
    if success:
        return "converged", "" if inside else "q is outside the joint limits (respect_limits=False)"
    closest = f"closest pose found: {position_error:.3g} m, {rotation_error:.3g} rad away"
    if reach > 0.0:
        return "unreachable", (
            f"the target is {reach:.3g} m beyond the reach of the chain from its first joint; "
            f"{closest}"
        )
    if same_stationary_point:
        return "unreachable", (
            f"all {attempts} attempts stopped at the same error with a vanishing "
            f"gradient Jᵀe; {closest}"
        )
    if all_diverged:
        return "diverged", f"every attempt produced NaN or inf; {closest}"
    return "max_iterations", (
        f"no attempt of {attempts} converged ({iterations} iterations); {closest}"
    )


def _body_twist_norm(e: np.ndarray) -> float:
    r"""``‖log(T⁻¹ T_d)‖`` from the world error ``e = (d, w) = (p_d − p, log(R_d Rᵀ))``.

    The body twist is ``ω_b = Rᵀ w`` and ``v_b = V(ω_b)⁻¹ Rᵀ d = Rᵀ V(w)⁻¹ d`` (``V`` is
    equivariant under rotation), so ``‖ξ_b‖² = ‖V(w)⁻¹ d‖² + ‖w‖²`` with
    ``V⁻¹`` of :func:`redik.lie.apply_inverse_v`.
    """
    dx, dy, dz, wx, wy, wz = e.tolist()
    vx, vy, vz = apply_inverse_v(wx, wy, wz, dx, dy, dz)
    return math.sqrt(vx * vx + vy * vy + vz * vz + wx * wx + wy * wy + wz * wz)


def _same_stationary_point(
    attempts: int, error_min: float, error_max: float, stationary: bool
) -> bool:
    """Every attempt (at least two) ended at one non-zero error (``error_min … error_max``
    within 1 %) with ``Jᵀe ≈ 0`` (``stationary``: ``‖Jᵀe‖ ≤ 1e-4 ‖e‖`` for each)."""
    return (
        attempts >= 2
        and math.isfinite(error_max)
        and error_min > 0.0
        and error_max <= 1.01 * error_min
        and stationary
    )


def _moving_columns(robot: Robot, frame: Frame) -> np.ndarray:
    """Where the joints that move ``frame`` (those on its path to the world) sit in ``q``."""
    model = robot.model
    body = int(model.site_bodyid[frame.id]) if frame.kind == "site" else frame.id
    path = set()
    while body > 0:
        path.add(body)
        body = int(model.body_parentid[body])
    joint_of_qpos = {int(adr): joint for joint, adr in enumerate(model.jnt_qposadr)}
    return np.array(
        [
            column
            for column, adr in enumerate(robot.qpos_indices)
            if int(model.jnt_bodyid[joint_of_qpos[int(adr)]]) in path
        ],
        dtype=int,
    )


def _reach(robot: Robot, frame: Frame, columns: np.ndarray) -> tuple[tuple[float, ...], float]:
    """``(a_1, r)``: no ``q`` puts ``frame`` farther than ``r`` from the first joint's anchor.

    The distance between the anchors of two consecutive hinges is constant (each hinge
    rotates everything after it about a line through its own anchor), so ``‖p − a_1‖`` is at
    most the sum of the anchor-to-anchor distances and the last anchor-to-frame distance,
    plus the full travel of every slide joint. Unlimited slides make the reach infinite.
    """
    model, data = robot.model, mujoco.MjData(robot.model)
    data.qpos[:] = robot.full_qpos(robot.midrange)
    mujoco.mj_kinematics(model, data)
    joint_of_qpos = {int(adr): joint for joint, adr in enumerate(model.jnt_qposadr)}
    joints = [joint_of_qpos[int(robot.qpos_indices[column])] for column in columns]
    anchors = data.xanchor[joints]
    point = data.site_xpos[frame.id] if frame.kind == "site" else data.xpos[frame.id]
    points = np.vstack((anchors, point))
    reach = float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))
    travel = (robot.upper - robot.lower)[columns][~robot.revolute[columns]]
    reach += float(np.sum(travel))  # inf for an unlimited slide
    return tuple(anchors[0].tolist()), reach


# --------------------------------------------------------------------------------------
# Small helpers


def _shift_into_limits(robot: Robot, q: np.ndarray) -> np.ndarray:
    """Revolute joints outside their range moved by the multiple of 2π that fits, if any.

    Returns ``q`` itself when no joint moved.
    """
    outside = robot.revolute & ((q < robot.lower) | (q > robot.upper))
    if not np.any(outside):
        return q
    q = q.copy()
    for i in np.flatnonzero(outside):
        shifted = robot.lower[i] + np.mod(q[i] - robot.lower[i], 2.0 * np.pi)
        if shifted <= robot.upper[i]:
            q[i] = shifted
    return q


def _check_seed(seed: object) -> None:
    """Refuse what ``np.random.default_rng`` would fail on deep inside a solve."""
    try:
        np.random.default_rng(seed)
    except (TypeError, ValueError) as error:
        raise InvalidInput(
            f"seed must be None, a non-negative integer or a numpy Generator, got {seed!r} "
            f"({error})"
        ) from None


def _count(value: object, name: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InvalidInput(f"{name} must be an integer ≥ {minimum}, got {value!r}")
    return int(value)
