r"""Regulate the full pose of a frame: :math:`e = \log(T^{-1} T_d)`, a body twist.

.. math::

    e(q) = \log\big(T(q)^{-1} T_d\big) \in \mathbb{R}^6, \qquad
    J(q) = -J_l^{-1}(e)\, J_b(q) = -J_l^{-1}(e)
    \begin{pmatrix} R^\top & 0 \\ 0 & R^\top \end{pmatrix} J_w(q)

with :math:`J_w` the world Jacobian and :math:`J_b` the body Jacobian
(:mod:`redik.conventions`), and :math:`J_l^{-1}` the SE(3) inverse left Jacobian
(:mod:`redik.tasks.frame_task`). These are the error and Jacobian of ``mink.FrameTask``,
so the two give the same step.

The error is :math:`\log` of :math:`T^{-1} T_d = (R^\top R_d,\; R^\top (p_d - p))`: the
rotation part through MuJoCo's quaternion routines (``mju_mat2Quat``, ``mju_quat2Vel``,
robust at every angle), the translation part :math:`v = V(ω)^{-1} R^\top (p_d - p)` as in
:func:`redik.lie.se3_log`. The 6 × 6 factor :math:`-J_l^{-1}(e)\,\mathrm{blockdiag}(R^\top,
R^\top)` is applied as two products: the body Jacobian, then the 6 × 6 inverse Jacobian
(closed form, :mod:`redik.tasks.frame_task`), weighted.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from .. import lie
from .frame_task import FrameTask, se3_left_jacobian_inverse_entries
from .kinematics import KinematicState
from .task import as_weight


def as_target_pose(target, name: str = "target") -> np.ndarray:
    """A 4 × 4 target pose from an array or anything with ``as_matrix()`` (``mink.SE3``)."""
    if hasattr(target, "as_matrix"):
        target = target.as_matrix()
    return lie.as_pose(target, name=name).copy()


_MINUS_ONES = -np.ones((6, 1))


class PoseTask(FrameTask):
    """Drive a frame to a target pose ``T_d`` (4 × 4, world frame).

    Args:
        target: The target pose ``T_wd`` (4 × 4 array or ``mink.SE3``).
        frame: Site or body name; None is the robot's end-effector.
        position_weight: Weight of the linear part ``v`` of the error (scalar or 3).
        orientation_weight: Weight of the angular part ``ω`` (scalar or 3).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        priority: Priority level, 0 highest.
    """

    def __init__(
        self,
        target,
        frame: str | None = None,
        position_weight=1.0,
        orientation_weight=1.0,
        gain: float = 1.0,
        priority: int = 0,
    ):
        super().__init__(frame, 1.0, gain, priority, size=6)
        self.set_weights(position_weight, orientation_weight)
        self.set_target(target)
        self._R_rel = np.empty((3, 3))
        self._R_rel_flat = self._R_rel.reshape(9)
        self._dp = np.empty(3)
        self._quat = np.empty(4)
        self._omega = np.empty(3)
        self._J_body = np.empty((6, 0))
        self._factor = np.empty((6, 6))
        self._factor_flat = self._factor.reshape(36)
        self._scales_version = -1

    def set_weights(self, position_weight, orientation_weight) -> None:
        """Weights of the linear and angular parts (each a scalar or 3 values)."""
        self.cost[:3] = as_weight(position_weight, 3, "position_weight")
        self.cost[3:] = as_weight(orientation_weight, 3, "orientation_weight")
        self.version += 1

    def set_target(self, target) -> None:
        """Replace the target pose (validated)."""
        self.target = as_target_pose(target)
        self._R_d = self.target[:3, :3].copy()
        self._p_d = self.target[:3, 3].copy()

    def _error(self, state: KinematicState) -> tuple[np.ndarray, tuple]:
        """``e = log(T⁻¹ T_d)`` as six floats, with ``Rᵀ`` of the current pose."""
        R, p = state.pose(self.frame)
        Rt = R.T
        np.dot(Rt, self._R_d, out=self._R_rel)
        np.subtract(self._p_d, p, out=self._dp)
        dx, dy, dz = np.dot(Rt, self._dp).tolist()
        mujoco.mju_mat2Quat(self._quat, self._R_rel_flat)
        mujoco.mju_quat2Vel(self._omega, self._quat, 1.0)
        wx, wy, wz = self._omega.tolist()
        theta2 = wx * wx + wy * wy + wz * wz
        if theta2 < 1e-12:
            c = 1.0 / 12.0 + theta2 / 720.0
        else:
            half = 0.5 * math.sqrt(theta2)
            c = (1.0 - half * math.cos(half) / math.sin(half)) / theta2
        # v = V(ω)⁻¹ d = d − ½ ω × d + c ω × (ω × d)
        cx, cy, cz = wy * dz - wz * dy, wz * dx - wx * dz, wx * dy - wy * dx
        ccx, ccy, ccz = wy * cz - wz * cy, wz * cx - wx * cz, wx * cy - wy * cx
        vx, vy, vz = dx - 0.5 * cx + c * ccx, dy - 0.5 * cy + c * ccy, dz - 0.5 * cz + c * ccz
        return Rt, (vx, vy, vz, wx, wy, wz)

    def _factor_times_jacobian(
        self,
        state: KinematicState,
        Rt: np.ndarray,
        error: tuple,
        row_scale: np.ndarray,
        out: np.ndarray,
    ) -> None:
        """``out = diag(row_scale) J_l⁻¹(e) blockdiag(Rᵀ, Rᵀ) J_w``."""
        J_world = state.jacobian(self.frame)
        n = J_world.shape[1]
        if self._J_body.shape[1] != n:
            self._J_body = np.empty((6, n))
        np.dot(Rt, J_world[:3], out=self._J_body[:3])
        np.dot(Rt, J_world[3:], out=self._J_body[3:])
        self._factor_flat[:] = se3_left_jacobian_inverse_entries(*error)
        self._factor *= row_scale
        np.dot(self._factor, self._J_body, out=out)

    def _refresh_scales(self) -> None:
        if self._scales_version != self.version:
            self._row_scale = -self.cost[:, None]
            self._error_scale = (-self.gain * self.cost).tolist()
            self._scales_version = self.version

    def residual_into(self, state: KinematicState, e: np.ndarray, J: np.ndarray) -> None:
        Rt, error = self._error(state)
        e[:] = error
        self._factor_times_jacobian(state, Rt, error, _MINUS_ONES, J)

    def weighted_residual_into(self, state: KinematicState, A: np.ndarray, b: np.ndarray) -> None:
        self._refresh_scales()
        Rt, error = self._error(state)
        self._factor_times_jacobian(state, Rt, error, self._row_scale, A)
        s = self._error_scale
        b[:] = (
            s[0] * error[0],
            s[1] * error[1],
            s[2] * error[2],
            s[3] * error[3],
            s[4] * error[4],
            s[5] * error[5],
        )

    def pose_errors(self, state: KinematicState) -> tuple[float, float]:
        R, p = state.pose(self.frame)
        return (
            float(np.linalg.norm(self._p_d - p)),
            lie.rotation_angle(R, self._R_d),
        )
