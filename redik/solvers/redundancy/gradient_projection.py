r"""Gradient projection: reach a pose and climb a secondary criterion in its self-motion.

The pose by Gauss–Newton on the body error twist (the :class:`~.corrector.Corrector`'s
IKinBody step), the criterion by its ascent direction projected onto ``ker J_b``
(:mod:`.nullspace`; Siciliano et al. §3.5.1). Twists and Jacobians follow
:mod:`redik.core.conventions`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from redik.core.result import IKResult, Status
from redik.core.rotation_policy import as_pose
from redik.solvers.redundancy.corrector import (
    SAMPLE_POSITION_TOLERANCE,
    SAMPLE_ROTATION_TOLERANCE,
    Corrector,
)
from redik.solvers.redundancy.nullspace import pseudo_inverse

if TYPE_CHECKING:
    from redik.kinematics.robot import Frame, Robot
    from redik.solvers.redundancy.scoring import Criterion


def gradient_projection_ik(
    robot: Robot,
    T_target: np.ndarray,
    q0: np.ndarray,
    criterion: Criterion,
    frame: str | Frame | None = None,
    *,
    gain: float = 0.5,
    max_step: float = 0.2,
    position_tolerance: float = SAMPLE_POSITION_TOLERANCE,
    rotation_tolerance: float = SAMPLE_ROTATION_TOLERANCE,
    step_tolerance: float = 1e-7,
    max_iterations: int = 2000,
) -> IKResult:
    r"""Reach ``T_target`` and climb ``criterion`` inside the self-motion: the gradient
    projection method (Siciliano et al. §3.5.1 with the pose error of §3.7.1).

    Each iteration, with the body error twist ``ξ_b = log(T(q)⁻¹ T_d)`` and body Jacobian
    ``J_b`` (:mod:`redik.core.conventions`):

    .. math:: Δq = J_b^+ ξ_b + (I - J_b^+ J_b)\, k\, \dot q_0(q),

    ``q̇₀`` the criterion's ascent direction, the step clipped to ``‖Δq‖ ≤ max_step`` and
    ``q`` to the joint limits. It stops when the pose is within tolerance and the projected
    criterion step is below ``step_tolerance``: a local optimum of the criterion on the
    self-motion manifold, reached from ``q0`` — compare
    :meth:`redik.solvers.redundancy.SelfMotion.best`, the best sample over the whole manifold.
    """
    T_target = as_pose(T_target, "T_target")
    q = robot.check_q(q0, "q0").copy()
    pose = Corrector(robot, T_target, robot.frame(frame), position_tolerance, rotation_tolerance)
    history = [q.copy()]
    errors: list[float] = []
    status = Status.MAX_ITERATIONS
    for _ in range(max_iterations):
        xi, position_error, rotation_error = pose.body_error(q)
        errors.append(float(np.linalg.norm(xi)))
        J_pinv = pseudo_inverse(pose.J_body)
        dq0 = gain * criterion.ascent(robot, q, pose.J)
        secondary = dq0 - J_pinv @ (pose.J_body @ dq0)
        step = J_pinv @ xi + secondary
        if (
            position_error <= position_tolerance
            and rotation_error <= rotation_tolerance
            and np.linalg.norm(secondary) <= step_tolerance
        ):
            status = Status.CONVERGED
            break
        norm = float(np.linalg.norm(step))
        if norm > max_step:
            step *= max_step / norm
        q = robot.clip(q + step)
        history.append(q.copy())
    message = ""
    if status != Status.CONVERGED:
        # The budget ran out mid-climb: drop the criterion and settle onto the pose.
        for _ in range(10):
            xi, _, _ = pose.body_error(q)
            q = robot.clip(q + pseudo_inverse(pose.J_body) @ xi)
        history.append(q.copy())
        message = "the criterion was still improving when the iteration budget ran out"
    xi, position_error, rotation_error = pose.body_error(q)
    if position_error <= position_tolerance and rotation_error <= rotation_tolerance:
        status = Status.CONVERGED
    errors.append(float(np.linalg.norm(xi)))
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
