r"""Inverse velocity kinematics with null-space projection, and the gradients fed to it.

A redundant arm (``n`` joints, a task of dimension ``m < n``) reaches a task velocity ``ẋ``
with infinitely many joint velocities. The classic resolution (Liégeois 1977; Siciliano,
Sciavicco, Villani & Oriolo, *Robotics: Modelling, Planning and Control*, §3.5.1, eq. 3.54)
takes the minimum-norm solution and adds any velocity that leaves the task unchanged:

.. math::

    \dot q = J^+ \dot x + (I - J^+ J)\, \dot q_0 .

``J⁺`` is the Moore–Penrose pseudo-inverse (or a damped one, ``Jᵀ(JJᵀ + λ²I)⁻¹``, near
singularities), ``P = I − J⁺J`` the orthogonal projector onto ``ker J``, and ``q̇₀`` usually
the gradient ``k ∇w(q)`` of a secondary criterion ``w`` to increase (eq. 3.55): distance
from the joint limits (eq. 3.58), manipulability ``√det(JJᵀ)`` (eq. 3.56), closeness to a
nominal posture. The functions here compute the projection; the criteria and their
gradients live in :mod:`redik.criteria` (re-exported here and in :mod:`redik.solvers.redundancy`);
:func:`gradient_projection_ik` iterates them into a solver that reaches a pose while
climbing a criterion.

Twists and Jacobians follow :mod:`redik.core.conventions`: ``(v, ω)`` order; the manipulability
gradient takes the ``"world"`` Jacobian (origin velocity and angular velocity in world axes),
for which ``det(JJᵀ)`` equals that of the body Jacobian.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import IKResult
from redik.lie import (
    as_pose,
    as_vector,
    inverse,
    pose_errors,
    real_array,
    se3_log,
    world_jacobian_to,
)

if TYPE_CHECKING:
    from redik.kinematics.robot import Frame, Robot
    from redik.solvers.redundancy.criteria import Criterion

_MAX_ENTRY = 1e100
"""Largest entry of ``J``, ``ẋ`` or ``q̇₀`` (and damping) :func:`nullspace_velocity` takes:
``J Jᵀ + λ²I`` and ``J⁺ J q̇₀`` stay finite."""

RANK_TOLERANCE = 1e-10
"""Singular values below ``RANK_TOLERANCE · σ_max`` count as zero in :func:`pseudo_inverse`."""


# --------------------------------------------------------------------------------------
# Pseudo-inverse, projector, basis


def pseudo_inverse(J: np.ndarray, damping: float = 0.0) -> np.ndarray:
    r"""``J⁺`` (n × m): Moore–Penrose by SVD, or ``Jᵀ(JJᵀ + λ²I)⁻¹`` for ``damping = λ > 0``.

    The undamped inverse drops singular values below ``RANK_TOLERANCE · σ_max``; the damped
    one (Nakamura & Hanafusa 1986; Wampler 1986) trades exactness for bounded ``‖q̇‖`` near
    singularities.
    """
    J = np.asarray(J, dtype=float)
    if damping > 0.0:
        m = J.shape[0]
        return J.T @ np.linalg.solve(J @ J.T + damping**2 * np.eye(m), np.eye(m))
    return np.linalg.pinv(J, rcond=RANK_TOLERANCE)


def nullspace_projector(J: np.ndarray, J_pinv: np.ndarray | None = None) -> np.ndarray:
    """``P = I − J⁺J`` (n × n): the orthogonal projector onto ``ker J`` (``JP = 0``, ``P² = P``)."""
    J = np.asarray(J, dtype=float)
    if J_pinv is None:
        J_pinv = pseudo_inverse(J)
    return np.eye(J.shape[1]) - J_pinv @ J


def nullspace_basis(J: np.ndarray, dimension: int | None = None) -> np.ndarray:
    """An orthonormal basis of ``ker J`` as the columns of an n × k matrix.

    ``k`` is ``n − rank J`` by default, or ``dimension`` when given (the right-singular vectors
    of the ``dimension`` smallest singular values: the directions that move the task least,
    which is ``ker J`` itself at full rank).
    """
    J = np.asarray(J, dtype=float)
    _, s, Vt = np.linalg.svd(J, full_matrices=True)
    if dimension is None:
        rank = int(np.sum(s > RANK_TOLERANCE * (s[0] if s.size else 0.0)))
        dimension = J.shape[1] - rank
    return Vt[J.shape[1] - dimension :].T.copy()


def nullspace_velocity(
    J: np.ndarray,
    twist: np.ndarray,
    dq0: np.ndarray | None = None,
    damping: float = 0.0,
) -> np.ndarray:
    r"""``q̇ = J⁺ẋ + (I − J⁺J) q̇₀`` (Siciliano et al. eq. 3.54).

    Args:
        J: The m × n task Jacobian.
        twist: The task velocity ``ẋ`` (m), in the same reference as ``J``.
        dq0: The secondary joint velocity ``q̇₀`` (n), e.g. ``k ∇w``; None for zero.
        damping: ``λ`` of the damped pseudo-inverse, 0 for Moore–Penrose.

    Returns:
        ``q̇`` (n). With ``damping = 0`` and ``J`` of full row rank, ``J q̇ = ẋ`` exactly and the
        second term changes nothing in the task.
    """
    J = real_array(J, "J")
    if J.ndim != 2 or not np.isfinite(J).all():
        raise InvalidInput(f"J must be a finite 2-D (m × n) matrix, got {J!r}")
    m, n = J.shape
    twist = as_vector(twist, m, "twist")
    if not (
        isinstance(damping, int | float | np.floating | np.integer) and 0.0 <= damping <= _MAX_ENTRY
    ):
        raise InvalidInput(f"damping must be a number in [0, {_MAX_ENTRY:g}], got {damping!r}")
    if max(np.abs(J).max(initial=0.0), np.abs(twist).max(initial=0.0)) > _MAX_ENTRY:
        raise InvalidInput(f"J and twist must be within ±{_MAX_ENTRY:g} (their products overflow)")
    J_pinv = pseudo_inverse(J, damping)
    dq = J_pinv @ twist
    if dq0 is not None:
        dq0 = as_vector(dq0, n, "dq0")
        if np.abs(dq0).max(initial=0.0) > _MAX_ENTRY:
            raise InvalidInput(f"dq0 must be within ±{_MAX_ENTRY:g} (its products overflow)")
        dq += dq0 - J_pinv @ (J @ dq0)
    return dq


# --------------------------------------------------------------------------------------
# A solver: pose by Gauss–Newton, criterion by gradient projection


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
    resolved = robot.frame(frame)
    T = np.eye(4)
    J = np.empty((6, robot.dof))
    J_body = np.empty((6, robot.dof))
    history = [q.copy()]
    errors: list[float] = []
    status = "max_iterations"
    for _ in range(max_iterations):
        robot.kinematics(q, resolved, T, J)
        R = T[:3, :3]
        world_jacobian_to("body", J, R, T[:3, 3], out=J_body)
        xi = se3_log(inverse(T) @ T_target)
        errors.append(float(np.linalg.norm(xi)))
        J_pinv = pseudo_inverse(J_body)
        dq0 = gain * criterion.ascent(robot, q, J)
        secondary = dq0 - J_pinv @ (J_body @ dq0)
        step = J_pinv @ xi + secondary
        position_error, rotation_error = pose_errors(T, T_target)
        if (
            position_error <= position_tolerance
            and rotation_error <= rotation_tolerance
            and np.linalg.norm(secondary) <= step_tolerance
        ):
            status = "converged"
            break
        norm = float(np.linalg.norm(step))
        if norm > max_step:
            step *= max_step / norm
        q = robot.clip(q + step)
        history.append(q.copy())
    message = ""
    if status != "converged":
        # The budget ran out mid-climb: drop the criterion and settle onto the pose.
        for _ in range(10):
            robot.kinematics(q, resolved, T, J)
            J_body[:3] = T[:3, :3].T @ J[:3]
            J_body[3:] = T[:3, :3].T @ J[3:]
            q = robot.clip(q + pseudo_inverse(J_body) @ se3_log(inverse(T) @ T_target))
        history.append(q.copy())
        message = "the criterion was still improving when the iteration budget ran out"
    robot.kinematics(q, resolved, T)
    position_error, rotation_error = pose_errors(T, T_target)
    if position_error <= position_tolerance and rotation_error <= rotation_tolerance:
        status = "converged"
    errors.append(float(np.linalg.norm(se3_log(inverse(T) @ T_target))))
    return IKResult(
        q=q,
        success=status == "converged",
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
