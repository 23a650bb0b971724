r"""Ascend Yoshikawa's manipulability :math:`w(q) = \sqrt{\det(J J^\top)}` of a frame.

:math:`J` is the frame's 6 × n Jacobian. :math:`w` is the same for the space, world and
body Jacobians (they differ by a matrix of determinant 1), so it is computed from the
space Jacobian, whose columns :math:`S_i` are the joints' current screw axes (Modern
Robotics §5.1.1). The gradient is analytic (Yoshikawa 1985; Park & Kim 1998):

.. math::

    \frac{\partial w}{\partial q_k}
    = w\, \mathrm{tr}\!\left((J J^\top)^{-1} \frac{\partial J}{\partial q_k} J^\top\right),
    \qquad
    \frac{\partial S_i}{\partial q_k} =
    \begin{cases} [S_k, S_i] = \mathrm{ad}_{S_k} S_i & k < i \\ 0 & k \ge i \end{cases}

(a joint moves only the axes after it on the chain). The task is the gradient-projection
step of Liégeois (1977) written as a least-squares objective,

.. math::

    \tfrac12 \| W (Δq - α ∇w) \|^2 \quad\Longrightarrow\quad H = W^2, \; c = -α W^2 ∇w,

so at a lower priority it yields :math:`Δq = α N N^\top ∇w`, the gradient projected on
what the higher levels leave free. Where :math:`w < 10^{-12}` (a singularity, where the
square root is not differentiable) the gradient is taken as zero. Needs ≥ 6 chain joints.
"""

from __future__ import annotations

import numpy as np

from ..exceptions import InvalidInput
from ..robot import Frame, Robot
from .kinematics import KinematicState
from .task import Task, as_weight

_SINGULAR = 1e-12


class ManipulabilityTask(Task):
    """Move along the gradient of ``w(q) = √det(J Jᵀ)`` of ``frame``.

    Args:
        frame: Site or body name; None is the robot's end-effector.
        weight: Scalar or per-joint weight ``w`` (the objective scales with ``w²``).
        gain: Gradient step ``α`` (radians per unit of manipulability gradient), ≥ 0.
        priority: Priority level, 0 highest.
    """

    def __init__(self, frame: str | None = None, weight=1.0, gain: float = 1.0, priority=1):
        super().__init__(priority)
        self.frame_name = frame
        self.frame: Frame | None = None
        self._weight_spec = weight
        self.weight = np.empty(0)
        if isinstance(gain, bool) or not isinstance(gain, int | float | np.integer | np.floating):
            raise InvalidInput(f"gain must be a finite number >= 0, got {gain!r}")
        self.gain = float(gain)
        if not np.isfinite(self.gain) or self.gain < 0.0:
            raise InvalidInput(f"gain must be finite and >= 0, got {gain}")

    def bind(self, robot: Robot) -> ManipulabilityTask:
        if not robot.is_chain:
            raise InvalidInput(
                f"ManipulabilityTask's gradient is that of a serial chain; {robot!r} is a "
                "whole-model robot: bind it to robot.chain(frame)"
            )
        if robot.dof < 6:
            raise InvalidInput(
                f"ManipulabilityTask needs at least 6 chain joints for det(J Jᵀ) > 0, "
                f"{robot!r} has {robot.dof}"
            )
        self.frame = robot.frame(self.frame_name)
        self.weight = as_weight(self._weight_spec, robot.dof, "ManipulabilityTask weight")
        return super().bind(robot)

    def _space_jacobian(self, state: KinematicState) -> np.ndarray:
        J = state.jacobian(self.frame)[:, state.chain_columns]
        _, p = state.pose(self.frame)
        # v_s = ṗ − ω × p = J_v + [p] J_ω (redik.conventions).
        J[:3] += np.cross(p, J[3:], axis=0)
        return J

    def value_and_gradient(self, state: KinematicState) -> tuple[float, np.ndarray]:
        """``(w, ∇w)`` at ``state``; ``∇w`` over the chain joints (``robot.dof``,)."""
        S = self._space_jacobian(state)
        n = S.shape[1]
        JJt = S @ S.T
        det = float(np.linalg.det(JJt))
        w = float(np.sqrt(max(det, 0.0)))
        gradient = np.zeros(n)
        if w < _SINGULAR:
            return w, gradient
        M = np.linalg.solve(JJt, S).T  # row i = ((J Jᵀ)⁻¹ S_i)ᵀ, since J Jᵀ is symmetric
        for k in range(n - 1):
            omega, v = S[3:, k], S[:3, k]
            later = S[:, k + 1 :]
            # ad_{S_k} S_i = (ω_k × v_i − ω_i × v_k, ω_k × ω_i), for every later column i.
            d_v = np.cross(omega, later[:3], axis=0) - np.cross(later[3:], v, axis=0)
            d_omega = np.cross(omega, later[3:], axis=0)
            gradient[k] = np.sum(M[k + 1 :, :3] * d_v.T) + np.sum(M[k + 1 :, 3:] * d_omega.T)
        gradient *= w
        return w, gradient

    def add_objective(self, state: KinematicState, H: np.ndarray, c: np.ndarray) -> None:
        _, gradient = self.value_and_gradient(state)
        columns = state.chain_columns
        weight2 = self.weight**2
        H[columns, columns] += weight2
        c[columns] -= self.gain * weight2 * gradient
