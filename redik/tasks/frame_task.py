r"""Shared ground of the tasks on a frame's pose: frame binding (:class:`FrameTargetTask`)
and the log-map Jacobians. (``redik.FrameTask`` itself, mink's name for the pose task, is
in :mod:`redik.tasks.pose_task`.)

:class:`PoseTask`, :class:`PositionTask` and :class:`OrientationTask` regulate one frame
(a site or body; ``None`` is the robot's end-effector) towards a target. Their errors are
those of :mod:`redik.core.conventions`: the body twist :math:`e = \log(T^{-1} T_d)` for a pose,
:math:`\log(R^\top R_d)` for an orientation, :math:`p - p_d` for a position.

The derivative of a log-map error needs the inverse left Jacobian of the group. Perturbing
the frame by a body twist :math:`δ = J_b Δq` (:math:`T \to T \exp(δ)`) changes
:math:`\log(T_d^{-1} T) = -e` by :math:`J_l^{-1}(e)\, δ` to first order (Barfoot, *State
Estimation for Robotics*, 2017, §7.1.5; Solà et al., *A micro Lie theory*, 2018, eq. 79),
so

.. math::

    \frac{\partial e}{\partial q} = -J_l^{-1}(e)\, J_b .

:math:`J_l^{-1}` on SO(3) and SE(3) (closed forms, and the relation to ``V(ω)⁻¹`` of the
SE(3) log) is group math: :func:`redik.lie.so3_left_jacobian_inverse` and
:func:`redik.lie.se3_left_jacobian_inverse`.
"""

from __future__ import annotations

import abc

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import FRAME_KINDS, Frame, Robot
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import ResidualTask


class FrameTargetTask(ResidualTask):
    """Base of the tasks that drive one frame to a target: :class:`~redik.tasks.PoseTask`
    (and its mink-named twin :class:`~redik.tasks.FrameTask`),
    :class:`~redik.tasks.PositionTask`, :class:`~redik.tasks.OrientationTask`. It resolves
    the frame on bind and reports the frame's pose errors (what :meth:`redik.Problem.solve`
    tests convergence on).

    Attributes:
        frame_name: The site, body or geom name given, or None for the end-effector.
        frame_type: ``"site"``, ``"body"`` or ``"geom"`` when the kind is fixed (mink's
            ``frame_type``), else None: the name is looked up as a site, body, then geom
            (:meth:`redik.Robot.frame`).
        frame: The resolved :class:`~redik.kinematics.robot.Frame` once bound.
    """

    def __init__(
        self,
        frame: str | None,
        weight,
        gain: float,
        priority: int,
        size: int,
        *,
        frame_type: str | None = None,
        lm_damping: float = 0.0,
    ):
        super().__init__(weight, gain, priority, size, lm_damping=lm_damping)
        if frame_type is not None and frame_type not in FRAME_KINDS:
            raise InvalidInput(f"frame_type must be one of {FRAME_KINDS}, got {frame_type!r}")
        if frame_type is not None and not isinstance(frame, str):
            raise InvalidInput(f"frame_name must be a string, got {frame!r}")
        self.frame_name = frame
        self.frame_type = frame_type
        self.frame: Frame | None = None

    def bind(self, robot: Robot) -> FrameTargetTask:
        name = self.frame_name
        self.frame = robot.frame(name if self.frame_type is None else f"{self.frame_type}:{name}")
        return super().bind(robot)

    @abc.abstractmethod
    def pose_errors(self, state: KinematicState) -> tuple[float | None, float | None]:
        """``(‖p_d − p‖, angle(Rᵀ R_d))`` at ``state``; None for what the task ignores."""
