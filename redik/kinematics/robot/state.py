"""The kinematic state of a robot: one ``MjData``, its forward kinematics, frames read in place.

:class:`RobotState` is what a solver or a task reads in its loop, as mink's ``Configuration``
is: :meth:`RobotState.update` writes ``q`` into ``data.qpos`` and runs MuJoCo's forward
kinematics, then frame poses are views into ``data`` and world Jacobians are written into
caller-owned buffers (MuJoCo's ``mj_jacSite``/``mj_jacBody``/``mj_jacGeom``), nothing checked
and nothing allocated. ``q`` is the robot's joint vector (``robot.nq`` entries, not
``model.nq``): the entries of ``data.qpos`` that are not the robot's hold the values of the
joints it does not move (their ``home`` keyframe values, or those a chain was cut at).
Frames, twist order and the ``"world"`` Jacobian are those of :mod:`redik.core.conventions`.

Threads: one state serves one thread at a time. :attr:`redik.Robot.state` is the state the
robot's own checked calls (``fk``, ``jacobian``) and most solvers use, so a robot shared
between threads is safe only for what never writes it once built: :func:`redik.solve_pose`
with ``method="dls"`` and ``respect_limits=True``, and :func:`redik.solve_batch`. Other
solvers need one :class:`~redik.Robot` per thread (build each from the same ``model``).
"""

from __future__ import annotations

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.robot.frames import FRAME_JACOBIANS, Frame, frame_pose_views


class RobotState:
    """Forward kinematics of a set of joints on one ``MjData``, read into buffers.

    Args:
        model: The MuJoCo model.
        qpos_indices: Where the robot's ``q`` sits in ``model.qpos`` (``robot.qpos_indices``).
        dof_indices: Where its tangent coordinates sit in ``model.qvel``, i.e. the columns of
            its Jacobians among MuJoCo's (``robot.dof_indices``).
        qpos: The full ``qpos`` to start from; its other entries are the held joints' values.

    Attributes:
        model: The :class:`mujoco.MjModel`.
        data: The :class:`mujoco.MjData` that :meth:`update` writes; its ``qpos`` holds the
            last ``q`` and the held joints' values.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        qpos_indices: NDArray[np.intp],
        dof_indices: NDArray[np.intp],
        qpos: NDArray[np.float64],
    ):
        self.model = model
        self.data = mujoco.MjData(model)
        self.data.qpos[:] = qpos
        # A slice writes faster than fancy indexing when the joints are contiguous in qpos,
        # and MuJoCo can write straight into the caller's J when the joints are every dof.
        self._qpos_index = _as_slice(qpos_indices)
        self._dof_indices = dof_indices
        self._jacobian_is_direct = model.nv == len(dof_indices) and np.array_equal(
            dof_indices, np.arange(len(dof_indices))
        )
        self._jacp = np.zeros((3, model.nv))
        self._jacr = np.zeros((3, model.nv))
        self._views: dict[Frame, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}

    def update(self, q: NDArray[np.float64]) -> None:
        """Write ``q`` into ``data.qpos`` and run forward kinematics, unchecked.

        ``mj_kinematics`` places every body, site and geom; ``mj_comPos`` fills the ``cdof``
        that the Jacobians read.

        Args:
            q: The robot's joint vector (``robot.nq``,), validated by the caller.
        """
        self.data.qpos[self._qpos_index] = q
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)

    def pose_views(self, frame: Frame) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Views of a frame's world rotation and position inside ``data``.

        Args:
            frame: A resolved frame (``robot.frame(name)``).

        Returns:
            ``(R, p)``, (3, 3) and (3,): valid after each :meth:`update`; do not write them.
        """
        views = self._views.get(frame)
        if views is None:
            views = self._views[frame] = frame_pose_views(self.data, frame)
        return views

    def pose_into(self, frame: Frame, T: NDArray[np.float64]) -> NDArray[np.float64]:
        """Copy a frame's current pose ``T_wf`` into a caller-owned buffer.

        Args:
            frame: A resolved frame.
            T: A (4, 4) array whose bottom row is ``[0, 0, 0, 1]``; written in place.

        Returns:
            ``T``.
        """
        R, p = self.pose_views(frame)
        T[:3, :3] = R
        T[:3, 3] = p
        return T

    def world_jacobian_into(self, frame: Frame, J: NDArray[np.float64]) -> NDArray[np.float64]:
        """Write a frame's ``"world"`` Jacobian into a caller-owned buffer.

        Args:
            frame: A resolved frame.
            J: A (6, ``robot.dof``) array: rows ``ṗ`` then ``ω`` in world axes, one column per
                tangent coordinate of the robot; written in place.

        Returns:
            ``J``.
        """
        jac = FRAME_JACOBIANS[frame.kind]
        if self._jacobian_is_direct and J.flags.c_contiguous:
            jac(self.model, self.data, J[:3], J[3:], frame.id)
            return J
        jac(self.model, self.data, self._jacp, self._jacr, frame.id)
        J[:3] = self._jacp[:, self._dof_indices]
        J[3:] = self._jacr[:, self._dof_indices]
        return J

    def kinematics(
        self,
        q: NDArray[np.float64],
        frame: Frame,
        T: NDArray[np.float64],
        J: NDArray[np.float64] | None = None,
    ) -> None:
        """One forward kinematics at ``q``: the frame's pose, and its world Jacobian if asked.

        Args:
            q: The robot's joint vector, validated by the caller.
            frame: A resolved frame.
            T: Written with the pose ``T_wf`` (4, 4).
            J: Written with the world Jacobian (6, ``robot.dof``) when given.
        """
        self.update(q)
        self.pose_into(frame, T)
        if J is not None:
            self.world_jacobian_into(frame, J)


def _as_slice(indices: NDArray[np.intp]) -> slice | NDArray[np.intp]:
    """``indices`` as a slice when they are consecutive, else unchanged."""
    if len(indices) and np.array_equal(indices, np.arange(indices[0], indices[0] + len(indices))):
        return slice(int(indices[0]), int(indices[0]) + len(indices))
    return indices
