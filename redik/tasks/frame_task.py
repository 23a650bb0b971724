r"""Regulate the full pose of a frame (mink's ``FrameTask``).

:math:`e = \log(T^{-1} T_d)`, a body twist.

.. math::

    e(q) = \log\big(T(q)^{-1} T_d\big) \in \mathbb{R}^6, \qquad
    J(q) = -J_l^{-1}(e)\, J_b(q) = -J_l^{-1}(e)
    \begin{pmatrix} R^\top & 0 \\ 0 & R^\top \end{pmatrix} J_w(q)

with :math:`J_w` the world Jacobian and :math:`J_b` the body Jacobian
(:mod:`redik.core.conventions`), and :math:`J_l^{-1}` the SE(3) inverse left Jacobian
(:func:`redik.lie.se3_left_jacobian_inverse`; why it appears:
:mod:`redik.tasks.single_frame_task`).
These are the error and Jacobian of ``mink.FrameTask``, so the two give the same step.

The error is :math:`\log` of :math:`T^{-1} T_d = (R^\top R_d,\; R^\top (p_d - p))`: the
rotation part :math:`ω = R^\top \log(R_d R^\top)` from the world-frame error of the compiled
solver kernel (:func:`redik.kinematics.compiled.pose_error`, robust at every angle), the
translation part :math:`v = V(ω)^{-1} R^\top (p_d - p)` by :func:`redik.lie.apply_inverse_v`,
as in :func:`redik.lie.se3_log`. Error, body Jacobian and the 6 × 6 inverse Jacobian
(:func:`redik.lie.se3_left_jacobian_inverse_entries`) are fused in one compiled function,
:func:`pose_residual`: this residual is the bulk of a QP step, and as Python scalar code it
cost about half of one. ``tests/test_tasks.py`` pins it to ``mink.FrameTask``'s error and
Jacobian and to finite differences.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.core.exceptions import InvalidInput
from redik.core.rotation_policy import as_pose
from redik.kinematics.compiled import pose_error
from redik.lie import apply_inverse_v, se3_left_jacobian_inverse_entries
from redik.tasks.kinematics import KinematicState
from redik.tasks.single_frame_task import SingleFrameTask
from redik.tasks.task import as_cost

if TYPE_CHECKING:
    from mink import SE3, Configuration


def as_target_pose(
    target: object, name: str = "target", *, strict: bool = False
) -> NDArray[np.float64]:
    """A 4 × 4 target pose from an array or anything with ``as_matrix()``.

    A 4 × 4 target pose from an array or anything with ``as_matrix()`` (``mink.SE3``), under
    :mod:`~redik.core.rotation_policy`.
    """
    if hasattr(target, "as_matrix"):
        target = target.as_matrix()
    return as_pose(target, name=name, strict=strict).copy()


_ONES = np.ones(6)
_MINUS_ONES = -_ONES
_NO_COLUMNS = np.empty((6, 0))
"""A Jacobian without columns: :func:`pose_residual` then computes the error alone."""


@numba.njit(cache=True)
def pose_residual(
    R: NDArray[np.float64],
    p: NDArray[np.float64],
    R_d: NDArray[np.float64],
    p_d: NDArray[np.float64],
    J_world: NDArray[np.float64],
    row_scale: NDArray[np.float64],
    error_scale: NDArray[np.float64],
    A: NDArray[np.float64],
    b: NDArray[np.float64],
) -> None:
    """``A = diag(row_scale) J_l⁻¹(e) blockdiag(Rᵀ, Rᵀ) J_w`` and ``b = error_scale ⊙ e``.

    ``e = log(T⁻¹ T_d) = (v, ω)`` (module docstring). With ``row_scale = −1`` and
    ``error_scale = 1`` these are the task's Jacobian ``J`` and error ``e``.
    """
    world = np.empty(6)
    pose_error(R_d, p_d, R, p, world)
    # Into the frame's own axes: d = Rᵀ(p_d − p), ω = Rᵀ log(R_d Rᵀ) = log(Rᵀ R_d).
    dx = R[0, 0] * world[0] + R[1, 0] * world[1] + R[2, 0] * world[2]
    dy = R[0, 1] * world[0] + R[1, 1] * world[1] + R[2, 1] * world[2]
    dz = R[0, 2] * world[0] + R[1, 2] * world[1] + R[2, 2] * world[2]
    wx = R[0, 0] * world[3] + R[1, 0] * world[4] + R[2, 0] * world[5]
    wy = R[0, 1] * world[3] + R[1, 1] * world[4] + R[2, 1] * world[5]
    wz = R[0, 2] * world[3] + R[1, 2] * world[4] + R[2, 2] * world[5]
    e = np.empty(6)
    e[0], e[1], e[2] = apply_inverse_v(wx, wy, wz, dx, dy, dz)  # v = V(ω)⁻¹ d
    e[3], e[4], e[5] = wx, wy, wz
    F = se3_left_jacobian_inverse_entries(e[0], e[1], e[2], wx, wy, wz)
    column = np.empty(6)
    for j in range(J_world.shape[1]):
        for k in range(3):
            column[k] = R[0, k] * J_world[0, j] + R[1, k] * J_world[1, j] + R[2, k] * J_world[2, j]
            column[3 + k] = (
                R[0, k] * J_world[3, j] + R[1, k] * J_world[4, j] + R[2, k] * J_world[5, j]
            )
        for i in range(6):
            total = 0.0
            for k in range(6):
                total += F[6 * i + k] * column[k]
            A[i, j] = row_scale[i] * total
    for i in range(6):
        b[i] = error_scale[i] * e[i]


class FrameTask(SingleFrameTask):
    """Drive a frame to a target pose ``T_d`` (4 × 4, world frame).

    Mink's ``FrameTask``, with mink's signature.

    Error ``log(T⁻¹ T_d)`` (a body twist) and its Jacobian are those of ``mink.FrameTask``
    (equal to 1e-12, ``tests/test_mink_interop.py``), so code written for mink reads the
    same::

        task = redik.FrameTask("attachment_site", "site", position_cost=1.0,
                               orientation_cost=1.0)
        task.set_target(T)  # or task.set_target_from_configuration(configuration)

        task = redik.FrameTask("ee", target=T)  # redik's defaults: the kind looked up, costs 1

    Args:
        frame_name: The site, body or geom name.
        frame_type: ``"site"``, ``"body"`` or ``"geom"`` (mink's ``frame_type``); None looks
            the name up as a site, body, then geom.
        position_cost: Cost of the linear part ``v`` of the error (scalar or 3; default 1).
        orientation_cost: Cost of the angular part ``ω`` (scalar or 3; default 1).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        lm_damping: mink's Levenberg–Marquardt scale ``λ ≥ 0``: adds ``λ‖α W e‖² I`` to the
            Hessian (:class:`~redik.tasks.task.ResidualTask`), damping the step towards an
            infeasible target.
        target: The target pose ``T_wd`` (4 × 4 array or ``mink.SE3``), or None (mink's way)
            to set it later (:meth:`set_target`, :meth:`set_target_from_configuration`; using
            the task before raises :class:`~redik.core.exceptions.TargetNotSet`).
        priority: Priority level, 0 highest (mink has none).
        strict: Refuse a near-rotation target instead of projecting it onto SO(3) with a
            warning (:mod:`~redik.core.rotation_policy`); also the default of
            :meth:`set_target`.
    """

    def __init__(
        self,
        frame_name: str,
        frame_type: str | None = None,
        position_cost: ArrayLike = 1.0,
        orientation_cost: ArrayLike = 1.0,
        gain: float = 1.0,
        lm_damping: float = 0.0,
        *,
        target: object = None,
        priority: int = 0,
        strict: bool = False,
    ):
        super().__init__(frame_name, frame_type, 1.0, gain, priority, 6, lm_damping=lm_damping)
        self.cost[:3] = as_cost(position_cost, 3, "position_cost")
        self.cost[3:] = as_cost(orientation_cost, 3, "orientation_cost")
        self.strict = strict
        if target is not None:
            self.set_target(target)
        self._scales_version = -1
        self._waits = (True, True)  # pose_errors' parts of nonzero cost, per cost version
        self._scratch = np.empty(6)

    def set_position_cost(self, position_cost: ArrayLike) -> None:
        """Replace the cost of the linear part (scalar or 3 values)."""
        self.cost[:3] = as_cost(position_cost, 3, "position_cost")
        self.version += 1

    def set_orientation_cost(self, orientation_cost: ArrayLike) -> None:
        """Replace the cost of the angular part (scalar or 3 values)."""
        self.cost[3:] = as_cost(orientation_cost, 3, "orientation_cost")
        self.version += 1

    def set_target(self, target: object, *, strict: bool | None = None) -> None:
        """Replace the target pose (validated; ``strict`` defaults to the task's)."""
        self.target = as_target_pose(target, strict=self.strict if strict is None else strict)
        self._R_d = self.target[:3, :3].copy()
        self._p_d = self.target[:3, 3].copy()

    def set_target_from_configuration(self, configuration: Configuration) -> None:
        """The target is the frame's current pose in ``configuration`` (mink's setter).

        mink's: the target is the frame's current pose in ``configuration`` (a
        ``mink.Configuration``). A task bound to a robot reads it through the robot; an unbound one
        needs ``frame_type`` (mink's lookup by name and type).
        """
        if self.robot is None and self.frame_type is not None:
            if not hasattr(configuration, "get_transform_frame_to_world"):
                raise InvalidInput(
                    f"configuration must be a mink.Configuration, got {configuration!r}"
                )
            self.set_target(
                configuration.get_transform_frame_to_world(self.frame_name, self.frame_type)
            )
            return
        R, p = self._state(configuration).pose(self.frame)
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = R, p
        self.set_target(T)

    @property
    def transform_target_to_world(self) -> SE3 | None:
        """The target as a ``mink.SE3`` (mink's name), or None before one is set."""
        from mink import SE3  # redik tasks already depend on mink; imported where used

        return None if self.target is None else SE3.from_matrix(self.target)

    def _refresh_scales(self) -> None:
        if self._scales_version != self.version:
            self._row_scale = -self.cost
            self._error_scale = -self.gain * self.cost
            self._waits = (bool(self.cost[:3].any()), bool(self.cost[3:].any()))
            self._scales_version = self.version

    def residual_into(
        self, state: KinematicState, e: NDArray[np.float64], J: NDArray[np.float64]
    ) -> None:
        """Write the error into ``e`` and its Jacobian into ``J`` (module docstring)."""
        if self.target is None:
            self._require_target()
        R, p = state.pose(self.frame)
        jacobian = state.jacobian(self.frame)
        pose_residual(R, p, self._R_d, self._p_d, jacobian, _MINUS_ONES, _ONES, J, e)

    def error_into(self, state: KinematicState, e: NDArray[np.float64]) -> None:
        """Write the error ``log(T⁻¹ T_d)`` alone into ``e`` (no Jacobian computed)."""
        if self.target is None:
            self._require_target()
        R, p = state.pose(self.frame)
        pose_residual(R, p, self._R_d, self._p_d, _NO_COLUMNS, _MINUS_ONES, _ONES, _NO_COLUMNS, e)

    def weighted_residual_into(
        self, state: KinematicState, A: NDArray[np.float64], b: NDArray[np.float64]
    ) -> None:
        """Write ``A = W J`` and ``b = −α W e`` (the hot path)."""
        if self.target is None:
            self._require_target()
        self._refresh_scales()
        R, p = state.pose(self.frame)
        jacobian = state.jacobian(self.frame)
        pose_residual(
            R, p, self._R_d, self._p_d, jacobian, self._row_scale, self._error_scale, A, b
        )

    def pose_errors(self, state: KinematicState) -> tuple[float | None, float | None]:
        """``(‖p_d − p‖, angle(Rᵀ R_d))`` at ``state``; None for a part of zero cost.

        A task with ``orientation_cost=0`` (mink's way to ask for a position only) does not
        wait for the orientation, and one with ``position_cost=0`` not for the position.
        """
        if self.target is None:
            self._require_target()
        self._refresh_scales()
        R, p = state.pose(self.frame)
        position, rotation = pose_error(self._R_d, self._p_d, R, p, self._scratch)
        return (position if self._waits[0] else None, rotation if self._waits[1] else None)
