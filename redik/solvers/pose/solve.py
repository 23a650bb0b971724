"""The entry points :func:`solve_pose` and :func:`solve_all`.

Validation of the arguments, dispatch to a method, restarts, and whole-model robots solved on
their chains. The methods and their options are described in :mod:`redik.solvers.pose`.
``"dls"`` runs in :mod:`~redik.solvers.pose.dls_solver` (a call whose scalar arguments were
seen before skips the validation here: the compiled kernel checks the target and ``q0``),
``"newton"``, ``"transpose"`` and ``"hybrid"`` in :mod:`~redik.solvers.pose.attempt` (the loops
of :mod:`redik.solvers.iterative`), ``"qp"`` in :mod:`~redik.solvers.pose.qp`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from redik.core.result import IKResult, Status
from redik.core.rotation_policy import as_pose
from redik.core.validate import integer, positive
from redik.core.validate import seed as check_seed
from redik.kinematics.robot import Frame, Robot
from redik.lie import wrap_angle
from redik.solvers.pose.attempt import PoseProblem, attempt_of
from redik.solvers.pose.cache import PoseCache
from redik.solvers.pose.closed_form import closed_form_solutions
from redik.solvers.pose.dls_solver import fast_kernel_key, kernel_key
from redik.solvers.pose.frame import PoseFrame
from redik.solvers.pose.options import (
    MAX_ITERATIONS,
    OPTIONS,
    RESTARTS,
    check_flag,
    check_method,
    check_options,
)
from redik.solvers.pose.result import Outcome, finish, limits_message


def solve_pose(
    robot: Robot,
    T_target: np.ndarray,
    q0: np.ndarray | None = None,
    method: str = "dls",
    pos_tol: float = 1e-6,
    rot_tol: float = 1e-5,
    max_iterations: int | None = None,
    restarts: int | None = None,
    respect_limits: bool = True,
    seed: int | None = None,
    frame: str | Frame | None = None,
    strict: bool = False,
    diagnose_limits: bool = True,
    **method_options: Any,
) -> IKResult:
    """Joint values that put ``frame`` at ``T_target`` (see :mod:`redik.solvers.pose`).

    Args:
        robot: The robot. A whole-model robot (:mod:`redik.kinematics.robot`) is solved on its chain
            to ``frame`` (``robot.chain``), every other joint held at its value in ``q0``;
            ``q`` and ``history`` are then the whole robot's.
        T_target: Desired pose ``T_sd`` of ``frame`` in the world (4 × 4).
        q0: First initial guess; default ``robot.home``.
        method: One of :data:`~redik.solvers.pose.options.METHODS`.
        pos_tol: Position tolerance (m) on ``‖p_d − p‖``.
        rot_tol: Rotation tolerance (rad) on ``angle(Rᵀ R_d)``.
        max_iterations: Iterations per attempt; default
            :data:`~redik.solvers.pose.options.MAX_ITERATIONS` for the method.
        restarts: Random restarts after the first attempt; default
            :data:`~redik.solvers.pose.options.RESTARTS`.
        respect_limits: Keep every iterate inside the joint limits (see
            :mod:`redik.solvers.pose`).
        seed: Seed of the random restarts (an integer ≥ 0, for reproducible results), or
            None for fresh entropy.
        frame: Site or body to place; default the end-effector.
        strict: Refuse a near-rotation target instead of projecting it onto SO(3) with a
            warning (:mod:`~redik.core.rotation_policy`).
        diagnose_limits: On a failure with ``respect_limits`` (``"max_iterations"``,
            ``"stalled"``, or ``"unreachable"`` within the chain's reach), solve once more
            without the limits (same method, budget and seed, at most
            :data:`LIMITS_RESTARTS` restarts); if that converges outside the limits, the
            status is ``"limits"`` and the message names the joints at their limits and
            those the unconstrained solution puts outside. Paid on failure only; ``False``
            skips it (:func:`solve_all` does, its failed starts are discarded).
        **method_options: ``"dls"``: ``damping`` (initial μ), ``min_damping`` (λ_min),
            ``max_damping``, ``patience`` and ``progress`` (an attempt ends as stalled when
            ``‖e‖²`` fell by less than the fraction ``progress`` in ``patience`` iterations);
            ``"newton"``: ``form`` ("body" or "space"), ``step``, ``stop`` ("pose" or the
            textbook's "twist", see :mod:`redik.solvers.pose`);
            ``"transpose"``: ``step`` ("armijo" or a number); ``"hybrid"``: ``switch_error``;
            ``"qp"``: passed on to :func:`redik.solvers.pose.qp.solve_pose_qp`.

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
    # "dls" with scalar arguments already validated for this robot and frame (the settings
    # key records their types too, so that True never passes for 1): the target and q0 are
    # checked by the compiled call itself. Anything else, or a refusal there, takes the full
    # validation below, which names the fault.
    arguments = (
        pos_tol, rot_tol, max_iterations, restarts, respect_limits,
        type(pos_tol), type(rot_tol), type(max_iterations), type(restarts), type(respect_limits),
    )  # fmt: skip
    if (
        type(method) is str
        and method == "dls"
        and not method_options
        and type(diagnose_limits) is bool
    ):
        solver = PoseCache.known_dls(robot, frame)
        key = fast_kernel_key(seed)
        if solver is not None and key is not None:
            result = solver.solve(T_target, q0, key, arguments)
            if result is not None:
                if result.success or not respect_limits or not diagnose_limits:
                    return result
                return _diagnose_limits(
                    result, robot, T_target, q0, "dls", pos_tol, rot_tol, max_iterations, restarts,
                    seed, frame, {},
                )  # fmt: skip
    T_target = as_pose(T_target, "T_target", strict=strict)
    if not robot.is_chain:
        return _solve_on_chain(
            robot, T_target, q0, method=method, pos_tol=pos_tol, rot_tol=rot_tol,
            max_iterations=max_iterations, restarts=restarts, respect_limits=respect_limits,
            seed=seed, frame=frame, diagnose_limits=diagnose_limits, **method_options,
        )  # fmt: skip
    q_start = robot.home.copy() if q0 is None else robot.check_q(q0, "q0").copy()
    method = check_method(method)
    respect_limits = check_flag(respect_limits, "respect_limits")
    diagnose_limits = check_flag(diagnose_limits, "diagnose_limits")
    seed = check_seed(seed)
    pos_tol, rot_tol = (
        positive(pos_tol, "pos_tol", unit="m"),
        positive(rot_tol, "rot_tol", unit="rad"),
    )
    max_iterations = integer(
        MAX_ITERATIONS[method] if max_iterations is None else max_iterations, "max_iterations", 1
    )
    restarts = integer(RESTARTS[method] if restarts is None else restarts, "restarts", 0)
    resolved = robot.frame(frame)
    cache = PoseCache.of(robot)
    pose_frame = cache.frame(resolved)  # refuses a frame no joint moves

    if method == "qp":
        from redik.solvers.pose.qp import solve_pose_qp  # on use: the others need no QP stack

        result = solve_pose_qp(
            robot, T_target, q_start, pos_tol=pos_tol, rot_tol=rot_tol,
            max_iterations=max_iterations, respect_limits=respect_limits, frame=frame,
            restarts=restarts, seed=seed, **method_options,
        )  # fmt: skip
    else:
        result = _solve_chain(
            robot, T_target, q_start, method, pos_tol, rot_tol, max_iterations, restarts,
            respect_limits, seed, frame, resolved, cache, pose_frame, arguments, method_options,
        )  # fmt: skip
    if result.success or not respect_limits or not diagnose_limits:
        return result
    return _diagnose_limits(
        result, robot, T_target, q0, method, pos_tol, rot_tol, max_iterations, restarts, seed,
        frame, method_options,
    )  # fmt: skip


def _solve_chain(
    robot: Robot,
    T_target: np.ndarray,
    q_start: np.ndarray,
    method: str,
    pos_tol: float,
    rot_tol: float,
    max_iterations: int,
    restarts: int,
    respect_limits: bool,
    seed: int | None,
    frame: str | Frame | None,
    resolved: Frame,
    cache: PoseCache,
    pose_frame: PoseFrame,
    arguments: tuple,
    method_options: dict,
) -> IKResult:
    """:func:`solve_pose` of a chain by a method other than ``"qp"``, arguments validated."""
    check_options(method, method_options)
    if method == "dls":
        # Kept under the arguments as given (with the options and their types, as for the
        # scalars above: damping=True must not pass for an accepted damping=1).
        solver = cache.dls(resolved, frame)
        arguments += tuple(
            sorted((name, value, type(value)) for name, value in method_options.items())
        )
        settings = solver.prepare(
            arguments, pos_tol, rot_tol, max_iterations, restarts, respect_limits, method_options
        )
        result = solver.solve(
            np.array(T_target, order="C"), q_start, kernel_key(seed), arguments, settings
        )
        if result is None:  # cannot happen: every argument passed the checks above
            raise RuntimeError("the compiled dls solve refused validated arguments")
        return result
    problem = PoseProblem(robot, resolved, T_target, pos_tol, rot_tol, respect_limits)
    attempt = attempt_of(method, {**OPTIONS[method], **method_options}, problem, max_iterations)
    attempts = [attempt(problem.project(q_start))]
    reach = 0.0
    if attempts[0].status != Status.CONVERGED:
        reach = pose_frame.reach_excess(T_target[:3, 3])
        if reach > 0.0:
            restarts = min(restarts, 2)  # a closest q is all there is to find
        rng = np.random.default_rng(seed)
        for _ in range(restarts):
            attempts.append(attempt(problem.project(robot.random_q(rng))))
            if attempts[-1].status == Status.CONVERGED:
                break
    return finish(problem, Outcome.of(attempts, robot.lower, robot.upper), method, reach)


LIMITS_RESTARTS = 2
"""Restarts of the unconstrained solve that tells ``"limits"`` apart (:func:`solve_pose`)."""


def _diagnose_limits(
    result: IKResult,
    robot: Robot,
    T_target: np.ndarray,
    q0: np.ndarray | None,
    method: str,
    pos_tol: float,
    rot_tol: float,
    max_iterations: int | None,
    restarts: int | None,
    seed: int | None,
    frame: str | Frame | None,
    method_options: dict,
) -> IKResult:
    """``result``, a failure within the limits, as ``"limits"`` if the target lies outside them.

    Its status turns to ``"limits"`` when one unconstrained solve reaches the target outside
    the limits.

    A target beyond the chain's reach, or a failure that is not a budget spent, a stall or
    an unreachable stationary point (a divergence), keeps its status: no solve is run.
    Otherwise :func:`solve_pose` runs with ``respect_limits=False``, the same method,
    tolerances, budget and seed, ``q0`` and at most :data:`LIMITS_RESTARTS` restarts. It is a
    diagnosis, not a proof: a converged unconstrained ``q`` outside the limits shows the pose
    exists without them; a redundant arm may still have a posture inside that no attempt
    found. An unconstrained ``q`` inside the limits (after the 2π shifts) leaves the status.
    """
    if result.status not in (Status.MAX_ITERATIONS, Status.STALLED, Status.UNREACHABLE):
        return result
    pose_frame = PoseCache.of(robot).frame(robot.frame(frame))
    if pose_frame.reach_excess(np.asarray(T_target, dtype=float)[:3, 3]) > 0.0:
        return result
    budget = RESTARTS[method] if restarts is None else restarts
    free = solve_pose(
        robot, T_target, q0, method=method, pos_tol=pos_tol, rot_tol=rot_tol,
        max_iterations=max_iterations, restarts=min(budget, LIMITS_RESTARTS), respect_limits=False,
        seed=seed, frame=frame, **method_options,
    )  # fmt: skip
    if not free.success or robot.within_limits(free.q):
        return result
    result.status, result.message = Status.LIMITS, limits_message(robot, result, free.q)
    return result


def _solve_on_chain(
    robot: Robot, T_target: np.ndarray, q0: np.ndarray | None, frame, **options
) -> IKResult:
    """:func:`solve_pose` for a whole-model robot, on its chain to ``frame``.

    The other joints are held at ``q0`` (default ``home``); ``q`` and ``history`` are the
    robot's.
    """
    q_whole = robot.home.copy() if q0 is None else robot.check_q(q0, "q0").copy()
    chain, q_chain = PoseCache.of(robot).chain(robot.frame(frame), q_whole)
    result = solve_pose(chain, T_target, q_chain, **options)
    result.q = robot.embed(chain, result.q, q_whole)
    result.history = np.array([robot.embed(chain, row, q_whole) for row in result.history])
    return result


def solve_all(
    robot: Robot,
    T_target: np.ndarray,
    n_starts: int = 100,
    seed: int | None = None,
    method: str = "dls",
    pos_tol: float = 1e-6,
    rot_tol: float = 1e-5,
    max_iterations: int | None = None,
    respect_limits: bool = True,
    frame: str | Frame | None = None,
    cluster_tol: float = 1e-3,
    strict: bool = False,
    q0: np.ndarray | None = None,
    **method_options: Any,
) -> list[IKResult]:
    """The distinct solutions reached from ``n_starts`` starts: ``q0`` if given, then random.

    ``method="analytic"`` returns instead every solution of the robot's closed-form solver
    (:func:`redik.solvers.analytic.solver_for`: the subproblems of the class its screws
    belong to, or for a general 6R arm the Raghavan–Roth elimination), exact to rounding
    and complete, with no starts (:mod:`.closed_form`); ``n_starts``, ``seed``, tolerances
    and ``cluster_tol`` do not apply, and a robot with no closed form raises its
    ``ModelError``/``InvalidInput``.

    Each start is solved by :func:`solve_pose` without restarts; the successful results are
    clustered: two solutions are the same when every joint differs by at most
    ``cluster_tol`` (radians or metres), comparing angles modulo 2π for the revolute joints
    that may turn fully — every one with ``respect_limits=False`` (the limits play no part:
    ``q`` and ``q + 2π`` are one pose), those without limits or whose range spans a full turn
    otherwise. A redundant arm has a continuum of solutions: the list then samples it.

    On a whole-model robot (:mod:`redik.kinematics.robot`) the solutions are those of its chain to
    ``frame``, every other joint held at its value in ``q0`` (default ``robot.home``) — as
    :func:`solve_pose` holds them — and each ``q`` is the whole robot's.

    Returns:
        The successful results, one per cluster (the most accurate), ordered by
        ``‖log(T⁻¹ T_d)‖`` — empty when no start converged.
    """
    if not robot.is_chain:  # the chain to the frame, the other joints at q0 (else home)
        q_whole = robot.home.copy() if q0 is None else robot.check_q(q0, "q0").copy()
        chain, q_chain = PoseCache.of(robot).chain(robot.frame(frame), q_whole)
        results = solve_all(
            chain, T_target, n_starts, seed, method, pos_tol, rot_tol, max_iterations,
            respect_limits, None, cluster_tol, strict,
            None if q0 is None else q_chain, **method_options,
        )  # fmt: skip
        for result in results:
            result.q = robot.embed(chain, result.q, q_whole)
            result.history = np.array([robot.embed(chain, row, q_whole) for row in result.history])
        return results
    T_target = as_pose(T_target, "T_target", strict=strict)  # once, not per start
    if method == "analytic":
        return closed_form_solutions(robot, T_target, respect_limits, frame, method_options)
    n_starts = integer(n_starts, "n_starts", 1)
    cluster_tol = positive(cluster_tol, "cluster_tol")
    first = None if q0 is None else robot.check_q(q0, "q0")
    rng = np.random.default_rng(check_seed(seed))
    turning = robot.periodic if respect_limits else robot.revolute
    solutions: list[IKResult] = []
    for start in range(n_starts):
        q_start = first if start == 0 and first is not None else robot.random_q(rng)
        result = solve_pose(
            robot, T_target, q_start, method=method, pos_tol=pos_tol, rot_tol=rot_tol,
            max_iterations=max_iterations, restarts=0, respect_limits=respect_limits,
            frame=frame, diagnose_limits=False, **method_options,
        )  # fmt: skip
        if result.success:
            _cluster(solutions, result, turning, cluster_tol)
    return sorted(solutions, key=lambda r: r.error)


def _cluster(
    solutions: list[IKResult], result: IKResult, turning: np.ndarray, cluster_tol: float
) -> None:
    """Add ``result`` to ``solutions``, or let it replace the same solution if more accurate.

    Two solutions are the same when every joint differs by at most ``cluster_tol``, the
    ``turning`` joints' angles compared modulo 2π.
    """
    for index, known in enumerate(solutions):
        difference = result.q - known.q
        difference[turning] = wrap_angle(difference[turning])
        if np.max(np.abs(difference)) <= cluster_tol:
            if result.error < known.error:
                solutions[index] = result
            return
    solutions.append(result)
