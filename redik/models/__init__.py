"""Model files and descriptions, below the kinematics that evaluates them.

- :mod:`~redik.models.loading`: MJCF/URDF files → ``mujoco.MjSpec`` (``package://`` meshes,
  kinematics-only loads, fixed links kept as frames, floating bases);
- :mod:`~redik.models.registry`: third-party model packages (``example-robot-data``,
  ``pybullet_data``) by name;
- :mod:`~redik.models.scenes`: the bundled scenes and :func:`scene_path`, which turns any of
  these names into a file;
- :mod:`~redik.models.dh`: Denavit–Hartenberg tables (both conventions);
- :mod:`~redik.models.builder`: MJCF from DH tables and screw axes (one module per step);
- :mod:`~redik.models.scene_library`: the tables the bundled scenes are generated from.

:func:`redik.load` (a :class:`~redik.kinematics.robot.Robot` from any of these) lives one
layer up, in :mod:`redik.kinematics.robot`.
"""

import warnings

from redik.models import registry
from redik.models.registry import example_robot_data, pybullet_data
from redik.models.scenes import list_scenes, scene_path, scenes_dir

__all__ = ["example_robot_data", "list_scenes", "pybullet_data", "scene_path", "scenes_dir"]

_REGISTRY_NAMES = frozenset(
    ("EXAMPLE_ROBOT_DATA", "PYBULLET_DATA", "ThirdPartyModel", "example_robot_data_dir",
     "pybullet_data_dir")
)  # fmt: skip
"""The other public names of the flat tree's ``redik.models`` module (now this package, the
registry in :mod:`redik.models.registry`), answered for one release like the moved modules
(:mod:`redik._compat`)."""


def __getattr__(name: str) -> object:
    if name in _REGISTRY_NAMES:
        warnings.warn(
            f"redik.models.{name} moved to redik.models.registry.{name}; the old path works "
            "until the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(registry, name)
    raise AttributeError(f"module 'redik.models' has no attribute {name!r}")
