r"""The pose of a robot's frame as a residual of the iterative methods: IKinBody beside Newton.

:class:`PoseResidual` is what :func:`redik.solve_pose` (``"newton"``, ``"transpose"``,
``"hybrid"``) and the redundancy tools hand to the loops of :mod:`redik.solvers.iterative`:
the error of the frame's pose ``T(q)`` from the target ``T_d`` and its Jacobian, in one of
three forms (twist order ``(v, ω)`` and the frame of each Jacobian as in
:mod:`redik.core.conventions`):

``"body"``
    ``e = V_b = log(T⁻¹ T_d)``, ``J = J_b``: Modern Robotics' *IKinBody* (Lynch & Park
    §6.2.2).
``"space"``
    ``e = V_s = Ad_T V_b``, ``J = J_s``: *IKinSpace*.
``"world"``
    ``e = (p_d − p, log(R_d Rᵀ))`` with the ``"world"`` Jacobian (MuJoCo's): the two halves
    are exactly the position error and the rotation angle.

The pair ``(e_p, e_R)`` that a pair tolerance tests (``stop``): ``"pose"`` gives
``(‖p_d − p‖, angle(Rᵀ R_d))``, the success test of every pose method, in every form;
``"twist"`` gives ``(‖v‖, ‖ω‖)`` of ``e`` — the book's ``ε_v``, ``ε_ω`` for the body and space
forms. The two differ only in the linear part: ``Rᵀ(p_d − p) = (G(θ)/θ) v_b`` (MR §3.3.3),
whose singular values are 1 and ``2 sin(θ/2)/θ ≤ 1``, so ``‖p_d − p‖ ≤ ‖v_b‖``.
"""

from __future__ import annotations

import math

import numpy as np

from redik.kinematics.robot import Frame, Robot
from redik.lie import adjoint, body_error_twist, so3_log, world_jacobian_to

FORMS = ("world", "body", "space")
"""The forms of the pose error."""

STOPS = ("pose", "twist")
"""The parts a pair tolerance tests: the pose errors, or the halves of the twist."""


class PosePoint:
    """A configuration, the frame's pose there, the error and the world Jacobian."""

    __slots__ = ("J", "J_world", "T", "e", "halves", "norm", "q")

    def __init__(self, q: np.ndarray, T: np.ndarray, J_world: np.ndarray, e: np.ndarray):
        self.q, self.T, self.J_world, self.e = q, T, J_world, e
        v0, v1, v2, w0, w1, w2 = e.tolist()
        linear, angular = v0 * v0 + v1 * v1 + v2 * v2, w0 * w0 + w1 * w1 + w2 * w2
        self.norm = math.sqrt(linear + angular)
        self.halves = (math.sqrt(linear), math.sqrt(angular))  # ‖e[:3]‖, ‖e[3:]‖
        self.J: np.ndarray | None = None  # in the residual's form, on first use


class PoseResidual:
    """The error of ``frame``'s pose from ``T_target`` (module docstring).

    Args:
        robot: The robot (a chain); ``q`` is its joint vector.
        frame: The resolved frame.
        T_target: The validated target pose (4 × 4).
        form: ``"world"``, ``"body"`` or ``"space"``.
        stop: ``"pose"`` or ``"twist"``: the parts a pair tolerance tests.
        respect_limits: Project every iterate into the joint limits (``clip``).
        free: Only these joints move (a boolean mask): the residual's ``q`` is then
            ``q_full[free]``, the others held at their values in ``q_full``.
        q_full: The robot's ``q`` the held joints take their values from.
    """

    def __init__(
        self,
        robot: Robot,
        frame: Frame,
        T_target: np.ndarray,
        form: str = "world",
        stop: str = "pose",
        respect_limits: bool = False,
        free: np.ndarray | None = None,
        q_full: np.ndarray | None = None,
    ) -> None:
        self.robot, self.frame, self.T_target = robot, frame, T_target
        self.form, self.stop = form, stop
        self.lower, self.upper = robot.lower, robot.upper
        self.respect_limits = respect_limits
        self.free = free
        self.q_full = None if free is None else np.array(q_full, dtype=float)
        if free is not None:
            self.lower, self.upper = self.lower[free], self.upper[free]

    def start(self, q: np.ndarray) -> PosePoint:
        """The point at ``q`` (a finite joint vector: the pose is always defined)."""
        return self.evaluate(np.array(q, dtype=float))

    def evaluate(self, q: np.ndarray) -> PosePoint:
        """One FK and world Jacobian at ``q`` (MuJoCo's), and the error in this form."""
        robot = self.robot
        T, J = np.eye(4), np.empty((6, robot.dof))
        robot.state.kinematics(self._full(q), self.frame, T, J)
        if self.form == "world":
            e = np.empty(6)
            np.subtract(self.T_target[:3, 3], T[:3, 3], out=e[:3])
            e[3:] = so3_log(self.T_target[:3, :3] @ T[:3, :3].T)
        else:
            e = body_error_twist(T, self.T_target)
            if self.form == "space":
                e = adjoint(T) @ e
        return PosePoint(q, T, J, e)

    def jacobian(self, point: PosePoint) -> np.ndarray:
        """``J`` of this form at the point: the world Jacobian, or ``J_b``, or ``J_s``."""
        if point.J is None:
            J = point.J_world if self.free is None else point.J_world[:, self.free]
            if self.form != "world":
                J = world_jacobian_to(self.form, J, point.T[:3, :3], point.T[:3, 3])
            point.J = J
        return point.J

    def errors(self, point: PosePoint) -> tuple[float, float]:
        """``(‖p_d − p‖, angle)`` for ``stop="pose"``, ``(‖v‖, ‖ω‖)`` of ``e`` for ``"twist"``.

        The rotation angle is ``‖ω‖`` in every form (``ω_b``, ``ω_s = R ω_b`` and
        ``log(R_d Rᵀ)`` all have the norm ``angle(Rᵀ R_d)``), as is ``‖p_d − p‖`` of the world
        form's ``e[:3]``.
        """
        if self.stop == "twist" or self.form == "world":
            return point.halves
        return math.dist(point.T[:3, 3].tolist(), self.T_target[:3, 3].tolist()), point.halves[1]

    def project(self, q: np.ndarray) -> np.ndarray:
        """``q`` clipped into the joint limits when they are respected, else ``q``."""
        return np.clip(q, self.lower, self.upper) if self.respect_limits else q

    def task_value(self, point: PosePoint) -> np.ndarray:
        """The frame's pose ``T(q)``."""
        return point.T

    def world(self, point: PosePoint) -> tuple[np.ndarray, np.ndarray]:
        """The world error ``(p_d − p, log(R_d Rᵀ))`` and the world Jacobian at the point."""
        if self.form == "world":
            return point.e, point.J_world
        e = np.empty(6)
        world_error(self.T_target, point.T, e)
        return e, point.J_world

    def full(self, q: np.ndarray) -> np.ndarray:
        """The robot's ``q`` from this residual's (the held joints at their values)."""
        return self._full(q).copy() if self.free is not None else q

    def _full(self, q: np.ndarray) -> np.ndarray:
        if self.free is None or self.q_full is None:
            return q
        q_full = self.q_full
        q_full[self.free] = q
        return q_full


def world_error(T_target: np.ndarray, T: np.ndarray, e: np.ndarray) -> tuple[float, float]:
    """Fill ``e = (p_d − p, log(R_d Rᵀ))``.

    Returns:
        ``(‖p_d − p‖, angle(Rᵀ R_d))``, the norms of the two halves.
    """
    np.subtract(T_target[:3, 3], T[:3, 3], out=e[:3])
    e[3:] = so3_log(T_target[:3, :3] @ T[:3, :3].T)
    return math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]), math.sqrt(
        e[3] * e[3] + e[4] * e[4] + e[5] * e[5]
    )
