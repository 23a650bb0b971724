"""Compile the plan's kernels into numba's on-disk cache before they are first used.

``python -m redik.qp.compiled.compile`` steps a panda stack (frame task, posture, joint
position and velocity boxes: the objective and the box QP on one level, and the lower level
on two, each an entry of its own), a whole-model torso whose arm keeps clear of a table
(collision rows, a free and a ball joint), and the panda stack on the general path (the frame
task's compiled residual, which :func:`redik.solve_problem` evaluates too), so that numba
compiles each compiled entry and its callees once and caches them (``cache=True``: next to the
sources, or under ``NUMBA_CACHE_DIR``). Nothing here is needed for correctness — every kernel
compiles on its first call anyway — but a cold first step costs seconds of compilation, and a
warm one loads it from the cache. ``make env`` runs it as a step of installing
(:mod:`redik.core.compile_ahead`).
"""

from __future__ import annotations

from collections.abc import Callable

import mujoco

from redik.core import compile_ahead
from redik.kinematics.robot import Robot, load
from redik.limits import CollisionAvoidanceLimit, ConfigurationLimit, VelocityLimit
from redik.qp.problem import Problem
from redik.tasks import FrameTask, PostureTask

_TORSO = """
<mujoco model="torso">
  <worldbody>
    <geom name="table" type="box" pos="0.4 0 0.9" size="0.2 0.2 0.02"/>
    <body name="torso" pos="0 0 1">
      <freejoint/>
      <geom type="box" size="0.1 0.15 0.25"/>
      <body name="head" pos="0 0 0.35">
        <joint type="ball"/>
        <geom type="sphere" size="0.08"/>
      </body>
      <body name="arm" pos="0 0 0.2">
        <joint name="shoulder" axis="0 1 0" range="-2 2"/>
        <geom name="arm" type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
        <body name="hand" pos="0.4 0 0">
          <joint name="elbow" axis="0 1 0" range="-2.5 2.5"/>
          <geom name="hand" type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
          <site name="tip" pos="0.3 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def _panda(strict: bool, compiled: bool = True) -> Callable[[], object]:
    def step() -> object:
        robot = load("panda")
        tasks = [
            FrameTask("ee", target=robot.fk(robot.home + 0.5)),
            PostureTask(cost=0.1, priority=1 if strict else 0),
        ]
        limits = [ConfigurationLimit(), VelocityLimit(1.0)]
        problem = Problem(robot, tasks, limits, compiled=compiled)
        problem.static_step(robot.home, 0.01, lm_damping=1e-3, max_step=0.5)
        return problem.step(robot.home, 0.01)

    return step


def _torso() -> object:
    robot = Robot(mujoco.MjModel.from_xml_string(_TORSO), joints="all")
    limits = [
        ConfigurationLimit(),
        CollisionAvoidanceLimit([(["hand", "arm"], ["table"])], detection_distance=0.5),
    ]
    tasks = [FrameTask("tip", target=robot.fk(robot.home, "tip")), PostureTask(cost=0.1)]
    problem = Problem(robot, tasks, limits)
    q = robot.home.copy()
    q[-2:] = 0.5, 0.5  # the arm bent down towards the table: its rows come in
    return problem.step(q, 0.01)


#: What :func:`redik.core.compile_ahead.compile_all` runs, by name.
STEPS: dict[str, Callable[[], object]] = {
    "weighted step (objective, box QP)": _panda(strict=False),
    "strict step (the lower level)": _panda(strict=True),
    "whole model with collision rows": _torso,
    "general path (the frame task's residual)": _panda(strict=False, compiled=False),
}


if __name__ == "__main__":
    compile_ahead.main(STEPS)
