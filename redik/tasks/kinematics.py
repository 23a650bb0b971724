"""The kinematic snapshot a task reads: frame poses, world Jacobians and the robot's ``q``.

A redik task is evaluated in two settings, and both hand it a :class:`KinematicState`:

- inside a :class:`redik.Problem` (the hot path), the state wraps the robot's own
  ``MjData`` after **one** ``robot.state.update(q)`` per step, and Jacobians have one column per
  tangent coordinate of the robot's joints (``robot.dof`` columns, :mod:`redik.kinematics.robot`);
- inside ``mink.solve_ik`` (interoperability), the state wraps the ``mink.Configuration``'s
  data, and Jacobians have one column per degree of freedom of the model (``model.nv``),
  the robot's sitting at ``robot.dof_indices``.

Jacobians are MuJoCo's ``"world"`` Jacobians of :mod:`redik.core.conventions` (origin velocity
and angular velocity in world axes, ``(v, ω)`` order). They are computed at most once per
frame and per update, into preallocated buffers.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Frame, Robot, frame_jacobian, frame_pose_views

if TYPE_CHECKING:
    from mink import Configuration


class KinematicState:
    """Frame poses and Jacobians of one configuration, computed lazily and cached.

    Attributes:
        robot: The robot whose chain defines ``q`` and the frames.
        q: The robot's configuration (``robot.nq``,) (on a chain, its joint values).
        n_columns: Number of Jacobian columns (``robot.dof`` or ``model.nv``).
        chain_columns: Column of each of the robot's tangent coordinates among the
            ``n_columns``.
    """

    def __init__(self, robot: Robot, model: mujoco.MjModel, data: mujoco.MjData, full: bool):
        self.robot = robot
        self.model = model
        self.data = data
        self._full = full
        self.n_columns = model.nv if full else robot.dof
        self.chain_columns = robot.dof_indices if full else np.arange(robot.dof)
        self.q = np.zeros(robot.nq)
        self._jacobians: dict[Frame, NDArray[np.float64]] = {}
        self._fresh: set[Frame] = set()
        # Views into data (its arrays never move), so reading a pose allocates nothing.
        self._views: dict[Frame, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}
        self._jacp = np.zeros((3, model.nv))
        self._jacr = np.zeros((3, model.nv))

    @classmethod
    def for_robot(cls, robot: Robot) -> KinematicState:
        """A state on the robot's own data with ``robot.dof`` Jacobian columns (hot path)."""
        return cls(robot, robot.model, robot.state.data, full=False)

    @classmethod
    def for_configuration(cls, robot: Robot, configuration: Configuration) -> KinematicState:
        """A state on a ``mink.Configuration`` (already updated) with ``model.nv`` columns."""
        model = configuration.model
        if model.nq != robot.model.nq or model.nv != robot.model.nv:
            raise InvalidInput(
                f"the configuration's model (nq={model.nq}, nv={model.nv}) is not the model of "
                f"{robot!r} (nq={robot.model.nq}, nv={robot.model.nv})"
            )
        state = cls(robot, model, configuration.data, full=True)
        state.q[:] = configuration.data.qpos[robot.qpos_indices]
        return state

    def update(self, q: NDArray[np.float64]) -> None:
        """Run forward kinematics at ``q`` (robot path only; no checks)."""
        self.robot.state.update(q)
        self.q[:] = q
        self._fresh.clear()

    def pose(self, frame: Frame) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Views ``(R, p)`` of the frame's world rotation (3 × 3) and position (3,)."""
        views = self._views.get(frame)
        if views is None:
            views = self._views[frame] = frame_pose_views(self.data, frame)
        return views

    def point_jacobian(self, body: int, point: NDArray[np.float64]) -> NDArray[np.float64]:
        """The world Jacobian (6 × ``n_columns``, fresh) of a point fixed to ``body``.

        Rows ``ṗ`` then ``ω`` in world axes (``mj_jac``) at the world point ``point``.
        """
        mujoco.mj_jac(self.model, self.data, self._jacp, self._jacr, point, body)
        J = np.empty((6, self.n_columns))
        columns = slice(None) if self._full else self.robot.dof_indices
        J[:3] = self._jacp[:, columns]
        J[3:] = self._jacr[:, columns]
        return J

    def jacobian(self, frame: Frame) -> NDArray[np.float64]:
        """The world Jacobian (6 × ``n_columns``) of ``frame``; do not modify it."""
        J = self._jacobians.get(frame)
        if J is None:
            J = self._jacobians[frame] = np.empty((6, self.n_columns))
        elif frame in self._fresh:
            return J
        if not self._full:
            self.robot.state.world_jacobian_into(frame, J)
        else:
            frame_jacobian(self.model, self.data, frame, self._jacp, self._jacr)
            J[:3] = self._jacp
            J[3:] = self._jacr
        self._fresh.add(frame)
        return J
