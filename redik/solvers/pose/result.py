r"""The :class:`~redik.core.result.IKResult` of a pose solve: success by the pose of the
returned ``q``, the status, and the unreachable diagnosis.

Success is decided from the pose of the returned ``q``: ``‖p_d − p‖ ≤ pos_tol``,
``angle(Rᵀ R_d) ≤ rot_tol`` and, with ``respect_limits``, ``lower ≤ q ≤ upper``
(:func:`verdict`). A revolute joint outside its range is first shifted by the multiple of 2π
that brings it inside, if one does (:func:`shift_into_limits`; the pose is unchanged).
``result.error`` is always the body error ``‖log(T⁻¹ T_d)‖`` (:func:`body_twist_norm`).

The compiled ``"dls"`` driver (:mod:`~redik.solvers.pose.dls`) computes the summary of its
attempts in the kernel; the Python drivers' attempts are summarised by :class:`Outcome`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from redik.core.result import IKResult
from redik.kinematics.robot import Robot
from redik.lie import apply_inverse_v, wrap_into_range
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
        best = attempts[-1]
        if best.status != "converged":
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
            all_diverged=all(attempt.status == "diverged" for attempt in attempts),
            e=best.e,
            position_error=float(np.linalg.norm(best.e[:3])),
            rotation_error=float(np.linalg.norm(best.e[3:])),
        )


def finish(problem: PoseProblem, outcome: Outcome, method: str, reach: float) -> IKResult:
    """The result of a Python driver's attempts; ``reach`` is the target's distance beyond
    the chain's reach (0 within it)."""
    robot = problem.robot
    q, e = shift_into_limits(robot, outcome.q), outcome.e
    position_error, rotation_error = outcome.position_error, outcome.rotation_error
    if q is not outcome.q:
        T, e = np.eye(4), np.empty(6)
        robot.kinematics(q, problem.frame, T)
        position_error, rotation_error = problem.world_error(T, e)
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
) -> tuple[str, str]:
    """``(status, message)`` of a solve from what its attempts found.

    A target farther from the first joint than the chain can reach (``reach > 0``), or one
    at which every attempt stopped at the same non-zero error with a vanishing gradient
    ``Jᵀe``, is ``"unreachable"``; other failures are ``"max_iterations"``, or
    ``"diverged"`` when every attempt hit a NaN.
    """
    if success:
        return "converged", "" if inside else "q is outside the joint limits (respect_limits=False)"
    closest = f"closest pose found: {position_error:.3g} m, {rotation_error:.3g} rad away"
    if reach > 0.0:
        return "unreachable", (
            f"the target is {reach:.3g} m beyond the reach of the chain from its first joint; "
            f"{closest}"
        )
    if same_stationary_point:
        return "unreachable", (
            f"all {attempts} attempts stopped at the same error with a vanishing "
            f"gradient Jᵀe; {closest}"
        )
    if all_diverged:
        return "diverged", f"every attempt produced NaN or inf; {closest}"
    return "max_iterations", (
        f"no attempt of {attempts} converged ({iterations} iterations); {closest}"
    )


def body_twist_norm(e: np.ndarray) -> float:
    r"""``‖log(T⁻¹ T_d)‖`` from the world error ``e = (d, w) = (p_d − p, log(R_d Rᵀ))``.

    The body twist is ``ω_b = Rᵀ w`` and ``v_b = V(ω_b)⁻¹ Rᵀ d = Rᵀ V(w)⁻¹ d`` (``V`` is
    equivariant under rotation), so ``‖ξ_b‖² = ‖V(w)⁻¹ d‖² + ‖w‖²`` with
    ``V⁻¹`` of :func:`redik.lie.apply_inverse_v`. The compiled ``"dls"`` kernel computes the
    same from the same source (:func:`redik.kinematics.dls.solve_one`).
    """
    dx, dy, dz, wx, wy, wz = e.tolist()
    vx, vy, vz = apply_inverse_v(wx, wy, wz, dx, dy, dz)
    return math.sqrt(vx * vx + vy * vy + vz * vz + wx * wx + wy * wy + wz * wz)


def same_stationary_point(
    attempts: int, error_min: float, error_max: float, stationary: bool
) -> bool:
    """Every attempt (at least two) ended at one non-zero error (``error_min … error_max``
    within 1 %) with ``Jᵀe ≈ 0`` (``stationary``: ``‖Jᵀe‖ ≤ 1e-4 ‖e‖`` for each)."""
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
