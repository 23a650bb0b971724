r"""One attempt of ``"newton"``, ``"transpose"`` or ``"hybrid"`` on a pose, from one start.

The methods are the loops of :mod:`redik.solvers.iterative`, run on the pose residual
(:class:`~redik.solvers.iterative.PoseResidual`); what is here is only what makes them a pose
solve — the problem (target, tolerances, limits), the options of each method and the
record of an attempt that :func:`~redik.solvers.pose.solve.solve_pose` restarts and
:mod:`~redik.solvers.pose.result` summarises:

``"newton"``
    :func:`~redik.solvers.iterative.newton_raphson` on the body twist (``form="body"``,
    *IKinBody*) or the space twist (``form="space"``, *IKinSpace*), step ``λ`` (``step``),
    stopping on the pose errors (``stop="pose"``) or on the twist's halves (``"twist"``,
    the book's rule).
``"transpose"``
    :func:`~redik.solvers.iterative.jacobian_transpose` on the world error, ``step`` ``"armijo"``
    or a constant ``α``.
``"hybrid"``
    :func:`~redik.solvers.iterative.transpose_then_newton` on the world error, Newton below
    ``switch_error``.

Every attempt stops on the pose test ``‖p_d − p‖ ≤ pos_tol`` and ``angle ≤ rot_tol`` (or
the twist's halves for ``stop="twist"``), its budget, a stall of its Armijo search
(:data:`~redik.solvers.iterative.ARMIJO_ATTEMPT_TRIALS` trials: a restart follows), or a
divergence.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import Status
from redik.core.validate import positive
from redik.kinematics.robot import Frame, Robot
from redik.solvers.iterative import (
    ARMIJO_ATTEMPT_TRIALS,
    Iterates,
    PosePoint,
    PoseResidual,
    StoppingRules,
    jacobian_transpose,
    newton_raphson,
    step_size,
    transpose_then_newton,
)


@dataclass(frozen=True)
class PoseProblem:
    """A validated pose solve: the robot and frame, the target, tolerances and limits."""

    robot: Robot
    frame: Frame
    T_target: np.ndarray
    pos_tol: float
    rot_tol: float
    respect_limits: bool

    def within(self, position_error: float, rotation_error: float) -> bool:
        """Both errors within their tolerances."""
        return position_error <= self.pos_tol and rotation_error <= self.rot_tol

    def project(self, q: np.ndarray) -> np.ndarray:
        """``q`` clipped into the limits when they are respected (a new array)."""
        robot = self.robot
        return np.clip(q, robot.lower, robot.upper) if self.respect_limits else np.array(q)


@dataclass
class Attempt:
    """The outcome of one attempt from one start."""

    q: np.ndarray
    status: Status  # CONVERGED, STALLED, MAX_ITERATIONS or DIVERGED
    history: list[np.ndarray]
    errors: list[float]  # ‖e‖ of the method's own error, per iterate
    error_sq: float  # ‖e‖² of the world error at q, to pick the closest attempt
    J: np.ndarray  # world Jacobian at q
    e: np.ndarray  # world error at q

    @classmethod
    def of(cls, run: Iterates[PosePoint], residual: PoseResidual) -> Attempt:
        """The attempt a finished run made."""
        e, J = residual.world(run.point)
        return cls(run.q, run.final_status, run.history, run.errors, float(e @ e), J, e)


AttemptFrom = Callable[[np.ndarray], Attempt]
"""``attempt(q_start) -> Attempt``: one attempt of a method, its options bound."""


def attempt_of(
    method: str, options: dict[str, object], problem: PoseProblem, max_iterations: int
) -> AttemptFrom:
    """The attempt of ``method`` (``"newton"``, ``"transpose"`` or ``"hybrid"``) on ``problem``.

    Args:
        method: The method.
        options: Its options, defaults filled in (:data:`~redik.solvers.pose.options.OPTIONS`).
        problem: The solve.
        max_iterations: Iterations per attempt.

    Raises:
        InvalidInput: An option value the method does not take.
    """
    form, stop = "world", "pose"
    if method == "newton":
        form = _choice(options["form"], "form", ("body", "space"))
        stop = _choice(options["stop"], "stop", ("pose", "twist"), " (Modern Robotics' rule)")
    residual = PoseResidual(
        problem.robot, problem.frame, problem.T_target, form, stop, problem.respect_limits
    )
    rules = StoppingRules(
        tol=(problem.pos_tol, problem.rot_tol),
        max_iterations=max_iterations,
        armijo_trials=ARMIJO_ATTEMPT_TRIALS,
    )
    if method == "newton":
        step = step_size(options["step"], "step")
        return lambda q: Attempt.of(newton_raphson(residual, q, rules, step), residual)
    if method == "transpose":
        step = step_size(options["step"], "step")
        return lambda q: Attempt.of(jacobian_transpose(residual, q, rules, step), residual)
    switch_error = positive(options["switch_error"], "switch_error")
    return lambda q: Attempt.of(transpose_then_newton(residual, q, rules, switch_error), residual)


def _choice(value: object, name: str, choices: tuple[str, ...], note: str = "") -> str:
    if not isinstance(value, str) or value not in choices:
        raise InvalidInput(
            f"{name} must be {' or '.join(repr(c) for c in choices)}{note}, got {value!r}"
        )
    return value
