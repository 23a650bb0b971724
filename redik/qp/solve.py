"""``solve_pose_qp``: one pose target by the QP driver — what ``solve_pose(method="qp")`` runs.

A :class:`redik.Problem` with a :class:`~redik.tasks.pose_task.PoseTask` at level 0 (plus
any extra ``tasks`` at lower levels), the position box when ``respect_limits``, iterated
from ``q0`` (:meth:`redik.Problem.solve`). Restarts are the caller's business.
"""

from __future__ import annotations

import numpy as np

from ..exceptions import InvalidInput
from ..result import IKResult
from ..robot import Robot

_OPTIONS = (
    "backend",
    "damping",
    "tasks",
    "gain",
    "max_step",
    "backend_options",
    "q_tol",
    "stationarity_tol",
)


def solve_pose_qp(
    robot: Robot,
    T_target: np.ndarray,
    q0: np.ndarray,
    *,
    pos_tol: float = 1e-6,
    rot_tol: float = 1e-5,
    max_iter: int = 100,
    respect_limits: bool = True,
    frame: str | None = None,
    restarts: int = 0,
    seed: int | np.random.Generator | None = None,
    **options,
) -> IKResult:
    """Drive ``frame`` (default the end-effector) to ``T_target`` from ``q0``.

    Options: ``backend`` (default ``"daqp"``; a list is a fallback chain), ``damping``
    (1e-6), ``tasks`` (extra redik/mink tasks, e.g. a ``PostureTask`` at priority 1),
    ``gain`` of the pose task (1.0), ``max_step`` (trust region per iteration, rad or m;
    default 0.5), ``q_tol``, ``stationarity_tol`` (lower levels finished to this projected
    gradient, :meth:`redik.Problem.solve`; default 1e-8), ``backend_options``.

    Raises:
        InvalidInput: an unknown option or a bad target/``q0``.
    """
    from ..problem import Problem
    from ..tasks.pose_task import PoseTask

    unknown = sorted(set(options) - set(_OPTIONS))
    if unknown:
        raise InvalidInput(f"unknown options {unknown} for method='qp'; known: {list(_OPTIONS)}")
    task = PoseTask(T_target, frame=frame, gain=options.get("gain", 1.0), priority=0)
    problem = Problem(
        robot,
        [task, *options.get("tasks", ())],
        limits=None if respect_limits else [],
        backend=options.get("backend", "daqp"),
        damping=options.get("damping", 1e-6),
        backend_options=options.get("backend_options"),
    )
    rng = np.random.default_rng(seed)
    best: IKResult | None = None
    iterations = 0
    for attempt in range(restarts + 1):
        start = q0 if attempt == 0 else robot.random_q(rng)
        result = problem.solve(
            start,
            pos_tol=pos_tol,
            rot_tol=rot_tol,
            max_iter=max_iter,
            q_tol=options.get("q_tol", 1e-12),
            max_step=options.get("max_step", 0.5),
            stationarity_tol=options.get("stationarity_tol", 1e-8),
        )
        iterations += result.iterations
        if best is None or result.success or result.error < best.error:
            best = result
            best.restarts = attempt
        if result.success:
            break
    best.iterations = iterations
    return best
