"""The model arguments shared by every subcommand that loads a robot, and their messages.

A bundled scene name, an MJCF/URDF path or ``example-robot-data:<name>`` /
``pybullet_data:<name>``, with the options of :func:`redik.load` for any model:
``--ee FRAME`` (the site or body to solve for), ``--fixed JOINT …`` (joints held still:
names or patterns), ``--no-meshes`` (kinematics only: every mesh geom dropped, so missing or
undecodable meshes do not matter), ``--floating-base`` (a free joint on the root body) and
``--package-path DIR`` (repeatable; folders searched for ``package://`` and relative mesh
paths). Messages written for Python callers name keyword arguments (``meshes=False``); the
command line reports them with its flags instead (:func:`in_flags`). The module name starts
with ``_``, so the CLI's subcommand discovery skips it.
"""

from __future__ import annotations

import argparse
import functools
import re
import sys
from pathlib import Path

import mujoco

from redik.core.exceptions import UnknownFrame
from redik.kinematics.robot import Robot, load
from redik.models.loading import FLOATING_BASE_JOINT

KEYWORD_FLAGS: list[tuple[re.Pattern[str], str]] = [
    (re.compile(r"\bmeshes=False\b"), "--no-meshes"),
    (re.compile(r"\bfloating_base=True\b"), "--floating-base"),
    (re.compile(r"\bpackage_paths=\[([^\]]*)\]"), "--package-path DIR ({inner})"),
    (re.compile(r"\bpackage_paths\b(\[\d+\])?"), "--package-path"),
    (re.compile(r"\bfixed=\[([^\]]*)\]"), "--fixed {names}"),
    (re.compile(r"\bfixed="), "--fixed"),
    (re.compile(r"^fixed: "), "--fixed: "),
    (re.compile(r"\bee="), "--ee "),
]
"""Keyword arguments of :func:`redik.load` in messages, and the flag that sets each."""


def add_model_arguments(parser: argparse.ArgumentParser, optional: bool = False) -> None:
    """Add the positional ``scene`` and the model options to a subcommand's parser.

    Args:
        parser: The subcommand's parser.
        optional: Whether ``scene`` may be left out (``redik info --list``).
    """
    parser.add_argument(
        "scene",
        nargs="?" if optional else None,
        help="bundled scene name, MJCF/URDF path, or example-robot-data:NAME / pybullet_data:NAME",
    )
    group = parser.add_argument_group("model")
    group.add_argument(
        "--ee", default=None, metavar="FRAME",
        help="the site or body to solve for (default: the site 'ee' when the model has one; "
        "else info describes the whole model)",
    )  # fmt: skip
    group.add_argument(
        "--fixed", nargs="+", default=None, metavar="JOINT",
        help="joints held still (names or patterns, e.g. 'head_*'; a ball joint on the chain "
        "must be held)",
    )  # fmt: skip
    group.add_argument(
        "--no-meshes",
        dest="meshes",
        action="store_false",
        help="kinematics only: drop every mesh geom (no mesh file is read)",
    )
    group.add_argument(
        "--floating-base",
        action="store_true",
        help="add a free joint to the root body (humanoids, quadrupeds)",
    )
    group.add_argument(
        "--package-path",
        dest="package_paths",
        action="append",
        type=Path,
        default=None,
        metavar="DIR",
        help="folder searched for package:// and relative mesh paths (repeatable)",
    )


def load_options(args: argparse.Namespace) -> dict:
    """The keyword arguments of :func:`redik.load` given on the command line."""
    return {
        "ee": args.ee,
        "fixed": args.fixed,
        "meshes": args.meshes,
        "floating_base": args.floating_base,
        "package_paths": args.package_paths,
    }


def load_robot(args: argparse.Namespace) -> Robot:
    """:func:`redik.load` of ``args.scene`` with the model options of the command line.

    Warns on stderr when ``--floating-base`` changes nothing (:func:`floating_base_note`).
    """
    robot = load(args.scene, **load_options(args))
    note = floating_base_note(robot) if args.floating_base else ""
    if note:
        print(f"redik {args.command}: warning: {note}", file=sys.stderr)
    return robot


def load_chain(args: argparse.Namespace) -> Robot:
    """:func:`load_robot`, for a command that solves for one frame: a chain to ``--ee``.

    Raises:
        UnknownFrame: the model names no end-effector and ``--ee`` was not given; the
            message lists the frames the robot's joints move.
    """
    robot = load_robot(args)
    if robot.ee is None:
        suggested = robot.suggested_frames()
        raise UnknownFrame(
            f"{robot.name!r} names no end-effector (no site 'ee'): pick one with --ee FRAME; "
            f"the frames its joints move: {', '.join(suggested) or '(none)'}"
        )
    return robot


def floating_base_note(robot: Robot) -> str:
    """Why ``--floating-base`` changed nothing for ``robot``, or "" when it did.

    It changes nothing on a model whose root already had a free joint (the flag then adds
    none), and nothing on a chain: a chain does not move the free joint, which keeps the
    root where the file puts it.
    """
    model = robot.model
    free = [j for j in range(model.njnt) if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) or f"#{j}" for j in free]
    if free and FLOATING_BASE_JOINT not in names:
        return (
            f"--floating-base changes nothing: {robot.name!r} already has a free joint "
            f"({', '.join(map(repr, names))})"
        )
    moved = set(robot.joint_ids.tolist())
    if free and not moved & set(free):
        return (
            f"--floating-base changes nothing here: the chain of {robot.name!r} does not move "
            f"its free joint {FLOATING_BASE_JOINT!r}, which keeps the root where the file puts "
            f"it; a floating base matters to a whole-model robot"
        )
    return ""


def in_flags(message: str) -> str:
    """``message`` with the keyword arguments of :func:`redik.load` named by their flags.

    ``"load with meshes=False"`` reads ``"load with --no-meshes"``, ``"fixed=['j1', 'j2']"``
    reads ``"--fixed j1 j2"``.
    """
    for pattern, flag in KEYWORD_FLAGS:
        message = pattern.sub(functools.partial(_flag_text, flag=flag), message)
    return message


def _flag_text(match: re.Match[str], flag: str) -> str:
    """The flag for one matched keyword.

    In the flag's text ``{names}`` stands for the quoted names of the matched list and
    ``{inner}`` for the list's text.
    """
    if "{" not in flag:
        return flag
    inner = match.group(1)
    names = re.findall(r"['\"]([^'\"]+)['\"]", inner)
    return flag.format(names=" ".join(names), inner=inner)
