"""The kinematic model: a MuJoCo model plus the joints redik may move.

A *chain* (``Robot(model, ee)``) moves the hinges and slides from the root to one frame and
runs every solver, fast paths included; a *whole-model* robot (``Robot(model, joints="all")``
or named joints and patterns) moves any set of hinge, slide, ball and free joints for the task
stacks. Both kinds, and ``q`` (``nq`` values) versus a tangent step ``Δq`` (``dof`` values), are
explained in :mod:`redik.kinematics.robot.robot`.

One idea per module:

- :mod:`~redik.kinematics.robot.robot`: :class:`Robot` (configuration and tangent space,
  forward kinematics and Jacobians, chains cut from a whole model);
- :mod:`~redik.kinematics.robot.selection`: which joints move (the chain to a frame, or names
  and ``fnmatch`` patterns, minus the fixed ones);
- :mod:`~redik.kinematics.robot.coordinates`: where those joints live in ``qpos`` and ``qvel``;
- :mod:`~redik.kinematics.robot.frames`: sites, bodies and geoms resolved by name, their pose
  and world Jacobian in ``MjData``;
- :mod:`~redik.kinematics.robot.solver_cache`: what solvers compile once per robot, safe to
  share between threads;
- :mod:`~redik.kinematics.robot.loader`: :func:`load`, a robot from a scene name or a path.
"""

from redik.kinematics.robot.frames import (
    FRAME_KINDS,
    Frame,
    frame_jacobian,
    frame_pose_views,
)
from redik.kinematics.robot.loader import load
from redik.kinematics.robot.robot import JACOBIAN_REFERENCES, Robot
from redik.kinematics.robot.solver_cache import SolverCache

__all__ = [
    "FRAME_KINDS",
    "JACOBIAN_REFERENCES",
    "Frame",
    "Robot",
    "SolverCache",
    "frame_jacobian",
    "frame_pose_views",
    "load",
]
