"""``redik info SCENE``: joints, ranges, frames and the end-effector pose at ``home``."""

from __future__ import annotations

import argparse

import numpy as np

from redik.apps.cli._model import add_model_arguments, load_robot
from redik.kinematics.robot.selection import JOINT_TYPE_NAMES, joint_name
from redik.lie import euler_angles
from redik.models.scenes import list_scenes


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "info", help="describe a robot: joints, ranges, frames, end-effector pose at home"
    )
    add_model_arguments(parser, optional=True)
    parser.add_argument("--ee", default=None, help="end-effector site or body (default: 'ee')")
    parser.add_argument("--list", action="store_true", help="list the bundled scenes")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.list or args.scene is None:
        print("bundled scenes:", ", ".join(list_scenes()))
        return 0
    robot = load_robot(args)
    print(f"{robot.name}: {robot.dof} joints, end-effector {robot.ee.kind} {robot.ee.name!r}")
    width = max(14, *(len(joint) + 2 for joint in robot.joint_names))
    print(f"{'joint':<{width}}{'type':<10}{'lower':>12}{'upper':>12}{'home':>12}")
    for i, joint in enumerate(robot.joint_names):
        kind = "revolute" if robot.revolute[i] else "prismatic"
        unit = "rad" if robot.revolute[i] else "m"
        print(
            f"{joint:<{width}}{kind:<10}{robot.lower[i]:>12.4f}{robot.upper[i]:>12.4f}"
            f"{robot.home[i]:>12.4f} {unit}"
        )
    moved = set(robot.joint_ids.tolist())
    held = [
        f"{joint_name(robot.model, j)} ({JOINT_TYPE_NAMES[int(robot.model.jnt_type[j])]})"
        for j in range(robot.model.njnt)
        if j not in moved
    ]
    if held:
        print("held joints (not moved):", ", ".join(held))
    print("sites: ", ", ".join(robot.frame_names("site")))
    print("bodies:", ", ".join(robot.frame_names("body")))
    T = robot.fk(robot.home)
    with np.printoptions(precision=6, suppress=True):
        print("end-effector pose at home (T_world_ee):")
        print(T)
        print("position [m]:", T[:3, 3])
        print("roll-pitch-yaw (xyz) [rad]:", euler_angles(T[:3, :3], "xyz"))
    return 0
