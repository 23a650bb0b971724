"""Robot descriptions from third-party packages on the package index, found by name.

Two packages ship many real URDFs and install with ``pip install "redik[models]"``:

* ``example-robot-data`` (Gepetto, LAAS-CNRS): arms (Panda, UR3/5/10, Kinova, xArm, Z1),
  bimanual and mobile manipulators (Baxter, PR2, TIAGo), humanoids (Talos, G1, iCub, Romeo)
  and quadrupeds (Go1, A1, ANYmal, Solo). Names follow its own loader (``"ur5"``, ``"talos"``,
  ``"panda"``); files live under ``<prefix>/share/example-robot-data/robots``.
* ``pybullet`` with ``pybullet_data``: KUKA LBR iiwa, Franka Panda, xArm6, quadrupeds.

:func:`example_robot_data` and :func:`pybullet_data` return the file's path, to be loaded with
:func:`redik.load` or :func:`redik.models.loading.load_spec`::

    robot = redik.load(redik.models.example_robot_data("ur5"), ee="tool0")
    spec = redik.models.loading.load_spec(redik.models.example_robot_data("talos"),
    floating_base=True)

Entries whose robot moves freely in the world (legged robots, humanoids, drones) say so in
:attr:`ThirdPartyModel.floating_base`; pass that to ``floating_base``. A name outside the
tables is looked up as a file stem (``"ur5_joint_limited_robot"``) or a relative path.
"""

from __future__ import annotations

import dataclasses
import difflib
import importlib.metadata
import os
import sys
from pathlib import Path

from redik.core.exceptions import ModelError

_INSTALL_HINT = 'install the "models" extra: pip install "redik[models]"'


@dataclasses.dataclass(frozen=True)
class ThirdPartyModel:
    """A robot description inside a third-party package.

    Attributes:
        path: The file, relative to the package's robot folder.
        floating_base: True for robots that move freely in the world (load with
            ``floating_base=True``); False for robots bolted to the ground or a mobile base
            whose wheels are joints.
    """

    path: str
    floating_base: bool = False


def _entry(path: str, floating_base: bool = False) -> ThirdPartyModel:
    return ThirdPartyModel(path, floating_base)


#: example-robot-data's robots by the names of its own Python loader.
EXAMPLE_ROBOT_DATA: dict[str, ThirdPartyModel] = {
    "a1": _entry("a1_description/urdf/a1.urdf", True),
    "allegro_left_hand": _entry("allegro_hand_description/urdf/allegro_left_hand.urdf"),
    "allegro_right_hand": _entry("allegro_hand_description/urdf/allegro_right_hand.urdf"),
    "anymal": _entry("anymal_b_simple_description/robots/anymal.urdf", True),
    "anymal_c": _entry("anymal_c_simple_description/urdf/anymal.urdf", True),
    "anymal_kinova": _entry("anymal_b_simple_description/robots/anymal-kinova.urdf", True),
    "asr_twodof": _entry("asr_twodof_description/urdf/TwoDofs.urdf"),
    "b1": _entry("b1_description/urdf/b1.urdf", True),
    "b1_z1": _entry("b1_description/urdf/b1-z1.urdf", True),
    "baxter": _entry("baxter_description/urdf/baxter.urdf"),
    "bolt": _entry("bolt_description/robots/bolt.urdf", True),
    "double_pendulum": _entry("double_pendulum_description/urdf/double_pendulum.urdf"),
    "double_pendulum_continuous": _entry(
        "double_pendulum_description/urdf/double_pendulum_continuous.urdf"
    ),
    "double_pendulum_simple": _entry(
        "double_pendulum_description/urdf/double_pendulum_simple.urdf"
    ),
    "finger_edu": _entry("finger_edu_description/robots/finger_edu.urdf"),
    "g1": _entry("g1_description/urdf/g1_29dof_rev_1_0.urdf", True),
    "g1_with_hand": _entry("g1_description/urdf/g1_29dof_with_hand_rev_1_0.urdf", True),
    "go1": _entry("go1_description/urdf/go1.urdf", True),
    "go2": _entry("go2_description/urdf/go2.urdf", True),
    "hector": _entry("hector_description/robots/quadrotor_base.urdf", True),
    "hyq": _entry("hyq_description/robots/hyq_no_sensors.urdf", True),
    "icub": _entry("icub_description/robots/icub.urdf", True),
    "icub_reduced": _entry("icub_description/robots/icub_reduced.urdf", True),
    "iris": _entry("iris_description/robots/iris_simple.urdf", True),
    "kinova": _entry("kinova_description/robots/kinova.urdf"),
    "laikago": _entry("laikago_description/urdf/laikago.urdf", True),
    "panda": _entry("panda_description/urdf/panda.urdf"),
    "panda_collision": _entry("panda_description/urdf/panda_collision.urdf"),
    "pr2": _entry("pr2_description/urdf/pr2.urdf"),
    "quadruped": _entry("quadruped_description/urdf/quadruped.urdf", True),
    "romeo": _entry("romeo_description/urdf/romeo.urdf", True),
    "simple_humanoid": _entry("simple_humanoid_description/urdf/simple_humanoid.urdf", True),
    "simple_humanoid_classical": _entry(
        "simple_humanoid_description/urdf/simple_humanoid_classical.urdf", True
    ),
    "so_arm_100": _entry("so_arm_description/urdf/so100.urdf"),
    "so_arm_101": _entry("so_arm_description/urdf/so101.urdf"),
    "solo8": _entry("solo_description/robots/solo.urdf", True),
    "solo12": _entry("solo_description/robots/solo12.urdf", True),
    "talos": _entry("talos_data/robots/talos_reduced.urdf", True),
    "talos_arm": _entry("talos_data/robots/talos_left_arm.urdf"),
    "talos_box": _entry("talos_data/robots/talos_reduced_box.urdf", True),
    "talos_full": _entry("talos_data/robots/talos_full_v2.urdf", True),
    "talos_full_box": _entry("talos_data/robots/talos_full_v2_box.urdf", True),
    "tiago": _entry("tiago_description/robots/tiago.urdf"),
    "tiago_dual": _entry("tiago_description/robots/tiago_dual.urdf"),
    "tiago_no_hand": _entry("tiago_description/robots/tiago_no_hand.urdf"),
    "tiago_pro": _entry("tiago_pro_description/robots/tiago_pro.urdf"),
    "ur3": _entry("ur_description/urdf/ur3_robot.urdf"),
    "ur3_gripper": _entry("ur_description/urdf/ur3_gripper.urdf"),
    "ur3_limited": _entry("ur_description/urdf/ur3_joint_limited_robot.urdf"),
    "ur5": _entry("ur_description/urdf/ur5_robot.urdf"),
    "ur5_gripper": _entry("ur_description/urdf/ur5_gripper.urdf"),
    "ur5_limited": _entry("ur_description/urdf/ur5_joint_limited_robot.urdf"),
    "ur10": _entry("ur_description/urdf/ur10_robot.urdf"),
    "ur10_limited": _entry("ur_description/urdf/ur10_joint_limited_robot.urdf"),
    "xarm": _entry("xarm_description/urdf/xarm7.urdf"),
    "z1": _entry("z1_description/urdf/z1.urdf"),
}

#: pybullet_data's robots (its many objects and scenes are reachable by relative path).
PYBULLET_DATA: dict[str, ThirdPartyModel] = {
    "a1": _entry("a1/a1.urdf", True),
    "aliengo": _entry("aliengo/aliengo.urdf", True),
    "franka_panda": _entry("franka_panda/panda.urdf"),
    "kuka_iiwa": _entry("kuka_iiwa/model.urdf"),
    "laikago": _entry("laikago/laikago_toes.urdf", True),
    "mini_cheetah": _entry("mini_cheetah/mini_cheetah.urdf", True),
    "minitaur": _entry("quadruped/minitaur.urdf", True),
    "r2d2": _entry("r2d2.urdf", True),
    "xarm6": _entry("xarm/xarm6_robot.urdf"),
}


def example_robot_data(name: str) -> Path:
    """Path of an example-robot-data URDF by name (:data:`EXAMPLE_ROBOT_DATA`), file stem or path.

    Raises:
        ModelError: the package is not installed (the message says which extra to install),
            or no file has that name (with the closest names).
    """
    return _find(name, example_robot_data_dir(), EXAMPLE_ROBOT_DATA, "example-robot-data")


def pybullet_data(name: str) -> Path:
    """Path of a pybullet_data URDF by name (:data:`PYBULLET_DATA`), file stem or path.

    Raises:
        ModelError: pybullet is not installed, or no file has that name.
    """
    return _find(name, pybullet_data_dir(), PYBULLET_DATA, "pybullet_data")


def example_robot_data_dir() -> Path:
    """The ``robots`` folder of the installed example-robot-data (pip, conda or ROS install)."""
    relative = Path("share", "example-robot-data", "robots")
    candidates = []
    try:
        distribution = importlib.metadata.distribution("example-robot-data")
        candidates.append(Path(str(distribution.locate_file(Path("cmeel.prefix") / relative))))
    except importlib.metadata.PackageNotFoundError:
        pass
    # Installs beside a Python prefix (conda, robotpkg) or in a ROS 2 workspace.
    candidates += [Path(p, "..", "..", "..", relative) for p in sys.path if p]
    candidates += [Path(sys.prefix, relative)]
    candidates += [
        Path(p, relative) for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p
    ]
    for candidate in candidates:
        if candidate.is_dir():
            return candidate.resolve()
    raise ModelError(f"example-robot-data is not installed; {_INSTALL_HINT}")


def pybullet_data_dir() -> Path:
    """The folder of pybullet's bundled models (``pybullet_data.getDataPath()``)."""
    try:
        import pybullet_data as data
    except ImportError:
        raise ModelError(f"pybullet (pybullet_data) is not installed; {_INSTALL_HINT}") from None
    return Path(data.getDataPath())


def _find(name: str, root: Path, table: dict[str, ThirdPartyModel], package: str) -> Path:
    if not isinstance(name, str) or not name:
        raise ModelError(f"a {package} model is named by a non-empty string, got {name!r}")
    entry = table.get(name)
    if entry is not None:
        path = root / entry.path
        if not path.is_file():
            raise ModelError(
                f"{package} at {root} has no {entry.path!r} for {name!r}; "
                f"a newer {package} may have moved it"
            )
        return path
    if "/" in name or name.endswith((".urdf", ".xml", ".sdf")):
        path = root / name
        if path.is_file():
            return path
    stems = {path.stem: path for path in sorted(root.rglob("*.urdf"))}
    if name in stems:
        return stems[name]
    close = difflib.get_close_matches(name, list(dict.fromkeys([*table, *stems])), n=5, cutoff=0.5)
    hint = f"; did you mean {', '.join(map(repr, close))}?" if close else ""
    raise ModelError(
        f"no {package} model named {name!r}{hint} (names: {sorted(table)}; "
        f"any URDF under {root} by file stem or relative path)"
    )
