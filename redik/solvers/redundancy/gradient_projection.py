r"""Gradient projection: reach a pose and climb a secondary criterion in its self-motion.

The pose by the Newton step on the body error twist, the criterion by its ascent direction
projected onto ``ker J_b`` — the step functions of :mod:`redik.solvers.iterative.steps`
(Siciliano et al. §3.5.1). Twists and Jacobians follow :mod:`redik.core.conventions`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from redik.core.result import IKResult, Status
from redik.core.rotation_policy import as_pose
from redik.solvers.iterative import (
    PoseResidual,
    StoppingRules,
    newton_raphson,
    newton_step,
    nullspace_projection,
)

if TYPE_CHECKING:
    from redik.kinematics.robot import Frame, Robot
    from redik.solvers.redundancy.scoring import Criterion

SETTLE_ITERATIONS = 10
"""Newton iterations that settle onto the pose when the budget ran out mid-climb."""


def gradient_projection_ik(
    robot: Robot,
    T_target: np.ndarray,
    q0: np.ndarray,
    criterion: Criterion,
    frame: str | Frame | None = None,
    *,
    gain: float = 0.5,
    max_step: float = 0.2,
    position_tolerance: float = 1e-9,
    rotation_tolerance: float = 1e-8,
    step_tolerance: float = 1e-7,
    max_iterations: int = 2000,
) -> IKResult:
    r"""Reach ``T_target`` and climb ``criterion`` inside the self-motion.

    The gradient projection method (Siciliano et al. §3.5.1 with the pose error of §3.7.1).
    Each iteration, with the body error twist ``ξ_b = log(T(q)⁻¹ T_d)`` and body Jacobian
    ``J_b`` (:mod:`redik.core.conventions`):

    .. math:: Δq = J_b^+ ξ_b + (I - J_b^+ J_b)\, k\, \dot q_0(q),

    ``q̇₀`` the criterion's ascent direction, the step clipped to ``‖Δq‖ ≤ max_step`` and
    ``q`` to the joint limits. It stops when the pose is within tolerance and the projected
    criterion step is below ``step_tolerance``: a local optimum of the criterion on the
    self-motion manifold, reached from ``q0`` — compare
    :meth:`redik.solvers.redundancy.SelfMotion.best`, the best sample over the whole manifold.
    When the budget runs out first, Newton's method settles ``q`` onto the pose
    (at most :data:`SETTLE_ITERATIONS` iterations).

    Args:
        robot: The robot.
        T_target: The pose to hold.
        q0: The start.
        criterion: The secondary criterion to climb.
        frame: The frame placed at the pose (default the end-effector).
        gain: ``k``.
        max_step: The largest ``‖Δq‖`` of one iteration.
        position_tolerance: The largest ``‖p_d − p‖`` (m) of the result.
        rotation_tolerance: The largest rotation angle (rad) of the result.
        step_tolerance: The projected criterion step below which the climb has ended.
        max_iterations: The iteration budget of the climb.

    Returns:
        An :class:`~redik.core.result.IKResult` (method ``"gradient_projection[name]"``).
    """
    T_target = as_pose(T_target, "T_target")
    q = robot.check_q(q0, "q0").copy()
    pose = PoseResidual(robot, robot.frame(frame), T_target, form="body")
    tolerances = (position_tolerance, rotation_tolerance)
    history, errors = [q.copy()], []
    status = Status.MAX_ITERATIONS
    for _ in range(max_iterations):
        point = pose.evaluate(q)
        errors.append(point.norm)
        J_b = pose.jacobian(point)
        secondary = nullspace_projection(J_b, gain * criterion.ascent(robot, q, point.J_world))
        within = all(np.less_equal(pose.errors(point), tolerances))
        if within and np.linalg.norm(secondary) <= step_tolerance:
            status = Status.CONVERGED
            break
        step = newton_step(J_b, point.e) + secondary
        norm = float(np.linalg.norm(step))
        if norm > max_step:
            step *= max_step / norm
        q = robot.clip(q + step)
        history.append(q.copy())
    message = ""
    if status != Status.CONVERGED:
        # The budget ran out mid-climb: drop the criterion and settle onto the pose.
        settle = PoseResidual(robot, pose.frame, T_target, form="body", respect_limits=True)
        rules = StoppingRules(tol=tolerances, max_iterations=SETTLE_ITERATIONS)
        q = newton_raphson(settle, q, rules).q
        history.append(q.copy())
        message = "the criterion was still improving when the iteration budget ran out"
    point = pose.evaluate(q)
    position_error, rotation_error = pose.errors(point)
    if position_error <= position_tolerance and rotation_error <= rotation_tolerance:
        status = Status.CONVERGED
    errors.append(point.norm)
    return IKResult(
        q=q,
        success=status == Status.CONVERGED,
        status=status,
        iterations=len(history) - 1,
        error=errors[-1],
        position_error=position_error,
        rotation_error=rotation_error,
        history=np.array(history),
        error_history=np.array(errors[: len(history)]),
        method=f"gradient_projection[{criterion.name}]",
        message=message,
    )
