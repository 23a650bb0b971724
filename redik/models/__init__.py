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

from redik.core.lazy import lazy_submodules
from redik.models.registry import example_robot_data, pybullet_data
from redik.models.scenes import list_scenes, scene_path, scenes_dir

__all__ = ["example_robot_data", "list_scenes", "pybullet_data", "scene_path", "scenes_dir"]

__getattr__ = lazy_submodules(__name__)
