r"""Regulate the pose of one frame relative to another (mink's ``RelativeFrameTask``).

With :math:`T_r`, :math:`T_f` the world poses of the root and the frame, the frame's pose in
the root is :math:`T_{rf} = T_r^{-1} T_f`, and with the target :math:`T_t` (the frame's
desired pose in the root) the error and Jacobian are mink's:

.. math::

    e = \log\big(T_t^{-1} T_{rf}\big), \qquad
    J = J_r^{-1}(e)\,\big(J_{b,f} - \mathrm{Ad}(T_{rf}^{-1})\, J_{b,r}\big),

with :math:`J_{b,f}`, :math:`J_{b,r}` the body Jacobians of the frame and the root
(:mod:`redik.core.conventions`) and :math:`J_r^{-1}(e) = J_l^{-1}(-e)` the SE(3) inverse right
Jacobian (:func:`redik.lie.se3_left_jacobian_inverse`). The relative body twist follows from
:math:`T_{rf}^{-1}\dot T_{rf} = ξ_f - \mathrm{Ad}(T_{rf}^{-1}) ξ_r`, and perturbing
:math:`T_{rf} \to T_{rf}\exp(δ)` changes :math:`e` by :math:`J_r^{-1}(e)\,δ` (Solà et al., *A
micro Lie theory*, 2018, eq. 79).

Two hands holding one object: at priority 0 the task holds their relative pose exactly
(the driver meets level 0 to its tolerances), and the object is then moved by a task on one
hand below it (``examples/two_hands_hold_box.py``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.core.exceptions import InvalidInput, TargetNotSet
from redik.kinematics.robot import FRAME_KINDS, Frame, Robot
from redik.lie import adjoint, inverse, rotation_angle, se3_left_jacobian_inverse, se3_log
from redik.tasks.frame_task import as_target_pose
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import ResidualTask, as_cost

if TYPE_CHECKING:
    from mink import SE3, Configuration


def _frame_argument(name: object, kind: object, which: str) -> None:
    if not isinstance(name, str):
        raise InvalidInput(f"{which}_name must be the name of a site, body or geom, got {name!r}")
    if kind is not None and kind not in FRAME_KINDS:
        raise InvalidInput(f"{which}_type must be one of {FRAME_KINDS}, got {kind!r}")


def _resolve(robot: Robot, name: str, kind: str | None) -> Frame:
    return robot.frame(name if kind is None else f"{kind}:{name}")


def _pose(state: KinematicState, frame: Frame) -> NDArray[np.float64]:
    R, p = state.pose(frame)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def _body_jacobian(
    state: KinematicState, frame: Frame, R: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The body Jacobian ``blockdiag(Rᵀ, Rᵀ) J_w`` of ``frame`` (6 × ``n_columns``)."""
    J = state.jacobian(frame)
    return np.vstack([R.T @ J[:3], R.T @ J[3:]])


class RelativeFrameTask(ResidualTask):
    """Drive the pose of ``frame`` in ``root`` to a target (mink's ``RelativeFrameTask``).

    Args:
        frame_name: The site, body or geom whose pose is regulated.
        frame_type: ``"site"``, ``"body"`` or ``"geom"`` (mink's); None looks the name up
            as a site, body, then geom.
        root_name: The site, body or geom the pose is measured in.
        root_type: Its kind, as ``frame_type``.
        position_cost: Cost of the linear part of the error (scalar or 3; default 1).
        orientation_cost: Cost of the angular part (scalar or 3; default 1).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        lm_damping: mink's Levenberg–Marquardt scale ``λ ≥ 0``
            (:class:`~redik.tasks.task.ResidualTask`).
        target: The frame's target pose in the root, ``T_t`` (4 × 4 or ``mink.SE3``), or
            None to set it later (:meth:`set_target`, :meth:`set_target_from_configuration`).
        priority: Priority level, 0 highest (mink has none).
        strict: Refuse a near-rotation target instead of projecting it onto SO(3).

    Attributes:
        frame: The resolved frame, once bound.
        root: The resolved root, once bound.
        target: The target ``T_t`` (4 × 4), or None.
    """

    frame: Frame
    root: Frame

    def __init__(
        self,
        frame_name: str,
        frame_type: str | None,
        root_name: str,
        root_type: str | None,
        position_cost: ArrayLike = 1.0,
        orientation_cost: ArrayLike = 1.0,
        gain: float = 1.0,
        lm_damping: float = 0.0,
        *,
        target: object = None,
        priority: int = 0,
        strict: bool = False,
    ):
        super().__init__(1.0, gain, priority, 6, lm_damping=lm_damping)
        _frame_argument(frame_name, frame_type, "frame")
        _frame_argument(root_name, root_type, "root")
        self.frame_name, self.frame_type = frame_name, frame_type
        self.root_name, self.root_type = root_name, root_type
        self.cost[:3] = as_cost(position_cost, 3, "position_cost")
        self.cost[3:] = as_cost(orientation_cost, 3, "orientation_cost")
        self.strict = strict
        self.target: NDArray[np.float64] | None = None
        if target is not None:
            self.set_target(target)

    def bind(self, robot: Robot) -> RelativeFrameTask:
        """Resolve both frames against ``robot``."""
        self.frame = _resolve(robot, self.frame_name, self.frame_type)
        self.root = _resolve(robot, self.root_name, self.root_type)
        super().bind(robot)
        return self

    def set_target(self, target: object, *, strict: bool | None = None) -> None:
        """Replace the target pose of the frame in the root (validated)."""
        self.target = as_target_pose(target, strict=self.strict if strict is None else strict)

    def set_target_from_configuration(self, configuration: Configuration) -> None:
        """The target is the frame's current pose in the root at ``configuration``.

        Args:
            configuration: A ``mink.Configuration`` of the bound robot's model.
        """
        state = self._state(configuration)
        self.set_target(inverse(_pose(state, self.root)) @ _pose(state, self.frame))

    def set_target_from_q(self, q: NDArray[np.float64]) -> None:
        """The target is the frame's pose in the root at the bound robot's ``q``."""
        robot = self._require_robot()
        self.set_target(inverse(robot.fk(q, self.root)) @ robot.fk(q, self.frame))

    @property
    def transform_target_to_root(self) -> SE3 | None:
        """The target as a ``mink.SE3`` (mink's name), or None before one is set."""
        from mink import SE3  # redik tasks already depend on mink; imported where used

        return None if self.target is None else SE3.from_matrix(self.target)

    def _relative(self, state: KinematicState) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(T_rf, T_t)``: the frame's pose in the root at ``state``, and the target."""
        if self.target is None:
            raise TargetNotSet(
                f"RelativeFrameTask on {self.frame_name!r} in {self.root_name!r} has no target: "
                "call set_target(...) first"
            )
        return inverse(_pose(state, self.root)) @ _pose(state, self.frame), self.target

    def residual_into(
        self, state: KinematicState, e: NDArray[np.float64], J: NDArray[np.float64]
    ) -> None:
        """Write ``e = log(T_t⁻¹ T_rf)`` and its Jacobian (module docstring)."""
        T_rf, target = self._relative(state)
        e[:] = se3_log(inverse(target) @ T_rf)
        J_frame = _body_jacobian(state, self.frame, state.pose(self.frame)[0])
        J_root = _body_jacobian(state, self.root, state.pose(self.root)[0])
        relative = J_frame - adjoint(inverse(T_rf)) @ J_root
        np.matmul(se3_left_jacobian_inverse(-e), relative, out=J)

    def pose_errors(self, state: KinematicState) -> tuple[float | None, float | None]:
        """``(‖p_rf − p_t‖, angle(R_tᵀ R_rf))`` at ``state``; None for a part of zero cost."""
        T_rf, target = self._relative(state)
        position = float(np.linalg.norm(T_rf[:3, 3] - target[:3, 3]))
        rotation = rotation_angle(T_rf[:3, :3], target[:3, :3])
        return (
            position if self.cost[:3].any() else None,
            rotation if self.cost[3:].any() else None,
        )
