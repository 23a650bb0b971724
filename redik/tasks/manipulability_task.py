r"""Ascend Yoshikawa's manipulability :math:`w(q) = \sqrt{\det(J J^\top)}` of a frame.

:math:`J` is the frame's 6 × n ``"world"`` Jacobian (:mod:`redik.core.conventions`); value and
analytic gradient :math:`∇w` are :func:`redik.criteria.manipulability` and
:func:`redik.criteria.manipulability_gradient` (Yoshikawa 1985; Haviland & Corke 2023). The
task is the gradient-projection step of Liégeois (1977) written as a least-squares
objective,

.. math::

    \tfrac12 \| W (Δq - α ∇w) \|^2 \quad\Longrightarrow\quad H = W^2, \; c = -α W^2 ∇w,

so at a lower priority it yields :math:`Δq = α N N^\top ∇w`, the gradient projected on
what the higher levels leave free. Where :math:`w < 10^{-12}` (a singularity, where the
square root is not differentiable) the gradient is taken as zero. Needs ≥ 6 chain joints.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik import criteria
from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Frame, Robot
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import Task, as_cost


class ManipulabilityTask(Task):
    """Move along the gradient of ``w(q) = √det(J Jᵀ)`` of ``frame``.

    Args:
        frame: Site or body name; None is the robot's end-effector.
        cost: Scalar or per-joint cost ``w`` (the objective scales with ``w²``; default 1).
        gain: Gradient step ``α`` (radians per unit of manipulability gradient), ≥ 0.
        priority: Priority level, 0 highest.

    Attributes:
        frame: The resolved frame, once bound.
    """

    frame: Frame

    def __init__(
        self,
        frame: str | None = None,
        cost: ArrayLike = 1.0,
        gain: float = 1.0,
        priority: int = 1,
    ):
        super().__init__(priority)
        self.frame_name = frame
        self._cost_spec = cost
        self.cost = np.empty(0)
        if isinstance(gain, bool) or not isinstance(gain, int | float | np.integer | np.floating):
            raise InvalidInput(f"gain must be a finite number >= 0, got {gain!r}")
        self.gain = float(gain)
        if not np.isfinite(self.gain) or self.gain < 0.0:
            raise InvalidInput(f"gain must be finite and >= 0, got {gain}")

    def bind(self, robot: Robot) -> ManipulabilityTask:
        """Prepare for ``robot`` (the base class's contract); returns self."""
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
        self.cost = as_cost(self._cost_spec, robot.dof, "ManipulabilityTask cost")
        super().bind(robot)
        return self

    def value_and_gradient(self, state: KinematicState) -> tuple[float, NDArray[np.float64]]:
        """``(w, ∇w)`` at ``state``; ``∇w`` over the chain joints (``robot.dof``,)."""
        J = state.jacobian(self.frame)[:, state.chain_columns]
        return float(criteria.manipulability(J)), criteria.manipulability_gradient(J)

    def objective_value(self, state: KinematicState) -> float:
        """``−mean(w²) w(q)``: the manipulability the task ascends, as a value to descend."""
        return -float(np.mean(self.cost**2)) * self.value_and_gradient(state)[0]

    def add_objective(
        self, state: KinematicState, H: NDArray[np.float64], c: NDArray[np.float64]
    ) -> None:
        """Add ``H = W²`` and ``c = −α W² ∇w`` at ``state`` (module docstring)."""
        _, gradient = self.value_and_gradient(state)
        columns = state.chain_columns
        cost2 = self.cost**2
        H[columns, columns] += cost2
        c[columns] -= self.gain * cost2 * gradient
