"""One control step beside the anchors: PlaCo and mink on one panda URDF, mink on the G1.

**Panda** (example-robot-data's ``panda.urdf``, read by redik, mink and PlaCo alike; the arm's
7 joints move, the fingers are held). The stack: a frame task on ``panda_hand`` (position and
orientation cost 1), a posture towards ``q_ready`` and joint-limit avoidance (cost
:data:`COST`), the joint position box and the URDF's joint velocities as a velocity box
(``dt`` = :data:`DT`), damping 1e-6, DAQP.

- redik: :class:`~redik.qp.Problem` ``step``, weighted (one level) and strict (the hand at
  priority 0, the joint-space tasks at priority 1).
- mink: ``configuration.update`` + ``solve_ik`` on the full model (the fingers are variables
  of zero cost but the posture's), limit avoidance as a second ``PostureTask`` towards the
  mid-range with cost ``√2 w / (q_max − q_min)``, ``ConfigurationLimit(gain=1)`` (redik's box is
  exact), ``VelocityLimit``.
- PlaCo (``placo``, Rhoban's C++ whole-body solver, when importable):
  ``update_kinematics`` + ``solve``. Its floating base and fingers are masked (equalities its
  QR eliminates), so its QP has the same 7 variables. The hand is a position and an
  orientation task, soft (weight 1) beside redik's weighted step or hard (an equality)
  beside the strict one; posture a soft joints task of weight ``w²``; limit avoidance one
  one-row joints task per joint towards mid-range of weight ``2w²s_i²`` (its task weights are
  scalars); its own joint and velocity limits. PlaCo puts every task into one QP (hard tasks
  as equalities), solved by eiquadprog.

The hand follows the pose of a joint-space sinusoid (0.25 Hz, 0.4 rad per joint) at 100 Hz;
``q`` advances by redik's strict step. Every contestant solves at that same ``q`` and target,
one after another in a random order (machine load hits all alike); targets and ``q`` are
written untimed.

**G1** (example-robot-data's 29-dof G1 on a floating base, 35 tangent coordinates): frame
tasks on both hands (tracking 8 cm circles) and both feet (held), a posture of cost
:data:`COST` (0 on the floating base, as mink's ``PostureTask`` leaves a free joint alone), the
joint box, and :data:`G1_PAIRS` collision pairs (every few of the arm-against-body pairs) with
``d_s`` 0.01, ``d_i`` 0.08, ``ξ`` 0.5 in both. redik's weighted step beside mink's
``solve_ik``.
"""

from __future__ import annotations

import gc
import math
import os
import statistics
import time
import xml.etree.ElementTree as ET
from typing import Any

import mink
import numpy as np

from redik.kinematics.robot import Robot, load
from redik.limits import CollisionAvoidanceLimit, ConfigurationLimit, VelocityLimit
from redik.models import scenes
from redik.qp import Problem
from redik.tasks import FrameTask, JointLimitAvoidanceTask, PostureTask

COST = 0.1
"""Cost ``w`` of the posture and joint-limit-avoidance tasks (PlaCo's weight ``w²``)."""

DT = 0.01
"""The control period (s)."""

Q_READY = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
"""The panda's ready pose, the posture's target and the path's centre."""

PANDA = "example-robot-data:panda"
G1 = "example-robot-data:g1"
G1_HANDS = ("left_rubber_hand", "right_rubber_hand")
G1_FEET = ("left_ankle_roll_link", "right_ankle_roll_link")
G1_PAIRS = 50
"""Collision pairs of the G1 stack."""

_ARMS = ["left_shoulder_*", "left_elbow*", "left_wrist*"]
_ARMS += [name.replace("left", "right") for name in _ARMS]
_BODY = ["torso_link", "pelvis*", "*hip*", "*knee*", "head_link", "logo_link"]
_COLLISION: dict[str, Any] = {"minimum_distance": 0.01, "detection_distance": 0.08, "gain": 0.5}


def placo_available() -> bool:
    """Whether ``placo`` imports (it is not in the lock: ``requirements-placo.txt``)."""
    # Idle OpenMP workers sleep instead of spinning on a core the next contestant needs (read
    # when the OpenMP runtime loads, with placo).
    os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    try:
        import placo  # noqa: F401
    except ImportError:
        return False
    return True


def _urdf_velocities(path: str) -> dict[str, float]:
    """The ``<limit velocity>`` of every revolute and prismatic joint of a URDF."""
    velocities = {}
    for joint in ET.parse(path).getroot().iter("joint"):
        limit = joint.find("limit")
        if limit is None or joint.get("type") not in ("revolute", "prismatic"):
            continue
        name, velocity = joint.get("name"), limit.get("velocity")
        if name is not None and velocity is not None:
            velocities[name] = float(velocity)
    return velocities


def _panda_problem(robot: Robot, strict: bool) -> Problem:
    lower = 1 if strict else 0
    frame = FrameTask("panda_hand", "body", target=robot.fk(Q_READY))
    tasks = [
        frame,
        PostureTask(Q_READY, cost=COST, priority=lower),
        JointLimitAvoidanceTask(cost=COST, priority=lower),
    ]
    velocity = _urdf_velocities(str(scenes.scene_path(PANDA)))
    limits = [ConfigurationLimit(), VelocityLimit([velocity[j] for j in robot.joint_names])]
    return Problem(robot, tasks, limits, backend="daqp", damping=1e-6)


class _MinkPanda:
    """mink's stack (module docstring); :meth:`step` returns the arm's ``Δq``."""

    def __init__(self, robot: Robot):
        model = robot.model
        self.robot = robot
        self.configuration = mink.Configuration(model, robot.full_qpos(Q_READY))
        self.frame = mink.FrameTask("panda_hand", "body", 1.0, 1.0)
        posture = mink.PostureTask(model, cost=COST)
        posture.set_target(robot.full_qpos(Q_READY))
        avoidance = JointLimitAvoidanceTask(COST).bind(robot)
        cost = np.zeros(model.nv)
        cost[robot.dof_indices] = COST * math.sqrt(2.0) * avoidance.scale
        middle = mink.PostureTask(model, cost=cost)
        middle.set_target(robot.full_qpos(avoidance.middle))
        self.tasks = [self.frame, posture, middle]
        velocity = _urdf_velocities(str(scenes.scene_path(PANDA)))
        self.limits = [
            mink.ConfigurationLimit(model, gain=1.0),
            mink.VelocityLimit(model, {j: velocity[j] for j in robot.joint_names}),
        ]

    def set_target(self, T: np.ndarray) -> None:
        self.frame.set_target(mink.SE3.from_matrix(T))

    def step(self, qpos: np.ndarray) -> np.ndarray:
        self.configuration.update(qpos)
        v = mink.solve_ik(self.configuration, self.tasks, DT, "daqp", 1e-6, limits=self.limits)
        return v * DT


class _PlacoPanda:
    """PlaCo's stack (module docstring), soft or hard hand."""

    def __init__(self, robot: Robot, hard: bool):
        import placo

        path = str(scenes.scene_path(PANDA))
        # package:// meshes resolve through the cmeel prefix, collisions ignored or not.
        share = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(path))))
        os.environ.setdefault("ROS_PACKAGE_PATH", share)
        self.wrapper = placo.RobotWrapper(path, placo.Flags.ignore_collisions)
        self.solver = placo.KinematicsSolver(self.wrapper)
        self.solver.mask_fbase(True)
        for finger in ("panda_finger_joint1", "panda_finger_joint2"):
            self.solver.mask_dof(finger)
        self.solver.enable_joint_limits(True)
        self.solver.enable_velocity_limits(True)
        self.solver.dt = DT
        self.solver.problem.regularization = 1e-6
        self.frame = self.solver.add_frame_task("panda_hand", robot.fk(Q_READY))
        self.frame.configure("hand", "hard" if hard else "soft", 1.0, 1.0)
        posture = self.solver.add_joints_task()
        posture.set_joints(dict(zip(robot.joint_names, Q_READY, strict=True)))
        posture.configure("posture", "soft", COST * COST)
        avoidance = JointLimitAvoidanceTask(COST).bind(robot)
        for name, scale, middle in zip(
            robot.joint_names, avoidance.scale, avoidance.middle, strict=True
        ):
            task = self.solver.add_joints_task()
            task.set_joints({name: middle})
            task.configure(f"limits_{name}", "soft", 2.0 * COST * COST * scale * scale)

    def set_target(self, T: np.ndarray) -> None:
        self.frame.T_world_frame = T

    def set_q(self, q: np.ndarray) -> None:
        full = self.wrapper.state.q
        full[7:14] = q  # after the floating base's 7 coordinates
        self.wrapper.state.q = full

    def step(self) -> np.ndarray:
        self.wrapper.update_kinematics()
        return self.solver.solve(False)[6:13]


def _timed(function, *args) -> tuple[np.ndarray, float]:
    start = time.perf_counter()
    out = function(*args)
    return out, (time.perf_counter() - start) * 1e6


def _panda_contestants(robot: Robot, with_placo: bool) -> dict:
    """Name → a function ``(q, T) → (Δq, µs)`` that writes the target and ``q`` untimed."""
    weighted, strict = _panda_problem(robot, False), _panda_problem(robot, True)
    reference = _MinkPanda(robot)

    def redik_step(problem):
        def run(q, T):
            problem.tasks[0].set_target(T)
            return _timed(problem.step, q, DT)

        return run

    def mink_step(q, T):
        reference.set_target(T)
        dq, us = _timed(reference.step, robot.full_qpos(q))
        return dq[robot.dof_indices], us

    contestants = {
        "redik strict": redik_step(strict),
        "redik weighted": redik_step(weighted),
        "mink weighted": mink_step,
    }
    if with_placo:
        for name, hard in (("placo soft", False), ("placo hard", True)):
            stack = _PlacoPanda(robot, hard)

            def placo_step(q, T, stack=stack):
                stack.set_target(T)
                stack.set_q(q)
                return _timed(stack.step)

            contestants[name] = placo_step
    return contestants


def _interleaved(contestants: dict, q: np.ndarray, targets: list, integrate) -> tuple[dict, dict]:
    """Every contestant at every state, in a random order; medians (µs) and the steps.

    ``q`` advances by the first contestant's step (``integrate(q, Δq)``); the first 100
    states warm caches and are not counted.
    """
    names = list(contestants)
    times: dict[str, list[float]] = {name: [] for name in names}
    steps: dict[str, list[np.ndarray]] = {name: [] for name in names}
    # A random order per state: a rotation keeps the cyclic order, so one contestant would
    # always run right after another one's aftermath (its caches, a solver's spinning threads).
    orders = np.random.default_rng(0).permuted(
        np.tile(np.arange(len(names)), (len(targets), 1)), axis=1
    )
    gc.collect()
    gc.disable()
    try:
        for target, order in zip(targets, orders, strict=True):
            for index in order:
                name = names[index]
                dq, us = contestants[name](q, target)
                times[name].append(us)
                steps[name].append(dq)
            q = integrate(q, steps[names[0]][-1])
    finally:
        gc.enable()
    return {name: statistics.median(values[100:]) for name, values in times.items()}, steps


def _panda_path(robot: Robot, count: int) -> tuple[np.ndarray, list[np.ndarray]]:
    """The start and the targets of the tracked path (module docstring)."""
    phase = np.random.default_rng(0).uniform(0.0, 2.0 * np.pi, 7)
    q = np.clip(Q_READY + 0.4 * np.sin(phase), robot.lower, robot.upper)
    targets = []
    for k in range(count):
        q_path = Q_READY + 0.4 * np.sin(2.0 * np.pi * 0.25 * k * DT + phase)
        targets.append(robot.fk(np.clip(q_path, robot.lower, robot.upper)))
    return q, targets


def panda_steps(steps: int, with_placo: bool) -> tuple[dict, dict]:
    """Medians (µs) of the panda contestants and the largest step differences."""
    robot = load(PANDA, ee="panda_hand", meshes=False)
    contestants = _panda_contestants(robot, with_placo)
    q, targets = _panda_path(robot, steps + 100)
    medians, dqs = _interleaved(contestants, q, targets, lambda q, dq: q + dq)
    agreement = {}
    for name, reference in (("mink weighted", "redik weighted"), ("placo soft", "redik weighted")):
        if name in dqs:
            agreement[name] = float(np.max(np.abs(np.array(dqs[name]) - dqs[reference])))
    return medians, agreement


def g1_pairs(robot: Robot, count: int = G1_PAIRS) -> list[tuple[int, int]]:
    """``count`` geom pairs, arm geoms against body geoms, evenly from redik's list.

    All of them when ``count`` is at least their number, none for 0.
    """
    pairs = CollisionAvoidanceLimit([(_ARMS, _BODY)]).bind(robot).pairs.tolist()
    count = min(count, len(pairs))
    return [tuple(pairs[int(i * len(pairs) / count)]) for i in range(count)]


def _g1_contestants(robot: Robot, pairs: list[tuple[int, int]]) -> dict:
    tasks = [FrameTask(frame, "body", target=robot.fk(robot.home, frame))
             for frame in G1_HANDS + G1_FEET]  # fmt: skip
    cost = np.full(robot.dof, COST)
    cost[:6] = 0.0
    limits: list = [ConfigurationLimit()]
    if pairs:
        limits.append(CollisionAvoidanceLimit([([a], [b]) for a, b in pairs], **_COLLISION))
    problem = Problem(robot, [*tasks, PostureTask(cost=cost, priority=0)], limits, damping=1e-6)
    model = robot.model
    configuration = mink.Configuration(model, robot.full_qpos(robot.home))
    frames = []
    for frame in G1_HANDS + G1_FEET:
        task = mink.FrameTask(frame, "body", 1.0, 1.0)
        task.set_target(mink.SE3.from_matrix(robot.fk(robot.home, frame)))
        frames.append(task)
    posture = mink.PostureTask(model, cost=COST)
    posture.set_target(robot.full_qpos(robot.home))
    mink_limits: list = [mink.ConfigurationLimit(model, gain=1.0)]
    if pairs:
        mink_limits.append(
            mink.CollisionAvoidanceLimit(
                model,
                [([a], [b]) for a, b in pairs],
                gain=_COLLISION["gain"],
                minimum_distance_from_collisions=_COLLISION["minimum_distance"],
                collision_detection_distance=_COLLISION["detection_distance"],
            )
        )

    def redik_step(q, targets):
        for task, T in zip(problem.tasks[:2], targets, strict=True):
            task.set_target(T)
        return _timed(problem.step, q, DT)

    def mink_step(q, targets):
        for task, T in zip(frames[:2], targets, strict=True):
            task.set_target(mink.SE3.from_matrix(T))
        qpos = robot.full_qpos(q)

        def solve():
            configuration.update(qpos)
            return mink.solve_ik(
                configuration, [*frames, posture], 1.0, "daqp", 1e-6, limits=mink_limits
            )

        v, us = _timed(solve)
        return v, us

    return {"redik weighted": redik_step, "mink weighted": mink_step}


def _g1_targets(robot: Robot, count: int) -> list[list[np.ndarray]]:
    """Both hands on 8 cm circles (0.3 Hz)."""
    hands = [robot.fk(robot.home, frame) for frame in G1_HANDS]
    targets = []
    for k in range(count):
        angle = 2.0 * np.pi * 0.3 * k * DT
        pair = []
        for side, T0 in zip((1.0, -1.0), hands, strict=True):
            T = T0.copy()
            T[:3, 3] += 0.08 * np.array([np.sin(angle), 0.0, side * (1.0 - np.cos(angle))])
            pair.append(T)
        targets.append(pair)
    return targets


def g1_steps(steps: int, pairs: int = G1_PAIRS) -> tuple[dict, float, int]:
    """Medians (µs) of redik's and mink's G1 step, the largest step difference, the pairs.

    With ``pairs`` collision pairs (:func:`g1_pairs`: 0 for none, at most all of them); the
    last value is how many there were.
    """
    robot = load(G1, joints="all", floating_base=True)
    targets = _g1_targets(robot, steps + 100)
    chosen = g1_pairs(robot, pairs)
    contestants = _g1_contestants(robot, chosen)
    medians, dqs = _interleaved(contestants, robot.home, targets, robot.integrate)
    difference = np.array(dqs["mink weighted"]) - np.array(dqs["redik weighted"])
    return medians, float(np.max(np.abs(difference))), len(chosen)
