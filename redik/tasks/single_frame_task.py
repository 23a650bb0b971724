r"""The base class of the tasks on one frame's target.

:class:`SingleFrameTask`, and the log-map Jacobians they share.

:class:`~redik.tasks.FrameTask`, :class:`~redik.tasks.PositionTask` and
:class:`~redik.tasks.OrientationTask` regulate one frame (a site, body or geom, named as in
mink: ``frame_name`` and ``frame_type``) towards a target. Their errors are those of
:mod:`redik.core.conventions`: the body twist :math:`e = \log(T^{-1} T_d)` for a pose,
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
from typing import NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.core.exceptions import InvalidInput, TargetNotSet
from redik.kinematics.robot import FRAME_KINDS, Frame, Robot
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import ResidualTask


class SingleFrameTask(ResidualTask):
    """Base class of the tasks that drive one frame to a target.

    :class:`~redik.tasks.FrameTask`, :class:`~redik.tasks.PositionTask`,
    :class:`~redik.tasks.OrientationTask`.

    Not a task of its own: subclasses set the target and implement
    :meth:`~redik.tasks.task.ResidualTask.residual_into` and :meth:`pose_errors`. The base
    resolves the frame on bind, refuses to run without a target, and reports the frame's
    pose errors (what :func:`redik.solve_problem` tests convergence on).

    Attributes:
        frame_name: The site, body or geom name.
        frame_type: ``"site"``, ``"body"`` or ``"geom"`` when the kind is fixed (mink's
            ``frame_type``), else None: the name is looked up as a site, body, then geom
            (:meth:`redik.Robot.frame`).
        frame: The resolved :class:`~redik.kinematics.robot.Frame` once bound.
        target: The target, or None until one is set.
    """

    frame: Frame

    def __init__(
        self,
        frame_name: str,
        frame_type: str | None,
        cost: ArrayLike,
        gain: float,
        priority: int,
        size: int,
        *,
        lm_damping: float = 0.0,
    ):
        super().__init__(cost, gain, priority, size, lm_damping=lm_damping)
        if not isinstance(frame_name, str):
            raise InvalidInput(
                f"frame_name must be the name of a site, body or geom, got {frame_name!r}"
            )
        if frame_type is not None and frame_type not in FRAME_KINDS:
            raise InvalidInput(f"frame_type must be one of {FRAME_KINDS}, got {frame_type!r}")
        self.frame_name = frame_name
        self.frame_type = frame_type
        self.target: NDArray[np.float64] | None = None

    def bind(self, robot: Robot) -> SingleFrameTask:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        name = self.frame_name
        self.frame = robot.frame(name if self.frame_type is None else f"{self.frame_type}:{name}")
        super().bind(robot)
        return self

    def _require_target(self) -> NoReturn:
        raise TargetNotSet(
            f"{type(self).__name__} on frame {self.frame_name!r} has no target: call "
            "set_target(...) first"
        )

    @abc.abstractmethod
    def pose_errors(self, state: KinematicState) -> tuple[float | None, float | None]:
        """``(‖p_d − p‖, angle(Rᵀ R_d))`` at ``state``; None for what the task ignores."""
