"""The ways to build a :class:`~redik.Robot`: from a scene, a file, a string, a table, screws.

A scene name or a file path, an MJCF or URDF string, a Denavit–Hartenberg table, or screw
axes.

Each compiles a :class:`mujoco.MjModel` (through :mod:`redik.models.loading`, which resolves
meshes and repairs what stops real-world files from loading, or the MJCF builders of
:mod:`redik.models.builder`) and hands it to the ``Robot`` constructor. :class:`RobotLoading`
holds them as class methods of ``Robot`` (``Robot.from_file``, ``Robot.from_dh``, …);
:func:`load` is ``redik.load``.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.models import loading, scenes
from redik.models.builder import dh_to_mjcf, screws_to_mjcf
from redik.models.dh import RowLike

if TYPE_CHECKING:
    from redik.kinematics.robot.robot import Robot


_RobotT = TypeVar("_RobotT", bound="RobotLoading")


class RobotLoading:
    """The class methods that build a robot from a description; ``Robot`` derives from it."""

    if TYPE_CHECKING:
        # The constructor the class methods call: Robot's.
        def __init__(
            self,
            model: mujoco.MjModel,
            ee: str | None = None,
            *,
            name: str | None = None,
            joints: str | Sequence[str] | None = None,
            fixed: Sequence[str] | None = None,
        ) -> None: ...

    @classmethod
    def from_file(
        cls: type[_RobotT],
        path: str | Path,
        ee: str | None = None,
        *,
        name: str | None = None,
        joints: str | Sequence[str] | None = None,
        fixed: Sequence[str] | None = None,
        **options: Any,
    ) -> _RobotT:
        """Load an MJCF (``.xml``) or URDF (``.urdf``) file.

        Fixed URDF links stay bodies, so ``tool0`` or ``panda_hand`` can be a frame.

        Args:
            path: The file.
            ee: The frame the robot is a chain to, as for the ``Robot`` constructor.
            name: A label; default the file's stem.
            joints: Which joints move, as for the ``Robot`` constructor
                (``joints="all", floating_base=True`` is a whole humanoid).
            fixed: Joints never moved, as for the ``Robot`` constructor.
            **options: For :func:`redik.models.loading.load_spec`: ``meshes=False`` for a
                kinematics-only model, ``visual``, ``package_paths`` for ``package://``
                meshes, ``floating_base``, ``keep_fixed_links``.

        Returns:
            The robot.

        Raises:
            ModelError: The file or a mesh is missing, or MuJoCo cannot compile the model.
        """
        model = loading.compile_spec(loading.load_spec(path, **options), str(path))
        return cls(model, ee=ee, name=name or Path(path).stem, joints=joints, fixed=fixed)

    @classmethod
    def from_xml_string(
        cls: type[_RobotT],
        xml: str,
        ee: str | None = None,
        name: str | None = None,
        *,
        joints: str | Sequence[str] | None = None,
        fixed: Sequence[str] | None = None,
        **options: Any,
    ) -> _RobotT:
        """Build from an MJCF or URDF string.

        Args:
            xml: The description.
            ee: As for :meth:`from_file`.
            name: A label; default the model's name.
            joints: As for :meth:`from_file`.
            fixed: As for :meth:`from_file`.
            **options: For :func:`redik.models.loading.load_spec_from_string`.

        Returns:
            The robot.

        Raises:
            ModelError: MuJoCo cannot compile the string.
        """
        spec = loading.load_spec_from_string(xml, **options)
        model = loading.compile_spec(spec, "the model string")
        return cls(model, ee=ee, name=name, joints=joints, fixed=fixed)

    @classmethod
    def from_dh(
        cls: type[_RobotT],
        rows: Iterable[RowLike],
        convention: str = "standard",
        limits: Sequence[Sequence[float]] | None = None,
        tool: NDArray[np.float64] | None = None,
        *,
        name: str = "dh_robot",
        home: Sequence[float] | None = None,
        **builder_options: Any,
    ) -> _RobotT:
        """Build from a Denavit–Hartenberg table.

        Spong et al., *Robot Modeling and Control*, §3.2 (standard); Craig, *Introduction to
        Robotics*, §3.4 (modified). The generated MJCF places the ``ee`` site at the last frame, so
        ``robot.fk(q)`` equals the table's ``T_0n(q) · tool``.

        Args:
            rows: The table, one row per joint (:func:`redik.models.dh.parse_rows`).
            convention: ``"standard"`` (Spong/Paul: ``Rz(θ) Tz(d) Tx(a) Rx(α)``) or
                ``"modified"`` (Craig: ``Rx(α) Tx(a) Rz(θ) Tz(d)``).
            limits: Joint ranges, n × 2.
            tool: The flange-to-tool transform (4, 4), or a row.
            name: The model's name.
            home: The ``home`` keyframe's joint values.
            **builder_options: For :func:`redik.models.builder.dh_to_mjcf` (``radius``,
                ``actuators``, ``custom``, …).

        Returns:
            The robot, a chain to ``ee``.
        """
        xml = dh_to_mjcf(rows, convention, limits, tool, name=name, home=home, **builder_options)
        return cls.from_xml_string(xml, name=name)

    @classmethod
    def from_screws(
        cls: type[_RobotT],
        screws: NDArray[np.float64],
        M: NDArray[np.float64],
        frame: str = "space",
        limits: Sequence[Sequence[float]] | None = None,
        *,
        name: str = "poe_robot",
        home: Sequence[float] | None = None,
        **builder_options: Any,
    ) -> _RobotT:
        """Build from a product of exponentials (Modern Robotics §4.1).

        ``robot.fk(q) = e^{[S_1] q_1} ⋯ e^{[S_n] q_n} M`` (space screws) or
        ``M e^{[B_1] q_1} ⋯ e^{[B_n] q_n}`` (body screws).

        Args:
            screws: 6 × n, columns ``S_i = (ω_i, v_i)`` in Modern Robotics' order (the one
                input in that order, :mod:`redik.core.conventions`).
            M: The home pose of the end-effector (4, 4).
            frame: ``"space"`` for space screws ``S_i``, ``"body"`` for body screws ``B_i``.
            limits: Joint ranges, n × 2.
            name: The model's name.
            home: The ``home`` keyframe's joint values.
            **builder_options: For :func:`redik.models.builder.screws_to_mjcf`.

        Returns:
            The robot, a chain to ``ee``.
        """
        xml = screws_to_mjcf(screws, M, frame, limits, name=name, home=home, **builder_options)
        return cls.from_xml_string(xml, name=name)


def load(name: str | os.PathLike[str], ee: str | None = None, **options: Any) -> Robot:
    """Load a bundled scene by name (``redik.load("panda")``) or any MJCF/URDF file by path.

    Example::

        redik.load("example-robot-data:ur5", ee="tool0", meshes=False)

    Args:
        name: Anything :func:`redik.models.scenes.scene_path` accepts.
        ee: As for :meth:`RobotLoading.from_file`.
        **options: For :meth:`RobotLoading.from_file` (``joints``, ``fixed``) and on to
            :func:`redik.models.loading.load_spec` (``meshes=False`` for kinematics only,
            ``visual``, ``package_paths``, ``floating_base``, ``keep_fixed_links``).

    Returns:
        The robot.

    Raises:
        InvalidInput: ``name`` is neither a string nor a path.
        ModelError: No such scene or file, or MuJoCo cannot compile it.
        UnknownFrame: ``ee`` names no site, body or geom of the model.
    """
    from redik.kinematics.robot.robot import Robot  # Robot derives from RobotLoading above

    return Robot.from_file(scenes.scene_path(name), ee=ee, **options)
