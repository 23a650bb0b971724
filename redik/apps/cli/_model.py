"""The model arguments shared by the subcommands that load a robot by name or path.

A bundled scene name, an MJCF/URDF path or ``example-robot-data:<name>`` /
``pybullet_data:<name>``, with the options of :func:`redik.models.loading.load_spec` for
third-party files: ``--no-meshes`` (kinematics only: every mesh geom dropped, so missing or
undecodable meshes do not matter), ``--floating-base`` (a free joint on the root body) and
``--package-path DIR`` (repeatable; folders searched for ``package://`` and relative mesh
paths). The module name starts with ``_``, so the CLI's subcommand discovery skips it.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from redik.kinematics.robot import Robot, load


def add_model_arguments(parser: argparse.ArgumentParser, optional: bool = False) -> None:
    """Add the positional ``scene`` (``optional``: it may be left out) and the load options
    to a subcommand's parser."""
    parser.add_argument(
        "scene",
        nargs="?" if optional else None,
        help="bundled scene name, MJCF/URDF path, or example-robot-data:NAME / pybullet_data:NAME",
    )
    group = parser.add_argument_group("model loading (third-party MJCF/URDF files)")
    group.add_argument(
        "--no-meshes",
        dest="meshes",
        action="store_false",
        help="kinematics only: drop every mesh geom (no mesh file is read)",
    )
    group.add_argument(
        "--floating-base",
        action="store_true",
        help="add a free joint to the root body (humanoids, quadrupeds); the chain holds it",
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
        "meshes": args.meshes,
        "floating_base": args.floating_base,
        "package_paths": args.package_paths,
    }


def load_robot(args: argparse.Namespace, **robot_options) -> Robot:
    """:func:`redik.load` of ``args.scene`` with ``args.ee`` and the load options
    (``robot_options``: ``fixed``, ``joints``)."""
    return load(args.scene, ee=args.ee, **robot_options, **load_options(args))
