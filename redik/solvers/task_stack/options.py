"""The settings of :func:`~redik.solvers.task_stack.solve_problem`, and their checks."""

from __future__ import annotations

import dataclasses

from redik.core.exceptions import InvalidInput
from redik.core.validate import integer, non_negative, positive
from redik.core.validate import seed as check_seed


@dataclasses.dataclass(frozen=True)
class SolveOptions:
    """How :func:`~redik.solvers.task_stack.solve_problem` iterates (checked when built).

    Attributes:
        pos_tol: Position tolerance (m) of every frame task of level 0 (and of ``‖W e‖`` of
            its other targets).
        rot_tol: Rotation tolerance (rad) of every frame task of level 0.
        max_iterations: Iterations per attempt.
        restarts: Attempts after the first, made while level 0 is not met.
        seed: Seed of every random draw (restarts, the warm start's own restarts): the same
            call gives the same answer; None draws fresh entropy.
        stationarity_tol: Bound on each lower level's projected gradient (the units of that
            gradient: ``α w² (q − r)`` for a posture task) for ``converged``; None stops once
            level 0 is met.
        lm_damping: Initial Levenberg–Marquardt scale ``μ`` of the reach steps
            (``λ = μ‖e‖²``).
        max_step: Optional trust region ``|Δq_i| ≤ max_step`` (rad or m) of every QP step.
        dt: The step duration handed to velocity limits (None without one).
        warm_start: Restart from the per-chain warm start (frame tasks at level 0), not from
            random draws alone.
    """

    pos_tol: float = 1e-6
    rot_tol: float = 1e-5
    max_iterations: int = 100
    restarts: int = 20
    seed: int | None = 0
    stationarity_tol: float | None = 1e-8
    lm_damping: float = 1e-2
    max_step: float | None = None
    dt: float | None = None
    warm_start: bool = True

    def __post_init__(self) -> None:
        non_negative(self.pos_tol, "pos_tol")
        non_negative(self.rot_tol, "rot_tol")
        integer(self.max_iterations, "max_iterations")
        integer(self.restarts, "restarts")
        check_seed(self.seed)
        if self.stationarity_tol is not None:
            positive(self.stationarity_tol, "stationarity_tol")
        non_negative(self.lm_damping, "lm_damping")
        if self.max_step is not None:
            positive(self.max_step, "max_step", allow_inf=True)
        if self.dt is not None:
            positive(self.dt, "dt", unit="s")
        if not isinstance(self.warm_start, bool):
            raise InvalidInput(f"warm_start must be True or False, got {self.warm_start!r}")
