"""The whole-body stacks that `redik bench qp` (part 4) times and the task-stack tests solve.

Each model is an example-robot-data robot with some joints moved and some held; its goal is
the pose of several frames at one configuration drawn inside the limits, and its stack is one
:class:`~redik.tasks.FrameTask` per frame at priority 0 with a
:class:`~redik.tasks.PostureTask` below (priority 1) that resolves the redundancy.
"""

from __future__ import annotations

import numpy as np

from redik import lie
from redik.kinematics.robot import Robot
from redik.qp import Problem
from redik.tasks import FrameTask, PostureTask

WHOLE_BODIES = {
    "g1": ("g1", True, "all", None,
           ("left_rubber_hand", "right_rubber_hand", "left_ankle_roll_link",
            "right_ankle_roll_link")),
    "talos": ("talos_box", True, "all", ["gripper_*", "head_*"],
              ("gripper_left_base_link", "gripper_right_base_link", "left_sole_link",
               "right_sole_link")),
    "baxter": ("baxter", False, ["left_[sew][0-9]", "right_[sew][0-9]"], None,
               ("left_gripper", "right_gripper")),
    "pr2": ("pr2", False,
            ["torso_lift_joint", "[rl]_shoulder_*", "[rl]_upper_arm*", "[rl]_elbow*",
             "[rl]_forearm_roll*", "[rl]_wrist_*"],
            None, ("r_gripper_tool_frame", "l_gripper_tool_frame")),
}  # fmt: skip
"""The models: example-robot-data name, floating base, joints moved, joints held, and the
frames given pose tasks."""


def whole_body(key: str, reduced: bool = False) -> tuple[Robot, tuple[str, ...]]:
    """The robot of ``WHOLE_BODIES[key]`` and its frames.

    Args:
        key: A key of :data:`WHOLE_BODIES`.
        reduced: Delete the joints the robot does not move from the model (so that a library
            that moves every joint of a model, as mink does, moves the same ones), instead of
            holding them.

    Returns:
        The robot and the frames its goals name.
    """
    from redik.models import example_robot_data
    from redik.models.loading import compile_spec, load_spec

    name, floating, joints, fixed, frames = WHOLE_BODIES[key]
    path = example_robot_data(name)
    full = Robot(compile_spec(load_spec(path, meshes=False, floating_base=floating)),
                 joints=joints, fixed=fixed)  # fmt: skip
    if not reduced:
        return full, frames
    spec = load_spec(path, meshes=False, floating_base=floating)
    for joint in [j for j in spec.joints if j.name not in set(full.joint_names)]:
        spec.delete(joint)
    for equality in list(spec.equalities):  # some name the joints just deleted
        spec.delete(equality)
    return Robot(compile_spec(spec), joints="all"), frames


def goal(robot: Robot, frames: tuple[str, ...], rng: np.random.Generator) -> dict:
    """Each frame's pose at one configuration drawn inside the limits."""
    q = robot.random_q(rng)
    return {frame: robot.fk(q, frame) for frame in frames}


def stack(robot: Robot, goal: dict) -> Problem:
    """A frame task per goal frame, the posture task below them."""
    tasks = [FrameTask(frame, target=T) for frame, T in goal.items()]
    return Problem(robot, [*tasks, PostureTask(priority=1)])


def reaches(robot: Robot, q: np.ndarray, goal: dict, pos_tol: float, rot_tol: float) -> bool:
    """Whether ``q`` is inside the limits and puts every frame within the tolerances."""
    if not robot.within_limits(q):
        return False
    for frame, T in goal.items():
        p_err, r_err = lie.pose_errors(robot.fk(q, frame), T)
        if p_err > pos_tol or r_err > rot_tol:
            return False
    return True
