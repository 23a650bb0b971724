"""One validated pose problem, and what one attempt of an iterative method returns.

The Python drivers (:mod:`~redik.solvers.pose.newton`, :mod:`~redik.solvers.pose.gradient`)
are :data:`Iteration` s: from a start ``q`` they iterate on a :class:`PoseProblem` and return
an :class:`Attempt`; :func:`~redik.solvers.pose.solve.solve_pose` restarts them and
:mod:`~redik.solvers.pose.result` makes the result of the attempts.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from redik.core.result import Status
from redik.kinematics.robot import Frame, Robot
from redik.lie import so3_log


class PoseProblem:
    """A validated solve: target, tolerances and limits.

    Its error is the world-frame ``e = (p_d − p, log(R_d Rᵀ))`` (``"world"`` in
    :mod:`redik.core.conventions`), whose halves are the reported position and rotation
    errors.
    """

    def __init__(
        self,
        robot: Robot,
        frame: Frame,
        T_target: np.ndarray,
        pos_tol: float,
        rot_tol: float,
        respect_limits: bool,
    ) -> None:
        self.robot = robot
        self.frame = frame
        self.T_target = T_target
        self.p_d = T_target[:3, 3].copy()
        self.R_d = T_target[:3, :3].copy()
        self.pos_tol = pos_tol
        self.rot_tol = rot_tol
        self.respect_limits = respect_limits
        self.lower = robot.lower
        self.upper = robot.upper
        self.n = robot.dof

    def project(self, q: np.ndarray) -> np.ndarray:
        """``q`` clipped into the limits when they are respected (a new array)."""
        return (
            np.clip(q, self.lower, self.upper) if self.respect_limits else np.array(q, dtype=float)
        )

    def world_error(self, T: np.ndarray, e: np.ndarray) -> tuple[float, float]:
        """Fill ``e = (p_d − p, log(R_d Rᵀ))``; return the position and rotation errors."""
        return world_error(self.T_target, T, e)

    def within(self, position_error: float, rotation_error: float) -> bool:
        return position_error <= self.pos_tol and rotation_error <= self.rot_tol


@dataclass
class Attempt:
    """The outcome of one attempt from one start."""

    q: np.ndarray
    status: Status  # CONVERGED, STALLED, MAX_ITERATIONS or DIVERGED
    history: list[np.ndarray]
    errors: list[float]
    error_sq: float  # ‖e‖² of the world error at q, to pick the closest attempt
    J: np.ndarray  # world Jacobian at q
    e: np.ndarray  # world error at q


Iteration = Callable[[PoseProblem, np.ndarray, int], Attempt]
"""``iterate(problem, q_start, max_iterations) -> Attempt``: one attempt of a Python driver."""


def world_error(T_target: np.ndarray, T: np.ndarray, e: np.ndarray) -> tuple[float, float]:
    """Fill ``e = (p_d − p, log(R_d Rᵀ))``; return the position and rotation errors."""
    np.subtract(T_target[:3, 3], T[:3, 3], out=e[:3])
    e[3:] = so3_log(T_target[:3, :3] @ T[:3, :3].T)
    return math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]), math.sqrt(
        e[3] * e[3] + e[4] * e[4] + e[5] * e[5]
    )
