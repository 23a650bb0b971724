"""The driver :func:`solve_problem` and the verdict of its attempts."""

from __future__ import annotations

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import Status
from redik.qp.problem import Problem
from redik.solvers.cache import solver_cache
from redik.solvers.pose.frame import PoseFrame
from redik.solvers.task_stack.attempt import Attempt, run_attempt
from redik.solvers.task_stack.options import SolveOptions
from redik.solvers.task_stack.result import QPResult
from redik.solvers.task_stack.starts import Chains, next_start
from redik.solvers.task_stack.steps import error_gradient

RESTARTS_BEYOND_REACH = 2
"""Restarts when a target lies beyond its chain's reach (:func:`redik.solve_pose`'s)."""

PROGRESS_BEYOND_REACH = 1e-3
"""The fraction the best merit must fall by in an attempt at a target beyond reach: only the
closest stretched posture is left to find, so a descent goes on until it stops falling."""

SAME_ERROR = 0.01
"""Attempts whose errors lie within this fraction of each other stopped at the same error."""

VANISHING_GRADIENT = 1e-4
"""A projected gradient of ``½‖W e‖²`` within this times ``‖W e‖`` vanishes."""


def solve_problem(
    problem: Problem, q0: np.ndarray, options: SolveOptions | None = None
) -> QPResult:
    r"""Solve ``problem``'s whole task stack from ``q0``: reach level 0, then optimise the rest.

    The lexicographic nonlinear program (Kanoun, Lamiraux & Wieber, IEEE T-RO 2011)

    .. math::

        \min_q f_K(q) \;\text{ s.t. }\; \dots \;\text{ s.t. }\; \min_q f_1(q)
        \;\text{ s.t. }\; e_0(q) = 0,\quad q \in \mathcal{Q},

    level 0's targets first, then every lower level in the set the levels above and the
    limits :math:`\mathcal{Q}` leave. Each attempt is one loop of reach, polish and optimise
    steps (:mod:`~redik.solvers.task_stack.attempt`); while level 0 is not met, seeded
    restarts alternate the per-chain warm start and random draws through it
    (:mod:`~redik.solvers.task_stack.starts`). A target beyond its chain's reach gets at most
    :data:`RESTARTS_BEYOND_REACH` restarts, each a descent to the closest stretched posture.

    Level 0's targets are its frame, position, orientation, equality and mink tasks; a
    regulariser beside them at priority 0 (a posture) shapes the steps but is not optimised
    once the targets are met — put it at priority 1 to have it finished. A level 0 without
    targets is optimised like the lower levels.

    Args:
        problem: The tasks and limits (:class:`redik.Problem`); only its steps are used.
        q0: The first start (``robot.nq``,), clipped into the limits.
        options: How to iterate; default :class:`SolveOptions()`.

    Returns:
        A :class:`~redik.solvers.task_stack.result.QPResult` with ``method="qp"``: the first
        attempt that meets level 0 (finished on the lower levels), else the attempt with the
        smallest level-0 error. Its status: ``converged`` (level 0 met, every optimised level
        stationary), ``suboptimal`` (level 0 met, a lower level not stationary within the
        budget or no step lowers it), ``unreachable`` (a target beyond its chain's reach, or
        every attempt stopped at the same error with a vanishing projected gradient),
        ``stalled`` (neither the descent nor its escape lowered the error), else
        ``max_iterations``.

    Raises:
        InvalidInput: ``problem`` or ``options`` of the wrong type.
        InvalidConfiguration: ``q0`` has the wrong shape or non-finite entries.
    """
    if not isinstance(problem, Problem):
        raise InvalidInput(f"problem must be a redik.Problem, got {type(problem).__name__}")
    options = SolveOptions() if options is None else options
    if not isinstance(options, SolveOptions):
        raise InvalidInput(f"options must be a SolveOptions, got {type(options).__name__}")
    q = problem.clip(problem.robot.check_q(q0, "q0"))
    problem.reset_backends()  # the same call gives the same answer, whatever ran before
    beyond = beyond_reach(problem)
    restarts, settings = options.restarts, {}
    if beyond:
        restarts = min(restarts, RESTARTS_BEYOND_REACH)
        settings = {"escapes": False, "progress": PROGRESS_BEYOND_REACH}
    attempts = [run_attempt(problem, q, "q0", options, settings)]
    rng = np.random.default_rng(options.seed)
    chains = None
    for _ in range(restarts):
        last = attempts[-1]
        if last.point.converged:
            break
        if chains is None and options.warm_start:
            chains = Chains(problem, options, solve_problem)
        start, label = next_start(problem, chains, last.point.q, last.start, rng)
        attempts.append(run_attempt(problem, start, label, options, settings))
    return _result(problem, attempts, beyond, options)


def beyond_reach(problem: Problem) -> tuple[str, float] | None:
    """The first frame target beyond its chain's reach: ``(frame, excess in m)``, or None.

    Only a robot without ball or free joints is tested (a floating base reaches anywhere);
    the bound is :func:`redik.solve_pose`'s (:class:`~redik.solvers.pose.frame.PoseFrame`).
    """
    robot = problem.robot
    if not robot.flat:
        return None
    for task in problem.frame_tasks:
        target = getattr(task, "target", None)
        if target is None or np.ndim(target) not in (1, 2):
            continue
        p_d = np.asarray(target)[:3, 3] if np.ndim(target) == 2 else np.asarray(target)
        if p_d.shape != (3,) or not robot.moves(task.frame):
            continue
        excess = _reach(robot, task.frame).reach_excess(p_d)
        if excess > 0.0:
            return task.frame.name, excess
    return None


def _reach(robot, frame) -> PoseFrame:
    """The frame's reach bound, kept while the joints the robot holds keep their values."""
    held = robot.full_qpos(robot.home).tobytes()
    entry = solver_cache(robot).get_or_build(
        ("task_stack.reach", frame),
        lambda: (held, PoseFrame(robot, frame)),
        lambda entry: entry[0] == held,
    )
    return entry[1]


def _result(problem: Problem, attempts: list[Attempt], beyond, options: SolveOptions) -> QPResult:
    last = attempts[-1]
    winner = last if last.point.converged else min(attempts, key=lambda a: a.point.merit)
    point = winner.point
    status, message = _verdict(problem, winner, attempts, beyond, options)
    return QPResult(
        q=point.q.copy(),
        success=point.converged,
        status=status,
        iterations=sum(attempt.iterations for attempt in attempts),
        error=point.error,
        position_error=point.position_error,
        rotation_error=point.rotation_error,
        history=np.array(winner.history),
        error_history=np.array(winner.errors),
        restarts=len(attempts) - 1,
        method="qp",
        message=message,
        stationarity=winner.stationarity,
        stationary=_stationary(problem, winner, options),
        start=winner.start,
    )


def _stationary(problem: Problem, winner: Attempt, options: SolveOptions) -> bool:
    """Level 0 met and every optimised level known to be stationary (trivially without one)."""
    if not winner.point.converged:
        return False
    optimised = len(problem.levels) - (1 if problem.has_targets else 0)
    if optimised == 0:
        return True
    if options.stationarity_tol is None:
        return False
    return max(winner.stationarity) <= options.stationarity_tol


def _verdict(
    problem: Problem, winner: Attempt, attempts: list[Attempt], beyond, options: SolveOptions
) -> tuple[Status, str]:
    """The status and message of the returned attempt (the rules of :func:`solve_problem`).

    Joints at their limits are named only when the problem holds the joint ranges and they
    are at them.
    """
    if winner.status is Status.CONVERGED:
        return Status.CONVERGED, ""
    if winner.status is Status.SUBOPTIMAL:
        gradients = [float(f"{value:.3g}") for value in winner.stationarity]
        return Status.SUBOPTIMAL, (
            f"level 0 is met; a lower level is not stationary within "
            f"{options.stationarity_tol:g} (projected gradients {gradients})"
        )
    where = _closest(winner)
    blocked = _joints_at_limits(problem, winner.point.q)
    tail = f"; {', '.join(blocked)} at their limits" if blocked else ""
    if beyond:
        frame, excess = beyond
        return Status.UNREACHABLE, (
            f"the target of {frame!r} is {excess:.3g} m beyond the reach of its chain; {where}"
        )
    if _same_stationary_point(problem, attempts, options):
        return Status.UNREACHABLE, (
            f"all {len(attempts)} attempts stopped at the same error with a vanishing "
            f"projected gradient (a stationary point of the error); {where}{tail}"
        )
    reason = (
        "the error stopped falling" if winner.status is Status.STALLED else "the budget ran out"
    )
    return winner.status, f"{reason} in each of {len(attempts)} attempts; {where}{tail}"


def _same_stationary_point(problem: Problem, attempts: list[Attempt], options) -> bool:
    """Whether every attempt stopped at one error with a vanishing projected gradient.

    At least two attempts, all ending within :data:`SAME_ERROR` of one non-zero error, each with a
    vanishing projected gradient of ``½‖W e‖²``.
    """
    errors = [attempt.point.error for attempt in attempts]
    if len(attempts) < 2 or min(errors) <= 0.0 or max(errors) > (1.0 + SAME_ERROR) * min(errors):
        return False
    return all(
        error_gradient(problem, attempt.point.q, options)
        <= VANISHING_GRADIENT * attempt.point.error
        for attempt in attempts
    )


def _closest(attempt: Attempt) -> str:
    point = attempt.point
    parts = []
    if point.position_error is not None:
        parts.append(f"{point.position_error:.3g} m")
    if point.rotation_error is not None:
        parts.append(f"{point.rotation_error:.3g} rad")
    return f"closest: {', '.join(parts) or f'‖W e‖ = {point.error:.3g}'} away"


def _joints_at_limits(problem: Problem, q: np.ndarray) -> list[str]:
    """Names of the joints within 1e-6 of a range the problem holds (none without one)."""
    if not problem.limited:
        return []
    robot = problem.robot
    values = robot.scalar_values(q)
    near = (values <= robot.lower + 1e-6) | (values >= robot.upper - 1e-6)
    return [robot.dof_names[i] for i in np.flatnonzero(near)]
