"""``redik info SCENE``: joints, ranges, the frames to pick, the end-effector pose at home."""

from __future__ import annotations

import argparse

import mujoco
import numpy as np

from redik.apps.cli._model import add_model_arguments, load_robot
from redik.kinematics.robot import Robot
from redik.kinematics.robot.selection import JOINT_TYPE_NAMES, joint_name
from redik.lie import euler_angles
from redik.models.scenes import list_scenes

SCALAR = {
    int(mujoco.mjtJoint.mjJNT_HINGE): ("revolute", "rad"),
    int(mujoco.mjtJoint.mjJNT_SLIDE): ("prismatic", "m"),
}
"""Joints of one coordinate: the name ``info`` gives their type, and their unit."""

QPOS_SIZE = {int(mujoco.mjtJoint.mjJNT_BALL): 4, int(mujoco.mjtJoint.mjJNT_FREE): 7}
"""Coordinates of a ball (quaternion) and a free joint (position and quaternion)."""


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``redik info`` to the command line."""
    parser = subparsers.add_parser(
        "info", help="describe a robot: joints, ranges, frames, end-effector pose at home"
    )
    add_model_arguments(parser, optional=True)
    parser.add_argument("--list", action="store_true", help="list the bundled scenes")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the bundled scenes (``--list``, or no scene) or describe one robot."""
    if args.list or args.scene is None:
        print("bundled scenes:", ", ".join(list_scenes()))
        return 0
    describe(load_robot(args))
    return 0


def describe(robot: Robot) -> None:
    """Print the robot: its joints, the frames to pick and, with an end-effector, its pose.

    Args:
        robot: A chain to an end-effector, or a whole-model robot with none named.
    """
    joints = len(robot.joint_names)
    count = f"{joints} joints" + (f" ({robot.dof} DoF)" if robot.dof != joints else "")
    if robot.ee is None:
        print(f"{robot.name}: {count}, whole model (no end-effector: pick one with --ee)")
    else:
        print(f"{robot.name}: {count}, end-effector {robot.ee.kind} {robot.ee.name!r}")
    _print_joints(robot)
    _print_frames(robot)
    if robot.ee is None:
        return
    T = robot.fk(robot.home)
    with np.printoptions(precision=6, suppress=True):
        print("end-effector pose at home (T_world_ee):")
        print(T)
        print("position [m]:", T[:3, 3])
        print("roll-pitch-yaw (xyz) [rad]:", euler_angles(T[:3, :3], "xyz"))


def _print_joints(robot: Robot) -> None:
    """One row per moved joint (type, range, home), then the joints held still.

    Hinges and slides show their range and home value; a ball joint its home quaternion and
    a free joint its home pose ``(x, y, z, qw, qx, qy, qz)``.
    """
    model = robot.model
    width = max(14, *(len(joint) + 2 for joint in robot.joint_names))
    print(f"{'joint':<{width}}{'type':<10}{'lower':>12}{'upper':>12}{'home':>12}")
    # Limits are per tangent coordinate (qvel), values per position coordinate (qpos).
    tangent = {int(adr): i for i, adr in enumerate(robot.dof_indices)}
    position = {int(adr): i for i, adr in enumerate(robot.qpos_indices)}
    home = robot.full_qpos(robot.home)
    for j, joint in zip(robot.joint_ids, robot.joint_names, strict=True):
        kind = int(model.jnt_type[j])
        adr = int(model.jnt_qposadr[j])
        if kind in SCALAR:
            i = tangent[int(model.jnt_dofadr[j])]
            print(
                f"{joint:<{width}}{SCALAR[kind][0]:<10}{robot.lower[i]:>12.4f}"
                f"{robot.upper[i]:>12.4f}{robot.home[position[adr]]:>12.4f} {SCALAR[kind][1]}"
            )
        else:
            values = " ".join(f"{v:.4f}" for v in home[adr : adr + QPOS_SIZE[kind]])
            print(f"{joint:<{width}}{JOINT_TYPE_NAMES[kind]:<10}{'':>24}  ({values})")
    moved = set(robot.joint_ids.tolist())
    held = [
        f"{joint_name(model, j)} ({JOINT_TYPE_NAMES[int(model.jnt_type[j])]})"
        for j in range(model.njnt)
        if j not in moved
    ]
    if held:
        print("held joints (not moved):", ", ".join(held))


def _print_frames(robot: Robot) -> None:
    """The frames ``--ee`` would name (:meth:`redik.Robot.suggested_frames`), then the rest.

    The suggested frames are the sites and the leaf bodies the robot's joints move; the
    other bodies are the links inside its chains and what the joints do not move.
    """
    suggested = robot.suggested_frames()
    sites = set(robot.frame_names("site"))
    print("frames for --ee (sites and leaf bodies the joints move):")
    print("  sites: ", ", ".join(n for n in suggested if n in sites) or "(none)")
    print("  leaf bodies:", ", ".join(n for n in suggested if n not in sites) or "(none)")
    picked = {name.removeprefix("body:") for name in suggested}
    others = [name for name in robot.frame_names("body") if name not in picked]
    others = [name for name in others if name != "world"]
    if others:
        print("other bodies:", ", ".join(others))
