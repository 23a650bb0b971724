"""Where the attempts of :func:`~redik.solvers.task_stack.solve_problem` start.

Attempt 0 starts at ``q0``. While level 0 is not met, the next starts alternate between

- ``"chains"``, the *per-chain warm start* from where the last attempt ended
  (:class:`Chains`): on a floating base the base alone is first fitted to every frame target
  (an attempt of the driver on the free joints), then each frame task's serial chain is
  solved for its target — a full pose by :func:`redik.solve_pose` (compiled damped least
  squares with its own seeded restarts), a position or an orientation by the driver on
  that chain — the joints an earlier chain moved held;
- ``"random+chains"``, a configuration drawn inside the limits (a floating base kept: the
  targets place it, not the draw) put through the same warm start (``"random"`` alone
  without frame tasks).

Each limb must choose a branch (elbow up or down, a knee) that its start may not; a solve
per chain with restarts finds it cheaply, and the attempt that follows finishes the whole
stack. A start that breaks a hard inequality limit (a collision distance: the chains know
nothing of collisions) is replaced by another draw: a driver's steps keep the feasibility of
their start.
"""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np

from redik.core.exceptions import RedikError
from redik.kinematics.robot import Robot
from redik.kinematics.robot.selection import joint_name, literal
from redik.limits import ConfigurationLimit
from redik.qp.problem import Problem
from redik.solvers.pose import solve_pose
from redik.tasks import FrameTask, OrientationTask, PositionTask, SingleFrameTask

CHAIN_RESTARTS = 20
"""Restarts of each chain's solve in the warm start."""

DRAWS = 10
"""Random draws a restart makes to find a start that meets the hard inequality limits."""

_BALL_OR_FREE = (mujoco.mjtJoint.mjJNT_BALL, mujoco.mjtJoint.mjJNT_FREE)


def chain_copy(task: SingleFrameTask) -> SingleFrameTask:
    """A fresh task of the same kind, frame, costs and target.

    A fresh task of the same kind, frame, costs and target (``task`` stays bound to its own robot).
    """
    frame = task.frame
    if isinstance(task, FrameTask):
        return FrameTask(frame.name, frame.kind, task.cost[:3], task.cost[3:], target=task.target)
    kind = PositionTask if isinstance(task, PositionTask) else OrientationTask
    return kind(frame.name, frame.kind, task.cost, target=task.target)


def _full_pose(task: SingleFrameTask) -> bool:
    return isinstance(task, FrameTask) and bool(np.all(task.cost > 0.0))


class Chains:
    """The per-chain warm start of a problem (module docstring), built once per solve.

    Args:
        problem: The problem; its frame tasks of level 0 with a target give the chains.
        options: The solve's options (tolerances, seed handling, ``dt``).
        solve: The driver itself, for the base fit and the partial-pose chains.
    """

    def __init__(self, problem: Problem, options, solve):
        self.problem = problem
        self.options = options
        self.solve = solve
        robot = problem.robot
        self.chains: list[tuple[SingleFrameTask, Robot]] = []
        held: set[str] = set()
        for task in problem.frame_tasks:
            if task.target is None:
                continue
            chain = _chain_robot(robot, task, held)
            if chain is not None:
                self.chains.append((task, chain))
                held |= set(chain.joint_names)
        self.base = _base_problem(problem)

    def __bool__(self) -> bool:
        return bool(self.chains) or self.base is not None

    def start(self, q: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """``q`` with the base fitted (a floating base), then each chain solved in turn."""
        if self.base is not None:
            q = self._fit_base(self.base, q)
        for task, chain in self.chains:
            q = self._solve_chain(task, chain, q, int(rng.integers(2**32)))
        return q

    def _solve_chain(self, task, chain: Robot, q: np.ndarray, seed: int) -> np.ndarray:
        robot = self.problem.robot
        chain.state.data.qpos[:] = robot.full_qpos(q)
        q_chain = chain.q_of()
        if _full_pose(task):
            result = solve_pose(
                chain, task.target, q_chain, restarts=CHAIN_RESTARTS, seed=seed,
                diagnose_limits=False,
            )  # fmt: skip
        else:
            options = dataclasses.replace(
                self.options, restarts=CHAIN_RESTARTS, seed=seed, stationarity_tol=None,
                warm_start=False,
            )  # fmt: skip
            sub = Problem(chain, [chain_copy(task)], [ConfigurationLimit()])
            result = self.solve(sub, q_chain, options)
        return robot.embed(chain, result.q, q)

    def _fit_base(self, problem: Problem, q: np.ndarray) -> np.ndarray:
        """``q`` with its free joints at the least-squares fit of every frame target."""
        robot, base = self.problem.robot, problem.robot
        base.state.data.qpos[:] = robot.full_qpos(q)
        options = dataclasses.replace(
            self.options, restarts=0, warm_start=False, stationarity_tol=None
        )
        fitted = self.solve(problem, base.q_of(), options).q
        return robot.embed(base, fitted, q)


def _chain_robot(robot: Robot, task: SingleFrameTask, held: set[str]) -> Robot | None:
    """The serial chain to ``task``'s frame over the joints not yet held.

    The serial chain to ``task``'s frame over the robot's hinges and slides not in ``held`` (None
    when no such joint moves the frame).
    """
    if not held and robot.is_chain and task.frame == robot.ee:
        return robot  # the robot is that chain: its own solver cache serves every restart
    model = robot.model
    moved = set(robot.joint_names)
    fixed = []
    for j in range(model.njnt):
        name = joint_name(model, j)
        if name not in moved or name in held or int(model.jnt_type[j]) in _BALL_OR_FREE:
            fixed.append(literal(name))
    try:
        return Robot(model, f"{task.frame.kind}:{task.frame.name}", joints=None, fixed=fixed)
    except RedikError:
        return None  # no joint left to move this frame


def _base_problem(problem: Problem) -> Problem | None:
    """The frame targets of level 0 on a robot that moves only the free joints.

    The frame targets of level 0 on a robot that moves only the free joints (None without a free
    joint).
    """
    robot = problem.robot
    model = robot.model
    free = [
        name
        for name, kind in zip(robot.joint_names, robot.joint_types, strict=True)
        if kind == "free"
    ]
    tasks = [chain_copy(task) for task in problem.frame_tasks if task.target is not None]
    if not free or not tasks:
        return None
    base = Robot(model, joints=[literal(name) for name in free])
    return Problem(base, tasks, limits=[])


def random_start(robot: Robot, q_last: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """A configuration drawn inside the limits, with the ball and free joints of ``q_last``."""
    q = robot.random_q(rng)
    if robot.flat:
        return q
    return robot.with_scalar_values(q_last, robot.scalar_values(q))


def next_start(
    problem: Problem, chains: Chains | None, q_last: np.ndarray, last_start: str, rng
) -> tuple[np.ndarray, str]:
    """The start after a failed attempt that ended at ``q_last`` (module docstring).

    Args:
        problem: The problem.
        chains: The warm start, or None.
        q_last: Where the last attempt ended.
        last_start: Where it started.
        rng: The solve's generator.

    Returns:
        ``(q, label)``.
    """
    if chains and last_start != "chains":
        q = chains.start(q_last, rng)
        if problem.feasible(q):
            return q, "chains"
    q = q_last
    for _ in range(DRAWS):
        q = random_start(problem.robot, q_last, rng)
        if chains:
            through = chains.start(q, rng)
            if problem.feasible(through):
                return through, "random+chains"
        if problem.feasible(q):
            return q, "random"
    return q, "random"
