r"""The range of a ball joint: its rotation angle stays below ``range[1]``.

MuJoCo limits a ball joint by the angle :math:`θ = \|e\|` of its rotation, :math:`e = \log Q`
(``mju_quat2Vel``; ``range = [0, θ_{max}]``), a cone, which no box on the three tangent
coordinates describes. A step :math:`Q \to Q \otimes \exp(δ)` (``mj_integratePos``, body
axes) changes :math:`e` by :math:`J_r^{-1}(e)\, δ` to first order, and :math:`e^\top
J_r^{-1}(e) = e^\top`, so

.. math::

    θ' = θ + \hat e^\top δ + O(\|δ\|^2), \qquad \hat e = e / θ,

and the row :math:`\hat e^\top δ \le θ_{max} - m - θ` (margin :math:`m` plus the back-end's
tolerance) keeps the angle inside to first order; a joint outside its cone is pulled back.
mink's ``ConfigurationLimit`` uses the same row (with a gain). At the identity
(:math:`θ = 0`) the row is undefined and left out, as mink does, so a long first step
could leave the cone (mink's own limit does: a posture 1.5 rad away from a 1.2 rad cone
is reached in one step from the identity). :meth:`BallJointLimit.admits` checks the true
angle of a trial configuration, and :func:`redik.solve_problem` shortens the step until
every angle is inside (or, for a joint already outside, no farther out). Sliding along
the cone's rim costs second-order overshoot that the driver also shortens: it may stall
there, inside the cone, rather than leave it.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Robot
from redik.limits.limit import InequalityLimit

_ANGLE_TOLERANCE = 1e-9
"""Radians by which :meth:`BallJointLimit.admits` lets an angle exceed its bound (rounding)."""


def limited_ball_joints(robot: Robot) -> list[int]:
    """The MuJoCo ids of the limited ball joints ``robot`` moves (those with a cone)."""
    return [
        int(j)
        for j, kind in zip(robot.joint_ids, robot.joint_types, strict=True)
        if kind == "ball" and robot.model.jnt_limited[j]
    ]


class BallJointLimit(InequalityLimit):
    """Keep every limited ball joint the robot moves inside its cone ``range[1]``.

    Args:
        margin: Angle (rad) to keep from each cone's rim, ≥ 0.
        priority: None (default): hard at every level; ``k``: ranked just above the tasks
            of priority ``k`` (:mod:`redik.limits.limit`).

    Attributes:
        joint_names: The limited ball joints, once bound.
        max_angle: Their bounds ``range[1] − margin − tolerance`` (rad).
    """

    def __init__(self, margin: float = 0.0, *, priority: int | None = None):
        try:
            margin = float(margin)
        except (TypeError, ValueError):
            raise InvalidInput(f"margin must be a number, got {margin!r}") from None
        if not (np.isfinite(margin) and margin >= 0.0):
            raise InvalidInput(f"margin must be finite and >= 0, got {margin}")
        self.margin = margin
        self._set_priority(priority)
        self.joint_names: tuple[str, ...] = ()
        self.max_angle = np.empty(0)

    def bind(self, robot: Robot, tolerance: float = 0.0) -> BallJointLimit:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        model = robot.model
        joints = limited_ball_joints(robot)
        self.joint_names = tuple(robot.joint_names[list(robot.joint_ids).index(j)] for j in joints)
        self.max_angle = np.array([model.jnt_range[j, 1] for j in joints]) - self.margin - tolerance
        if np.any(self.max_angle <= 0.0):
            raise InvalidInput(
                f"BallJointLimit: margin {self.margin} leaves no cone for ball joints "
                f"{self.joint_names} of ranges {[model.jnt_range[j, 1] for j in joints]} rad"
            )
        dof_index = {int(d): i for i, d in enumerate(robot.dof_indices)}
        self._qpos = [int(model.jnt_qposadr[j]) for j in joints]
        self._columns = [dof_index[int(model.jnt_dofadr[j])] for j in joints]
        self._rotation = np.zeros(3)
        self._floor = self.max_angle.copy()
        self._G = np.zeros((len(joints), robot.dof))
        self._h = np.zeros(len(joints))
        super().bind(robot, tolerance)
        return self

    def angles_at(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """The rotation angle (rad) of each joint of :attr:`joint_names` at ``q``."""
        robot = self._require_robot()
        qpos = robot.full_qpos(robot.check_q(q))
        return np.array([self._angle(qpos, i) for i in range(len(self._columns))])

    def _angle(self, qpos: NDArray[np.float64], i: int) -> float:
        """The rotation angle of joint ``i``; its rotation vector left in ``_rotation``."""
        start = self._qpos[i]
        mujoco.mju_quat2Vel(self._rotation, qpos[start : start + 4], 1.0)
        return float(np.linalg.norm(self._rotation))

    def inequalities(
        self, state: Any, dt: float | None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
        """``(G, h)`` at the current state, or None when inactive."""
        qpos = self._require_robot().state.data.qpos
        G, h = self._G, self._h
        count = 0
        for i, column in enumerate(self._columns):
            angle = self._angle(qpos, i)
            self._floor[i] = max(self.max_angle[i], angle)
            if angle < 1e-9:
                continue  # at the identity the axis is undefined; admits() guards the step
            G[count].fill(0.0)
            np.divide(self._rotation, angle, out=G[count, column : column + 3])
            h[count] = self.max_angle[i] - angle
            count += 1
        if count == 0:
            return None
        return G[:count].copy(), h[:count].copy()

    def admits(self) -> bool:
        """Whether every cone angle holds at the current state (module docstring).

        Every angle within its bound at the current state, or no farther out than at the last
        linearisation (an angle out by no more than the tolerance, an earlier step's slack, is held
        to its bound again: else the slack compounds step after step).
        """
        qpos = self._require_robot().state.data.qpos
        for i in range(len(self._columns)):
            bound = self.max_angle[i]
            floor = self._floor[i] if self._floor[i] > bound + _ANGLE_TOLERANCE else bound
            if self._angle(qpos, i) > floor + _ANGLE_TOLERANCE:
                return False
        return True
