"""``solve_pose_qp``: one pose target by the task-stack driver — ``solve_pose(method="qp")``.

A :class:`redik.Problem` with a :class:`~redik.tasks.FrameTask` at level 0 (plus any extra
``tasks`` at lower levels), the position box when ``respect_limits``, solved from ``q0`` by
:func:`redik.solve_problem` — the one driver of every task stack, with its seeded restarts
and per-chain warm start.

**A turn is free.** Without extra ``tasks``, a revolute joint whose range spans a full turn
or more (the UR arms' ±2π) is periodic for this method: it is not boxed, and each iterate is
turned back into its range (:class:`~redik.limits.ConfigurationLimit` with
``periodic=True``), so a bound the pose does not need never stops it. With extra ``tasks``
(a posture measures a turned joint differently) the box stays.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Frame, Robot
from redik.limits import BallJointLimit, ConfigurationLimit, Limit
from redik.limits.ball_joint_limit import limited_ball_joints
from redik.qp.problem import Problem
from redik.solvers.pose.cache import PoseCache
from redik.solvers.task_stack import QPResult, SolveOptions, solve_problem
from redik.tasks.frame_task import FrameTask

OPTIONS = {
    "backend": "daqp",
    "damping": 1e-9,
    "tasks": (),
    "gain": 1.0,
    "max_step": 1.0,
    "backend_options": None,
    "stationarity_tol": 1e-8,
    "lm_damping": 1e-2,
    "warm_start": True,
}
"""The options of ``method="qp"`` and their defaults: the back-end, the problem's ``damping``
(the Hessian regularisation ``ε``: 1e-6 would slow the convergence to targets near a
singularity, σ_min ≈ 2e-4, to a linear rate ``ε/(σ² + ε)``), extra ``tasks`` (redik or mink,
e.g. a ``PostureTask`` at priority 1), the pose task's ``gain``, and the driver's
:class:`~redik.solvers.task_stack.SolveOptions` ``max_step``, ``stationarity_tol``,
``lm_damping`` and ``warm_start``."""

PROBLEMS_KEPT = 16
"""Problems (one per frame and setting) a robot keeps for ``"qp"``; all are dropped past it."""


def solve_pose_qp(
    robot: Robot,
    T_target: np.ndarray,
    q0: np.ndarray,
    *,
    pos_tol: float = 1e-6,
    rot_tol: float = 1e-5,
    max_iterations: int = 100,
    respect_limits: bool = True,
    frame: str | Frame | None = None,
    restarts: int = 0,
    seed: int | None = None,
    **options,
) -> QPResult:
    """Drive ``frame`` (default the end-effector) to ``T_target`` from ``q0``.

    Args:
        robot: The robot.
        T_target: The target pose (4 × 4).
        q0: The first start.
        pos_tol: Position tolerance (m).
        rot_tol: Rotation tolerance (rad).
        max_iterations: Iterations per attempt.
        respect_limits: Keep the joint ranges (the default limits) or none.
        frame: The frame; None is the end-effector.
        restarts: Attempts after the first (:class:`~redik.solvers.task_stack.SolveOptions`).
        seed: Seed of the restarts.
        **options: Any of :data:`OPTIONS`.

    Returns:
        The :class:`~redik.solvers.task_stack.QPResult` of :func:`redik.solve_problem`.

    Raises:
        InvalidInput: an unknown option, ``tasks`` that is not a list, or a bad target/``q0``.
    """
    unknown = sorted(set(options) - set(OPTIONS))
    if unknown:
        raise InvalidInput(f"unknown options {unknown} for method='qp'; known: {list(OPTIONS)}")
    tasks = options.get("tasks", ())
    if hasattr(tasks, "compute_qp_objective"):  # one task is the list of it, as in Problem
        options = {**options, "tasks": [tasks]}
    elif isinstance(tasks, str) or not isinstance(tasks, Iterable):
        raise InvalidInput(
            f"tasks must be a list of tasks (or a single one, e.g. PostureTask(priority=1)), "
            f"got {tasks!r}"
        )
    settings = {**OPTIONS, **options}
    problem = _problem(robot, T_target, frame, respect_limits, settings, "tasks" in options)
    solve_options = SolveOptions(
        pos_tol=pos_tol,
        rot_tol=rot_tol,
        max_iterations=max_iterations,
        restarts=restarts,
        seed=seed,
        stationarity_tol=settings["stationarity_tol"],
        lm_damping=settings["lm_damping"],
        max_step=settings["max_step"],
        warm_start=settings["warm_start"],
    )
    return solve_problem(problem, q0, solve_options)


def _problem(
    robot: Robot, T_target, frame, respect_limits: bool, settings: dict, extra_tasks: bool
) -> Problem:
    """The pose problem with ``T_target`` set, kept per frame and settings when it can be.

    On the default back-end, daqp, without extra ``tasks`` or ``backend_options`` (objects of
    the caller's), it is kept in the robot's :class:`~redik.solvers.pose.cache.PoseCache`:
    daqp's answer does not depend on the QPs it solved before, while a warm-started
    back-end's (proxsuite) would make a call depend on the calls before it.
    """

    def build() -> Problem:
        task = FrameTask(robot.frame(frame).name, gain=settings["gain"], target=T_target)
        return Problem(
            robot,
            [task, *settings["tasks"]],
            limits=_limits(robot, periodic=not extra_tasks) if respect_limits else [],
            backend=settings["backend"],
            damping=settings["damping"],
            backend_options=settings["backend_options"],
        )

    if extra_tasks or settings["backend_options"] is not None or settings["backend"] != "daqp":
        return build()
    problems = PoseCache.of(robot).qp_problems
    key = (frame, bool(respect_limits), settings["damping"], settings["gain"])
    try:
        problem = problems.get(key)
    except TypeError:  # an unhashable setting (an array): built afresh
        return build()
    if problem is None:
        if len(problems) >= PROBLEMS_KEPT:  # a gain swept call by call must not leak
            problems.clear()
        problem = problems[key] = build()
    else:
        problem.tasks[0].set_target(T_target)
    return problem


def _limits(robot: Robot, periodic: bool) -> list:
    """The robot's own ranges, full-turn joints periodic when ``periodic``.

    The robot's own ranges (:class:`redik.Problem`'s default limits), full-turn joints periodic when
    ``periodic`` (module docstring).
    """
    limits: list[Limit] = [ConfigurationLimit(periodic=periodic)]
    if limited_ball_joints(robot):
        limits.append(BallJointLimit())
    return limits
