"""``redik.load``: a :class:`~redik.kinematics.robot.Robot` from a scene name or a file path."""

from __future__ import annotations

import os

from redik.kinematics.robot.robot import Robot
from redik.models import scenes


def load(name: str | os.PathLike[str], ee: str | None = None, **options) -> Robot:
    """Load a bundled scene by name (``redik.load("panda")``) or any MJCF/URDF file by path.

    ``name`` is anything :func:`redik.models.scenes.scene_path` accepts; ``options`` go to
    :meth:`Robot.from_file` (``joints``, ``fixed``) and on to
    :func:`redik.models.loading.load_spec` (``meshes=False`` for kinematics only, ``visual``,
    ``package_paths``, ``floating_base``, ``keep_fixed_links``)::

        redik.load("example-robot-data:ur5", ee="tool0", meshes=False)

    Raises:
        InvalidInput: ``name`` is neither a string nor a path.
        ModelError: no such scene or file, or MuJoCo cannot compile it.
        UnknownFrame: ``ee`` names no site or body of the model.
    """
    return Robot.from_file(scenes.scene_path(name), ee=ee, **options)
