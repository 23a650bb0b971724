"""``solve_pose_qp``: one pose target by the QP driver — what ``solve_pose(method="qp")`` runs.

A :class:`redik.Problem` with a :class:`~redik.tasks.frame_task.FrameTask` at level 0 (plus
any extra ``tasks`` at lower levels), the position box when ``respect_limits``, iterated
from ``q0`` (:meth:`redik.Problem.solve`).

**Bounded latency.** An attempt that stops making progress — ``‖e‖²`` not halved in
``patience`` iterations, the signature of a start that drifts into a singularity or
against a limit — ends early, and a restart takes over from the nearest in pose of
``candidates`` random configurations, by the distance
``‖p − p_d‖² + w²‖R − R_d‖²_F / 2 ≈ ‖p − p_d‖² + (w θ)²`` with ``w`` = 0.5 m per rad (as
:mod:`redik.solvers.batch`'s restarts), so few iterations are spent on hopeless starts. Each
attempt also has its own budget, ``max_iterations``.

**A turn is free.** A revolute joint whose range spans a full turn or more (the UR arms'
±2π) is periodic for this solver: it is not boxed, and each iterate is turned back into its
range (:class:`~redik.limits.ConfigurationLimit` with ``periodic=True``; ``"dls"`` wraps such
joints the same way, :mod:`redik.kinematics.dls`): a bound the pose does not need never
stops it. With extra ``tasks`` (a posture measures a turned joint differently) the box
stays, and an attempt that stalls with such a joint against a bound restarts from the same
configuration turned by 2π — the same pose, unblocked — before any random restart.

It lives in the solvers layer, in the pose package, and drives :mod:`redik.solvers.problem`
(its first home ``redik.qp.solve`` sat below ``problem`` and imported it: a cycle);
:mod:`redik.qp` is the QP core only.
"""

from __future__ import annotations

from collections.abc import Iterable

import numba
import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import IKResult
from redik.core.validate import integer
from redik.core.validate import seed as check_seed
from redik.kinematics.chain import Chain
from redik.kinematics.compiled import COMPILE, chain_kinematics
from redik.kinematics.robot import Robot
from redik.limits import BallJointLimit, ConfigurationLimit
from redik.limits.ball_joint_limit import limited_ball_joints
from redik.solvers.pose.cache import PoseCache
from redik.solvers.problem import Problem
from redik.tasks.frame_task import FrameTask

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
    "plateau",
    "candidates",
    "lm_damping",
)

_PROBLEMS_KEPT = 16
"""Problems (one per frame and setting) a robot keeps for ``"qp"``; all are dropped past it."""

_ROTATION_SCALE = 0.5
"""Metres per radian in the pose distance that picks restart seeds."""


def solve_pose_qp(
    robot: Robot,
    T_target: np.ndarray,
    q0: np.ndarray,
    *,
    pos_tol: float = 1e-6,
    rot_tol: float = 1e-5,
    max_iterations: int = 100,
    respect_limits: bool = True,
    frame: str | None = None,
    restarts: int = 0,
    seed: int | None = None,
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
    ``max_iterations``), ``plateau`` (an attempt whose ``‖e‖²`` fell by less than this fraction in
    one iteration ends as stalled: a plateau against a limit; default 0.01, None to wait),
    ``candidates`` (each restart starts from the nearest in pose of this
    many random configurations; default 16), ``backend_options``. The defaults are those
    that gave the shortest tail over 200 random targets per robot (panda, iiwa14, ur5e)
    from home and from random seeds (``redik bench qp``).

    Raises:
        InvalidInput: an unknown option or a bad target/``q0``.
    """
    unknown = sorted(set(options) - set(_OPTIONS))
    if unknown:
        raise InvalidInput(f"unknown options {unknown} for method='qp'; known: {list(_OPTIONS)}")
    candidates = integer(options.get("candidates", 16), "candidates", 1)
    tasks = options.get("tasks", ())
    if hasattr(tasks, "compute_qp_objective"):  # one task is the list of it, as in Problem
        options = {**options, "tasks": [tasks]}
    elif isinstance(tasks, str) or not isinstance(tasks, Iterable):
        raise InvalidInput(
            f"tasks must be a list of tasks (or a single one, e.g. PostureTask(priority=1)), "
            f"got {tasks!r}"
        )
    problem = _problem(robot, T_target, frame, respect_limits, options)
    task = problem.tasks[0]
    chain = _chain_of(robot, task.frame) if restarts else None
    rng = np.random.default_rng(check_seed(seed))
    best: IKResult | None = None
    iterations = 0
    unwound = None  # the last attempt's q with its blocked full-turn joints turned back
    for attempt in range(restarts + 1):
        if attempt == 0:
            start = q0
        elif unwound is not None:
            start = unwound
        else:
            start = _nearest_start(robot, task, rng, candidates, chain)
        result = problem.solve(
            start,
            pos_tol=pos_tol,
            rot_tol=rot_tol,
            max_iterations=max_iterations,
            q_tol=options.get("q_tol", 1e-12),
            max_step=options.get("max_step", 1.0),
            stationarity_tol=options.get("stationarity_tol", 1e-8),
            patience=options.get("patience", 5),
            progress=options.get("progress", 0.5),
            plateau=options.get("plateau", 0.01),
            lm_damping=options.get("lm_damping", 0.01),
        )
        iterations += result.iterations
        if best is None or result.success or result.error < best.error:
            best = result
            best.restarts = attempt
        if result.success:
            break
        unwound = _unwound(robot, result.q) if result.status == "stalled" else None
    best.iterations = iterations
    return best


_AT_BOUND = 1e-6
"""A joint within this of a bound (rad) is against it (the box is shrunk by ≤ 1e-6)."""


def _unwound(robot: Robot, q: np.ndarray) -> np.ndarray | None:
    """``q`` with each revolute joint that sits against a bound turned by 2π away from it,
    where that stays in range (the same pose); None when no joint is so blocked."""
    values = robot.scalar_values(q)
    turn = 2.0 * np.pi
    up = robot.revolute & (values <= robot.lower + _AT_BOUND) & (values + turn <= robot.upper)
    down = robot.revolute & (values >= robot.upper - _AT_BOUND) & (values - turn >= robot.lower)
    if not (up.any() or down.any()):
        return None
    values = values + turn * up - turn * down
    return robot.with_scalar_values(q, values)


def _problem(robot: Robot, T_target, frame, respect_limits: bool, options: dict) -> Problem:
    """The pose problem, with ``T_target`` set.

    On the default back-end, daqp, without extra ``tasks`` or ``backend_options`` (objects
    of the caller's), it is kept in the robot's
    :class:`~redik.solvers.pose.cache.PoseCache` per frame and settings, as ``"dls"`` keeps
    its compiled chain: building the task, the problem and the back-end's
    workspace cost about a third of a typical solve. daqp's answer does not depend on the
    QPs it solved before (checked bitwise in ``tests/test_problem.py``); a warm-started
    back-end's (proxsuite) would, and would make a call depend on the calls before it, so
    those are built per call.
    """

    def build() -> Problem:
        return Problem(
            robot,
            [
                FrameTask(
                    robot.frame(frame).name,
                    gain=options.get("gain", 1.0),
                    target=T_target,
                    priority=0,
                ),
                *options.get("tasks", ()),
            ],
            limits=_limits(robot, periodic="tasks" not in options) if respect_limits else [],
            backend=options.get("backend", "daqp"),
            damping=options.get("damping", 1e-9),
            backend_options=options.get("backend_options"),
        )

    backend = options.get("backend", "daqp")
    if "tasks" in options or "backend_options" in options or backend != "daqp":
        return build()
    problems = PoseCache.of(robot).qp_problems
    key = (
        frame,
        bool(respect_limits),
        options.get("damping", 1e-9),
        options.get("gain", 1.0),
    )
    try:
        problem = problems.get(key)
    except TypeError:  # an unhashable setting (an array): built afresh
        return build()
    if problem is None:
        if len(problems) >= _PROBLEMS_KEPT:  # a gain swept call by call must not leak
            problems.clear()
        problem = problems[key] = build()
    else:
        problem.tasks[0].set_target(T_target)
    return problem  # type: ignore[return-value]


def _limits(robot: Robot, periodic: bool) -> list:
    """The robot's own ranges (:class:`redik.Problem`'s default limits), full-turn joints
    periodic when ``periodic`` (module docstring)."""
    limits = [ConfigurationLimit(periodic=periodic)]
    if limited_ball_joints(robot):
        limits.append(BallJointLimit())
    return limits


def _nearest_start(
    robot: Robot, task, rng: np.random.Generator, candidates: int, chain: tuple | None = None
) -> np.ndarray:
    """The nearest in pose to ``task``'s target of ``candidates`` random configurations.

    The distance ``‖p − p_d‖² + w²‖R − R_d‖²_F / 2`` (``‖R − R_d‖²_F = 4(1 − cos θ) ≈ 2θ²``:
    ``(w θ)²`` near 0). With ``chain`` (:func:`_chain_of`), the candidates' poses come from
    the compiled chain (:func:`redik.kinematics.compiled.chain_kinematics`) in one call —
    16 candidates cost ~150 µs through MuJoCo's forward kinematics, a few iterations of the
    solve, paid at every restart.
    """
    qs = robot.random_q(rng, size=candidates)
    if candidates == 1:
        return qs[0]
    target = task.target
    weight = 0.5 * _ROTATION_SCALE**2
    if chain is not None:
        base, links, revolute, columns = chain
        chain_q = np.ascontiguousarray(qs[:, columns])
        return qs[_nearest_index(base, links, revolute, chain_q, target, weight)]
    poses = np.empty((candidates, 4, 4))
    for q, T in zip(qs, poses, strict=True):
        robot.state.update(q)  # forward kinematics only: robot.fk would also check and allocate
        robot.state.pose_into(task.frame, T)
    distance = np.sum((poses[:, :3, 3] - target[:3, 3]) ** 2, axis=1) + weight * np.sum(
        (poses[:, :3, :3] - target[:3, :3]) ** 2, axis=(1, 2)
    )
    return qs[int(np.argmin(distance))]


@numba.njit(**COMPILE)
def _nearest_index(base, links, revolute, qs, target, weight):
    """Index of the row of ``qs`` whose chain pose is nearest ``target`` (as above)."""
    n = revolute.shape[0]
    R, p = np.empty((3, 3)), np.empty(3)
    axes, origins = np.empty((n, 3)), np.empty((n, 3))
    best, index = np.inf, 0
    for k in range(qs.shape[0]):
        chain_kinematics(base, links, revolute, qs[k], R, p, axes, origins)
        distance = 0.0
        for a in range(3):
            distance += (p[a] - target[a, 3]) ** 2
            for b in range(3):
                distance += weight * (R[a, b] - target[a, b]) ** 2
        if distance < best:
            best, index = distance, k
    return index


def _chain_of(robot: Robot, frame) -> tuple | None:
    """``(base, links, revolute, columns)`` of the compiled chain to ``frame``, kept in the
    robot's :class:`~redik.solvers.pose.cache.PoseCache`; None on a whole-model robot
    (its restarts use MuJoCo's forward kinematics)."""
    chains = PoseCache.of(robot).qp_chains
    frame = robot.frame(frame)
    if frame not in chains:
        chain = None
        if robot.is_chain:
            compiled = Chain.from_robot(robot, frame)
            chain = (compiled.base, compiled.links, compiled.revolute, compiled.columns)
            # Load the compiled function now (~5 ms from numba's disk cache), with the
            # problem, rather than in the middle of the first solve that restarts.
            _nearest_index(*chain[:3], compiled.home[None, :], np.eye(4), 1.0)
        chains[frame] = chain
    return chains[frame]
