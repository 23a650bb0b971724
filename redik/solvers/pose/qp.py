"""``solve_pose_qp``: one pose target by the QP driver — what ``solve_pose(method="qp")`` runs.

A :class:`redik.Problem` with a :class:`~redik.tasks.pose_task.PoseTask` at level 0 (plus
any extra ``tasks`` at lower levels), the position box when ``respect_limits``, iterated
from ``q0`` (:meth:`redik.Problem.solve`).

**Bounded latency.** An attempt that stops making progress — ``‖e‖²`` not halved in
``patience`` iterations, the signature of a start that drifts into a singularity or
against a limit — ends early, and a restart takes over from the nearest in pose of
``candidates`` random configurations, by the distance
``‖p − p_d‖² + w²‖R − R_d‖²_F / 2 ≈ ‖p − p_d‖² + (w θ)²`` with ``w`` = 0.5 m per rad (as
:mod:`redik.solvers.batch`'s restarts), so few iterations are spent on hopeless starts. Each
attempt also has its own budget, ``max_iter``.

It lives in the solvers layer, in the pose package, and drives :mod:`redik.solvers.problem`
(its first home ``redik.qp.solve`` sat below ``problem`` and imported it: a cycle);
:mod:`redik.qp` is the QP core only.
"""

from __future__ import annotations

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import IKResult
from redik.kinematics.robot import Robot
from redik.solvers.problem import Problem
from redik.tasks.pose_task import PoseTask

_OPTIONS = (
    "backend",
    "damping",
    "tasks",
    "gain",
    "max_step",
    "backend_options",
    "q_tol",
    "stationarity_tol",
    "patience",
    "progress",
    "candidates",
    "lm_damping",
)

_ROTATION_SCALE = 0.5
"""Metres per radian in the pose distance that picks restart seeds."""


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
    (1e-9, the Hessian regularisation: 1e-6 slows the convergence to targets near a
    singularity — σ_min ≈ 2e-4 on some UR5e targets — to a linear rate of
    ``ε/(σ² + ε)`` ≈ 0.96), ``tasks`` (extra redik/mink tasks, e.g. a ``PostureTask`` at
    priority 1), ``gain`` of the pose task (1.0), ``max_step`` (trust region per
    iteration, rad or m; default 1.0), ``lm_damping`` (initial Levenberg–Marquardt scale,
    0.01), ``q_tol``, ``stationarity_tol`` (lower levels finished to this projected
    gradient, :meth:`redik.Problem.solve`; default 1e-8), ``patience`` and ``progress``
    (an attempt whose ``‖e‖²`` fell by less than the fraction ``progress`` in ``patience``
    iterations ends as stalled; defaults 5 and 0.5; ``patience=None`` waits for
    ``max_iter``), ``candidates`` (each restart starts from the nearest in pose of this
    many random configurations; default 16), ``backend_options``. The defaults are those
    that gave the shortest tail over 200 random targets per robot (panda, iiwa14, ur5e)
    from home and from random seeds (``redik bench qp``).

    Raises:
        InvalidInput: an unknown option or a bad target/``q0``.
    """
    unknown = sorted(set(options) - set(_OPTIONS))
    if unknown:
        raise InvalidInput(f"unknown options {unknown} for method='qp'; known: {list(_OPTIONS)}")
    candidates = options.get("candidates", 16)
    if (
        isinstance(candidates, bool)
        or not isinstance(candidates, int | np.integer)
        or candidates < 1
    ):
        raise InvalidInput(f"candidates must be an integer >= 1, got {candidates!r}")
    task = PoseTask(T_target, frame=frame, gain=options.get("gain", 1.0), priority=0)
    problem = Problem(
        robot,
        [task, *options.get("tasks", ())],
        limits=None if respect_limits else [],
        backend=options.get("backend", "daqp"),
        damping=options.get("damping", 1e-9),
        backend_options=options.get("backend_options"),
    )
    rng = np.random.default_rng(seed)
    best: IKResult | None = None
    iterations = 0
    for attempt in range(restarts + 1):
        start = q0 if attempt == 0 else _nearest_start(robot, task, rng, candidates)
        result = problem.solve(
            start,
            pos_tol=pos_tol,
            rot_tol=rot_tol,
            max_iter=max_iter,
            q_tol=options.get("q_tol", 1e-12),
            max_step=options.get("max_step", 1.0),
            stationarity_tol=options.get("stationarity_tol", 1e-8),
            patience=options.get("patience", 5),
            progress=options.get("progress", 0.5),
            lm_damping=options.get("lm_damping", 0.01),
        )
        iterations += result.iterations
        if best is None or result.success or result.error < best.error:
            best = result
            best.restarts = attempt
        if result.success:
            break
    best.iterations = iterations
    return best


def _nearest_start(robot: Robot, task, rng: np.random.Generator, candidates: int) -> np.ndarray:
    """The nearest in pose to ``task``'s target of ``candidates`` random configurations."""
    qs = robot.random_q(rng, size=candidates)
    if candidates == 1:
        return qs[0]
    poses = np.empty((candidates, 4, 4))
    for q, T in zip(qs, poses, strict=True):
        robot.update(q)  # forward kinematics only: robot.fk would also check and allocate
        robot.pose_into(task.frame, T)
    # ‖p − p_d‖² + w²‖R − R_d‖²_F / 2, and ‖R − R_d‖²_F = 4(1 − cos θ) ≈ 2θ²: (w θ)² near 0.
    target = task.target
    distance = np.sum((poses[:, :3, 3] - target[:3, 3]) ** 2, axis=1) + (
        0.5 * _ROTATION_SCALE**2
    ) * np.sum((poses[:, :3, :3] - target[:3, :3]) ** 2, axis=(1, 2))
    return qs[int(np.argmin(distance))]
