"""What every pose solve of one frame of one robot shares.

The joints that move the frame and how far the chain can reach: built once per frame and
kept by the robot (:class:`~redik.solvers.pose.cache.PoseCache`).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Frame, Robot, frame_pose_views


class PoseFrame:
    """The joints of ``robot`` that move ``frame``, and the reach of the chain.

    :attr:`columns` are the joints' indices into ``q``; no ``q`` puts the frame farther than
    :attr:`reach` from :attr:`origin`, the first joint's anchor (:func:`reach_bound`).

    Raises:
        InvalidInput: no joint of the robot moves ``frame`` (such as ``"world"``).
    """

    def __init__(self, robot: Robot, frame: Frame) -> None:
        self.robot = robot
        self.frame = frame
        self.columns = moving_columns(robot, frame)
        if self.columns.size == 0:
            raise InvalidInput(
                f"no joint of {robot.name!r} moves frame {frame.name!r} (the chain joints are "
                f"{list(robot.joint_names)}), so no q can place it; name a site or body "
                f"below one of them"
            )
        self.every_joint = self.columns.size == robot.dof
        self.origin, self.reach = reach_bound(robot, frame, self.columns)

    def reach_excess(self, p_d: np.ndarray) -> float:
        """How far (m) ``p_d`` lies beyond the chain's reach (0 inside; see :func:`reach_bound`).

        The compiled ``"dls"`` kernel computes the same (:func:`redik.solvers.dls.solve_one`).
        """
        if not math.isfinite(self.reach):
            return 0.0
        excess = math.dist(p_d.tolist(), self.origin) - self.reach
        return excess if excess > 1e-9 * max(1.0, self.reach) else 0.0


def moving_columns(robot: Robot, frame: Frame) -> np.ndarray:
    """Where the joints that move ``frame`` (those on its path to the world) sit in ``q``."""
    model = robot.model
    body = robot.body_of(frame)
    path = set()
    while body > 0:
        path.add(body)
        body = int(model.body_parentid[body])
    joint_of_qpos = {int(adr): joint for joint, adr in enumerate(model.jnt_qposadr)}
    return np.array(
        [
            column
            for column, adr in enumerate(robot.qpos_indices)
            if int(model.jnt_bodyid[joint_of_qpos[int(adr)]]) in path
        ],
        dtype=int,
    )


def reach_bound(robot: Robot, frame: Frame, columns: np.ndarray) -> tuple[tuple[float, ...], float]:
    """``(a_1, r)``: no ``q`` puts ``frame`` farther than ``r`` from the first joint's anchor.

    The distance between the anchors of two consecutive hinges is constant (each hinge
    rotates everything after it about a line through its own anchor), so ``‖p − a_1‖`` is at
    most the sum of the anchor-to-anchor distances and the last anchor-to-frame distance,
    plus the full travel of every slide joint. Unlimited slides make the reach infinite.
    """
    model, data = robot.model, mujoco.MjData(robot.model)
    data.qpos[:] = robot.full_qpos(robot.midrange)
    mujoco.mj_kinematics(model, data)
    joint_of_qpos = {int(adr): joint for joint, adr in enumerate(model.jnt_qposadr)}
    joints = [joint_of_qpos[int(robot.qpos_indices[column])] for column in columns]
    anchors = data.xanchor[joints]
    point = frame_pose_views(data, frame)[1]
    points = np.vstack((anchors, point))
    reach = float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))
    travel = (robot.upper - robot.lower)[columns][~robot.revolute[columns]]
    reach += float(np.sum(travel))  # inf for an unlimited slide
    return tuple(anchors[0].tolist()), reach
