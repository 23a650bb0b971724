r"""The :class:`~redik.core.result.IKResult` of a pose solve.

Success by the pose of the returned ``q``, the status, and the unreachable diagnosis.

Success is decided from the pose of the returned ``q``: ``‖p_d − p‖ ≤ pos_tol``,
``angle(Rᵀ R_d) ≤ rot_tol`` and, with ``respect_limits``, ``lower ≤ q ≤ upper``
(:func:`verdict`). A revolute joint outside its range is first shifted by the multiple of 2π
that brings it inside, if one does (:func:`shift_into_limits`; the pose is unchanged).
``result.error`` is always the body error ``‖log(T⁻¹ T_d)‖`` (:func:`body_twist_norm`).

The compiled ``"dls"`` driver (:mod:`~redik.solvers.pose.dls_solver`) computes the summary of its
attempts in the kernel; the Python drivers' attempts are summarised by :class:`Outcome`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from redik.core.result import IKResult, Status
from redik.kinematics.robot import Robot
from redik.lie import apply_inverse_v, wrap_angle, wrap_into_range
from redik.solvers.iterative import world_error
from redik.solvers.pose.attempt import Attempt, PoseProblem


def stationarity(attempt: Attempt, lower: np.ndarray, upper: np.ndarray) -> float:
    """``‖Jᵀe‖`` without the components that push against an active joint limit."""
    g = attempt.J.T @ attempt.e
    g[(attempt.q <= lower) & (g < 0.0)] = 0.0
    g[(attempt.q >= upper) & (g > 0.0)] = 0.0
    return float(np.linalg.norm(g))


@dataclass
class Outcome:
    """What :func:`finish` needs from all the attempts of a solve."""

    q: np.ndarray  # of the returned attempt: the converged one, else the closest
    history: np.ndarray  # the returned attempt's iterates
    errors: np.ndarray  # and its ‖e‖
    iterations: int  # over every attempt
    attempts: int
    same_stationary_point: bool
    all_diverged: bool
    e: np.ndarray  # world error at q (by FK of q)
    position_error: float  # at q
    rotation_error: float

    @classmethod
    def of(cls, attempts: list[Attempt], lower: np.ndarray, upper: np.ndarray) -> Outcome:
        """The summary of ``attempts``, the returned one the converged or else the closest."""
        best = attempts[-1]
        if best.status != Status.CONVERGED:
            best = min(attempts, key=lambda attempt: attempt.error_sq)
        errors = np.sqrt([a.error_sq for a in attempts])
        gradients = np.array([stationarity(a, lower, upper) for a in attempts])
        return cls(
            q=best.q,
            history=np.array(best.history),
            errors=np.array(best.errors),
            iterations=sum(len(attempt.history) - 1 for attempt in attempts),
            attempts=len(attempts),
            same_stationary_point=same_stationary_point(
                len(attempts), errors.min(), errors.max(), bool(np.all(gradients <= 1e-4 * errors))
            ),
            all_diverged=all(attempt.status == Status.DIVERGED for attempt in attempts),
            e=best.e,
            position_error=float(np.linalg.norm(best.e[:3])),
            rotation_error=float(np.linalg.norm(best.e[3:])),
        )


def finish(problem: PoseProblem, outcome: Outcome, method: str, reach: float) -> IKResult:
    """The result of the attempts of ``"newton"``, ``"transpose"`` or ``"hybrid"``.

    ``reach`` is the target's distance beyond the chain's reach (0 within it).
    """
    robot = problem.robot
    q, e = shift_into_limits(robot, outcome.q), outcome.e
    position_error, rotation_error = outcome.position_error, outcome.rotation_error
    if q is not outcome.q:
        T, e = np.eye(4), np.empty(6)
        robot.state.kinematics(q, problem.frame, T)
        position_error, rotation_error = world_error(problem.T_target, T, e)
    inside = robot.within_limits(q)
    success = problem.within(position_error, rotation_error) and (
        inside or not problem.respect_limits
    )
    status, message = verdict(
        success, inside, position_error, rotation_error, reach,
        outcome.same_stationary_point, outcome.all_diverged, outcome.attempts,
        outcome.iterations,
    )  # fmt: skip
    return IKResult(
        q=q.copy(),
        success=success,
        status=status,
        iterations=outcome.iterations,
        error=body_twist_norm(e),
        position_error=position_error,
        rotation_error=rotation_error,
        history=outcome.history,
        error_history=outcome.errors,
        restarts=outcome.attempts - 1,
        method=method,
        message=message,
    )


def verdict(
    success: bool,
    inside: bool,
    position_error: float,
    rotation_error: float,
    reach: float,
    same_stationary_point: bool,
    all_diverged: bool,
    attempts: int,
    iterations: int,
) -> tuple[Status, str]:
    """``(status, message)`` of a solve from what its attempts found.

    A target farther from the first joint than the chain can reach (``reach > 0``), or one
    at which every attempt stopped at the same non-zero error with a vanishing gradient
    ``Jᵀe``, is ``"unreachable"``; other failures are ``"max_iterations"``, or
    ``"diverged"`` when every attempt hit a NaN.
    """
    if success:
        return (
            Status.CONVERGED,
            "" if inside else "q is outside the joint limits (respect_limits=False)",
        )
    closest = f"closest pose found: {position_error:.3g} m, {rotation_error:.3g} rad away"
    if reach > 0.0:
        return Status.UNREACHABLE, (
            f"the target is {reach:.3g} m beyond the reach of the chain from its first joint; "
            f"{closest}"
        )
    if same_stationary_point:
        return Status.UNREACHABLE, (
            f"all {attempts} attempts stopped at the same error with a vanishing "
            f"gradient Jᵀe; {closest}"
        )
    if all_diverged:
        return Status.DIVERGED, f"every attempt produced NaN or inf; {closest}"
    return Status.MAX_ITERATIONS, (
        f"no attempt of {attempts} converged ({iterations} iterations); {closest}"
    )


def body_twist_norm(e: np.ndarray) -> float:
    r"""``‖log(T⁻¹ T_d)‖`` from the world error ``e = (d, w) = (p_d − p, log(R_d Rᵀ))``.

    The body twist is ``ω_b = Rᵀ w`` and ``v_b = V(ω_b)⁻¹ Rᵀ d = Rᵀ V(w)⁻¹ d`` (``V`` is
    equivariant under rotation), so ``‖ξ_b‖² = ‖V(w)⁻¹ d‖² + ‖w‖²`` with
    ``V⁻¹`` of :func:`redik.lie.apply_inverse_v`. The compiled ``"dls"`` kernel computes the
    same from the same source (:func:`redik.solvers.dls.solve_one`).
    """
    dx, dy, dz, wx, wy, wz = e.tolist()
    vx, vy, vz = apply_inverse_v(wx, wy, wz, dx, dy, dz)
    return math.sqrt(vx * vx + vy * vy + vz * vz + wx * wx + wy * wy + wz * wz)


def same_stationary_point(
    attempts: int, error_min: float, error_max: float, stationary: bool
) -> bool:
    """Every attempt (at least two) ended at one non-zero error with ``Jᵀe ≈ 0``.

    One error: ``error_min … error_max`` within 1 %; ``stationary``: ``‖Jᵀe‖ ≤ 1e-4 ‖e‖``
    for each attempt.
    """
    return (
        attempts >= 2
        and math.isfinite(error_max)
        and error_min > 0.0
        and error_max <= 1.01 * error_min
        and stationary
    )


def shift_into_limits(robot: Robot, q: np.ndarray) -> np.ndarray:
    """Revolute joints outside their range moved by the multiple of 2π that fits, if any.

    Returns ``q`` itself when no joint moved.
    """
    outside = robot.revolute & ((q < robot.lower) | (q > robot.upper))
    if not np.any(outside):
        return q
    q = q.copy()
    for i in np.flatnonzero(outside):
        shifted = wrap_into_range(q[i], robot.lower[i])
        if shifted <= robot.upper[i]:
            q[i] = shifted
    return q


def limits_message(robot: Robot, result: IKResult, q_free: np.ndarray) -> str:
    """The message of a ``"limits"`` failure.

    It names the joints of ``result.q`` at a limit (within 1e-6 rad or m), the joints the
    unconstrained solution ``q_free`` puts outside (angles in (−π, π]), and the closest pose
    found within the limits.
    """
    names = robot.joint_names
    values, free = robot.scalar_values(result.q), robot.scalar_values(q_free)
    # No multiple of 2π brought these inside (shift_into_limits): show them in (−π, π].
    free = np.where(robot.revolute, wrap_angle(free), free)
    lower, upper = robot.lower, robot.upper

    def name(i: int) -> str:
        return names[i] if len(names) == len(lower) else f"dof {i}"

    at_limit = [
        f"{name(i)} at its {'lower' if values[i] - lower[i] <= 1e-6 else 'upper'} limit"
        for i in range(len(lower))
        if values[i] - lower[i] <= 1e-6 or upper[i] - values[i] <= 1e-6
    ]
    outside = [
        f"{name(i)} = {free[i]:.3g} outside [{lower[i]:.3g}, {upper[i]:.3g}]"
        for i in range(len(lower))
        if not lower[i] <= free[i] <= upper[i]
    ]
    return (
        f"the target is reached only outside the joint limits as far as can be told: a solve "
        f"without them converged with {', '.join(outside)}; within them, "
        f"{', '.join(at_limit) if at_limit else 'no joint at a limit'}; closest pose found: "
        f"{result.position_error:.3g} m, {result.rotation_error:.3g} rad away"
    )
