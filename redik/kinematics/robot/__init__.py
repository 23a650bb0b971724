"""The kinematic model: a MuJoCo model plus the joints redik may move.

A *chain* (``Robot(model, ee)``, or a model with a site ``ee``) moves the hinges and slides
from the root to one frame and runs every solver, fast paths included; a *whole-model* robot
(a model that names no end-effector, ``Robot(model, joints="all")``, or named joints and
patterns) moves any set of hinge, slide, ball and free joints for the task stacks. Both
kinds, and ``q`` (``nq`` values) versus a tangent step ``Δq`` (``dof`` values), are explained
in :mod:`redik.kinematics.robot.robot`.

One idea per module:

- :mod:`~redik.kinematics.robot.robot`: :class:`Robot`, the model side (configuration and
  tangent space, limits, frames, checked forward kinematics and Jacobians, chains cut from a
  whole model);
- :mod:`~redik.kinematics.robot.state`: :class:`RobotState`, the kinematic state (one
  ``MjData``: ``update(q)``, poses and Jacobians into buffers, unchecked, for hot loops);
- :mod:`~redik.kinematics.robot.selection`: which joints move (the chain to a frame, or names
  and ``fnmatch`` patterns, minus the fixed ones);
- :mod:`~redik.kinematics.robot.coordinates`: where those joints live in ``qpos`` and ``qvel``;
- :mod:`~redik.kinematics.robot.frames`: sites, bodies and geoms resolved by name, their pose
  and world Jacobian in ``MjData``;
- :mod:`~redik.kinematics.robot.loader`: :func:`load` and the ``Robot.from_*`` constructors, a
  robot from a scene name, a file, a string, a DH table or screws.
"""

from redik.kinematics.robot.frames import (
    FRAME_KINDS,
    Frame,
    frame_jacobian,
    frame_pose_views,
)
from redik.kinematics.robot.loader import load
from redik.kinematics.robot.robot import JACOBIAN_REFERENCES, Robot
from redik.kinematics.robot.state import RobotState

__all__ = [
    "FRAME_KINDS",
    "JACOBIAN_REFERENCES",
    "Frame",
    "Robot",
    "RobotState",
    "frame_jacobian",
    "frame_pose_views",
    "load",
]
