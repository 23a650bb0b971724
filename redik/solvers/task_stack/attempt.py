"""One attempt of :func:`~redik.solvers.task_stack.solve_problem`: a loop over three steps.

Each iteration takes one step, chosen by where the iterate is
(:mod:`~redik.solvers.task_stack.steps`):

==============================================  ============================================
where the iterate is                            step
==============================================  ============================================
level 0 not met, ``‖W e‖`` above                :func:`_approach`: descent — the damped
:data:`POLISH_ERROR`                            reach step, monotone; none acceptable raises
                                                ``μ`` eightfold (Levenberg–Marquardt)
descent stalled (``μ`` at its bound, or the     :func:`_escape`: the watchdog of Chamberlain,
best ``‖W e‖²`` not cut by :data:`PROGRESS` in  Powell, Lemaréchal & Pedersen (Math. Prog.
:data:`PATIENCE` iterations)                    Study 1982) — one undamped step taken
                                                whatever its merit, then undamped reach steps
                                                accepted against the largest of the last
                                                :data:`MEMORY` merits; a new best returns to
                                                descent, none in :data:`PATIENCE` ends the
                                                attempt ``stalled`` at its best point
level 0 not met, ``‖W e‖`` below                the polish step, else the reach step
:data:`POLISH_ERROR`
level 0 met                                     :func:`_optimise`: ``converged`` when every
                                                optimised level is stationary, else the
                                                optimise step; ``suboptimal`` when none is
                                                acceptable
==============================================  ============================================

A monotone descent walks into the basin of a constrained stationary point (an elbow bent
the wrong way against its limit) and then rejects the one step that would leave it; the
escape takes it. A non-monotone search from the first step would hurt where a monotone
descent converges: the watchdog keeps the descent and escapes only from a stall.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from redik.core.result import Status
from redik.qp.problem import Problem
from redik.solvers.task_stack.options import SolveOptions
from redik.solvers.task_stack.steps import (
    Point,
    measure,
    optimise_step,
    polish_step,
    reach_step,
    restore,
)

MEMORY = 8
"""Merits the non-monotone test of an escape compares with."""

PATIENCE = 10
"""Iterations in which the best ``‖W e‖²`` must fall by :data:`PROGRESS`."""

PROGRESS = 0.5
"""Fraction by which the best ``‖W e‖²`` must fall in :data:`PATIENCE` iterations."""

POLISH_ERROR = 1e-3
"""Level-0 error ``‖W e‖`` below which the polish step is tried first."""

MU_MIN, MU_MAX = 1e-9, 1e6
"""Bounds of the Levenberg–Marquardt scale ``μ`` of the descent."""


@dataclasses.dataclass
class Attempt:
    """How one attempt ended.

    Attributes:
        point: Its returned point: the last (level 0 met), else the best.
        status: ``converged``, ``suboptimal``, ``stalled`` or ``max_iterations``.
        iterations: Iterations taken.
        stationarity: The optimised levels' projected gradients at ``point`` (level 0 met).
        start: Where it started (:class:`~redik.solvers.task_stack.result.QPResult`).
        history: Its iterates, ``history[0]`` the start.
        errors: ``‖W e‖`` of each iterate.
    """

    point: Point
    status: Status
    iterations: int
    stationarity: list[float]
    start: str
    history: list[np.ndarray]
    errors: list[float]


@dataclasses.dataclass
class Search:
    """The memory of the approach to level 0 within one attempt.

    Attributes:
        merits: ``‖W e‖²`` of the iterates of the current escape (the non-monotone window).
        best: The best ``‖W e‖²`` after each iteration (the patience test).
        best_point: The iterate with the smallest ``‖W e‖²`` so far (what a failed attempt
            returns: an escape may end above it).
        mu: The Levenberg–Marquardt scale of the descent.
        escaping: Whether the attempt is in an escape.
        escapes: Whether a stalled descent may escape (not for a target beyond reach, whose
            answer is the least-squares minimum the descent finds).
        progress: The fraction the best merit must fall by in :data:`PATIENCE` iterations.
    """

    merits: list[float]
    best: list[float]
    best_point: Point
    mu: float
    escaping: bool = False
    escapes: bool = True
    progress: float = PROGRESS

    def record(self, point: Point) -> None:
        """Remember the iterate ``point``."""
        self.merits.append(point.merit)
        self.best.append(min(self.best[-1], point.merit))
        if point.merit < self.best_point.merit:
            self.best_point = point

    def stalled(self) -> bool:
        """The best ``‖W e‖²`` fell by less than ``progress`` in the last :data:`PATIENCE`."""
        if len(self.best) <= PATIENCE:
            return False
        return self.best[-1] > (1.0 - self.progress) * self.best[-1 - PATIENCE]


def run_attempt(
    problem: Problem, q: np.ndarray, start: str, options: SolveOptions, search_settings: dict
) -> Attempt:
    """Iterate from ``q`` until converged, suboptimal, stalled or out of iterations.

    Args:
        problem: The problem.
        q: The start.
        start: Its label.
        options: The solve's options.
        search_settings: ``escapes`` and ``progress`` of the :class:`Search`.

    Returns:
        The :class:`Attempt`.
    """
    point = measure(problem, q, options)
    search = Search([point.merit], [point.merit], point, options.lm_damping, **search_settings)
    history, errors = [point.q], [point.error]
    status, iterations = None, options.max_iterations
    for iteration in range(options.max_iterations):
        if point.converged:
            point, status = _optimise(problem, point, options)
        else:
            point, status = _approach(problem, point, search, options)
        if status is not None:
            iterations = iteration
            break
        search.record(point)
        history.append(point.q)
        errors.append(point.error)
    else:
        point, status = _out_of_iterations(problem, point, search, options)
    if point.q is not history[-1]:  # the returned point ends the history (a restored or best one)
        history.append(point.q)
        errors.append(point.error)
    stationarity = (point.stationarity or []) if point.converged else []
    return Attempt(point, status, iterations, stationarity, start, history, errors)


def _out_of_iterations(
    problem: Problem, point: Point, search: Search, options: SolveOptions
) -> tuple[Point, Status]:
    """The verdict when the budget ran out: on level 0, stationary or not; else the best point."""
    if not point.converged:
        return search.best_point, Status.MAX_ITERATIONS
    if options.stationarity_tol is None or not _optimised_levels(problem):
        return point, Status.CONVERGED
    if point.values is None:
        point = restore(problem, point, options)
    stationarity = _stationarity(problem, point, options)
    status = Status.CONVERGED if _stationary(stationarity, options) else Status.SUBOPTIMAL
    return point, status


def _optimise(problem: Problem, point: Point, options: SolveOptions) -> tuple[Point, Status | None]:
    """One iteration on level 0.

    ``converged`` when stationary, else an optimise step, or ``suboptimal`` when none is acceptable.
    """
    if options.stationarity_tol is None or not _optimised_levels(problem):
        return point, Status.CONVERGED  # level 0 met is all there is to ask
    if point.values is None:
        point = restore(problem, point, options)  # the first point on level 0
    stationarity = _stationarity(problem, point, options)
    if _stationary(stationarity, options):
        return point, Status.CONVERGED
    trial = optimise_step(problem, point, stationarity, options)
    return (point, Status.SUBOPTIMAL) if trial is None else (trial, None)


def _approach(
    problem: Problem, point: Point, search: Search, options: SolveOptions
) -> tuple[Point, Status | None]:
    """One iteration towards level 0 (module docstring): polish, descent or escape."""
    trial = polish_step(problem, point, options) if point.error <= POLISH_ERROR else None
    if trial is None and search.escaping:
        reference = max(search.merits[-MEMORY:])
        trial, _ = reach_step(problem, point, 0.0, reference, options)
    elif trial is None:
        trial, alpha = reach_step(problem, point, search.mu, point.merit, options)
        search.mu = _next_damping(search.mu, alpha)
        if trial is None and search.mu < MU_MAX:
            return point, None  # the next step is more damped
    if trial is not None and not search.stalled():
        if search.escaping and trial.merit < (1.0 - search.progress) * search.best_point.merit:
            search.escaping = False
        return trial, None
    if search.escaping or not search.escapes:
        return search.best_point, Status.STALLED
    return _escape(problem, search, options)


def _escape(problem: Problem, search: Search, options: SolveOptions) -> tuple[Point, Status | None]:
    """Start an escape from the best point.

    Its undamped QP step, taken in full when the limits admit it.
    """
    point = search.best_point
    dq = problem.static_step(point.q, options.dt, max_step=options.max_step)
    kick = measure(problem, problem.integrate(point.q, dq), options)
    if not kick.admitted:
        return point, Status.STALLED
    search.escaping = True
    search.merits = [point.merit, kick.merit]
    search.best = [point.merit]  # the patience of the escape counts from here
    return kick, None


def _stationarity(problem: Problem, point: Point, options: SolveOptions) -> list[float]:
    """The optimised levels' projected gradients at ``point`` (cached on it).

    The optimised levels' projected gradients at ``point`` (cached on it); none asked for with
    ``stationarity_tol=None``.
    """
    if options.stationarity_tol is None:
        return []
    if point.stationarity is None:
        point.stationarity = problem.stationarity(point.q, options.dt)
    return point.stationarity


def _optimised_levels(problem: Problem) -> int:
    """How many levels are optimised below level 0's targets (all of them without targets)."""
    return len(problem.levels) - (1 if problem.has_targets else 0)


def _stationary(stationarity: list[float], options: SolveOptions) -> bool:
    tol = options.stationarity_tol
    return not stationarity or (tol is not None and max(stationarity) <= tol)


def _next_damping(mu: float, alpha: float) -> float:
    """A full step trusted the model.

    Damp less; a cut one (``alpha < 1``) or none (``alpha = 0``): damp more (Nielsen 1999). ``μ =
    0`` (undamped) grows from :data:`MU_MIN` only when no step was found.
    """
    if alpha == 1.0:
        return max(mu * 0.5, MU_MIN) if mu > 0.0 else 0.0
    if mu == 0.0 and alpha > 0.0:
        return 0.0
    return min(max(mu, MU_MIN) * 8.0, MU_MAX)
