r"""Gradient descent on a pose error (Jacobian transpose), and the transpose-then-Newton hybrid.

``"transpose"``: ``q ← q + α Jᵀ e`` on ``½‖e‖²``, ``e = (p_d − p, log(R_d Rᵀ))``; with
``step="armijo"`` (default) each line search starts at Buss's step
``α₀ = ⟨e, JJᵀe⟩ / ‖JJᵀe‖²`` (the minimiser along ``Jᵀe`` of the linearised error) and
backtracks until the Armijo condition holds (:func:`redik.solvers.iterative.armijo_backtrack`),
so ``‖e‖`` never increases; a number is a constant ``α``. ``"hybrid"``: transpose (Armijo)
steps while ``‖e‖ > switch_error``, where the gradient is robust, then Newton steps
``q ← q + J⁺ e`` for quadratic terminal convergence; an increasing Newton step falls back to a
gradient step.
"""

from __future__ import annotations

import math

import numpy as np

from redik.core.result import Status
from redik.core.validate import positive
from redik.solvers.iterative import ARMIJO_ATTEMPT_TRIALS, armijo_backtrack
from redik.solvers.pose.attempt import Attempt, Iteration, PoseProblem


def transpose_step(
    problem: PoseProblem,
    q: np.ndarray,
    J: np.ndarray,
    e: np.ndarray,
    E: float,
    step: float | str,
    trial: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> tuple[np.ndarray, float] | None:
    """One gradient step ``q + α Jᵀe`` evaluated into ``trial = (T, J, e)``.

    Armijo (:func:`redik.solvers.iterative.armijo_backtrack`): start from Buss's
    ``α₀ = ⟨e, JJᵀe⟩/‖JJᵀe‖²`` and halve until ``‖e(q + αg)‖² ≤ ‖e‖² − 2cα‖g‖²``.
    Returns ``(q_new, ‖e_new‖²)``, or None when no trial decreases the error (or every
    trial is non-finite).
    """
    T_trial, J_trial, e_trial = trial
    g = J.T @ e
    slope = float(g @ g)
    last = [q]

    def squared_error_at(alpha: float) -> float:
        last[0] = problem.project(q + alpha * g)
        problem.robot.state.kinematics(last[0], problem.frame, T_trial, J_trial)
        problem.world_error(T_trial, e_trial)
        return float(e_trial @ e_trial)

    if step != "armijo":
        E_new = squared_error_at(step)
        return (last[0], E_new) if math.isfinite(E_new) else None
    Jg = J @ g
    curvature = float(Jg @ Jg)
    # The merit ‖e‖² = 2F has the slope ∇(‖e‖²)ᵀg = −2‖g‖² along g = Jᵀe.
    alpha, _ = armijo_backtrack(
        squared_error_at,
        E,
        -2.0 * slope,
        slope / curvature if curvature > 0.0 else 1.0,
        trials=ARMIJO_ATTEMPT_TRIALS,
    )
    return None if alpha is None else (last[0], float(e_trial @ e_trial))


def transpose(options: dict) -> Iteration:
    """The ``"transpose"`` attempt for ``options["step"]`` ("armijo" or a positive number)."""
    step = options["step"]
    if step != "armijo":
        step = positive(step, "step")

    def iterate(problem: PoseProblem, q: np.ndarray, max_iterations: int) -> Attempt:
        return gradient_then_newton(problem, q, max_iterations, step, switch_error=0.0)

    return iterate


def hybrid(options: dict) -> Iteration:
    """The ``"hybrid"`` attempt for ``options["switch_error"]`` (a positive ``‖e‖``)."""
    switch_error = positive(options["switch_error"], "switch_error")

    def iterate(problem: PoseProblem, q: np.ndarray, max_iterations: int) -> Attempt:
        return gradient_then_newton(problem, q, max_iterations, "armijo", switch_error)

    return iterate


def gradient_then_newton(
    problem: PoseProblem, q: np.ndarray, max_iterations: int, step: float | str, switch_error: float
) -> Attempt:
    """Gradient steps while ``‖e‖ > switch_error``, Newton steps ``J⁺e`` below it."""
    robot, frame, n = problem.robot, problem.frame, problem.n
    T, J, e = np.eye(4), np.empty((6, n)), np.empty(6)
    trial = (np.eye(4), np.empty((6, n)), np.empty(6))
    robot.state.kinematics(q, frame, T, J)
    errors_now = problem.world_error(T, e)
    E = float(e @ e)
    history, errors = [q.copy()], [math.sqrt(E)]
    status = Status.MAX_ITERATIONS
    for _ in range(max_iterations):
        if problem.within(*errors_now):
            status = Status.CONVERGED
            break
        stepped = None
        if E < switch_error**2:
            q_new = problem.project(q + np.linalg.pinv(J) @ e)
            T_new, J_new, e_new = trial
            robot.state.kinematics(q_new, frame, T_new, J_new)
            problem.world_error(T_new, e_new)
            E_new = float(e_new @ e_new)
            if E_new < E:
                stepped = q_new, E_new
        if stepped is None:
            stepped = transpose_step(problem, q, J, e, E, step, trial)
        if stepped is None or not math.isfinite(stepped[1]):
            status = Status.STALLED if stepped is None else Status.DIVERGED
            break
        q, E = stepped
        (T, J, e), trial = trial, (T, J, e)
        errors_now = (float(np.linalg.norm(e[:3])), float(np.linalg.norm(e[3:])))
        history.append(q.copy())
        errors.append(math.sqrt(E))
    else:
        if problem.within(*errors_now):
            status = Status.CONVERGED
    return Attempt(q, status, history, errors, E, J, e)
