r"""Newton–Raphson on a pose: Modern Robotics' *IKinBody* and *IKinSpace* (Lynch & Park §6.2.2).

The body error twist ``V_b = log(T_sb⁻¹ T_sd)`` and ``q ← q + J_b⁺ V_b``; with
``form="space"`` the space form, ``V_s = Ad_{T_sb} V_b`` and ``q ← q + J_s⁺ V_s``. Stopping
rule (``stop``): ``"pose"`` (default) stops when ``‖p_d − p‖ ≤ pos_tol`` and
``angle(Rᵀ R_d) ≤ rot_tol`` — the success test of every method; ``"twist"`` is the book's
rule, ``‖ω‖ ≤ ε_ω = rot_tol`` and ``‖v‖ ≤ ε_v = pos_tol`` of the error twist of the form in
use (their difference: :mod:`redik.solvers.pose`).
"""

from __future__ import annotations

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import Status
from redik.core.validate import positive
from redik.lie import adjoint, body_error_twist, pose_errors, world_jacobian_to
from redik.solvers.pose.attempt import Attempt, Iteration, PoseProblem


def newton(options: dict) -> Iteration:
    """The ``"newton"`` attempt for ``options`` ``form`` ("body" or "space"), ``step`` (a
    positive multiple of the Newton step) and ``stop`` ("pose" or "twist")."""
    form = options["form"]
    if form not in ("body", "space"):
        raise InvalidInput(f"form must be 'body' or 'space', got {form!r}")
    step = positive(options["step"], "step")
    stop = options["stop"]
    if stop not in ("pose", "twist"):
        raise InvalidInput(f"stop must be 'pose' or 'twist' (Modern Robotics' rule), got {stop!r}")

    def twist_and_jacobian(
        T: np.ndarray, J: np.ndarray, T_target: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        V_b = body_error_twist(T, T_target)  # body error twist, (v, ω)
        J_form = world_jacobian_to(form, J, T[:3, :3], T[:3, 3])
        return (V_b if form == "body" else adjoint(T) @ V_b), J_form

    def done(problem: PoseProblem, T: np.ndarray, V: np.ndarray) -> bool:
        if stop == "twist":  # ‖v‖ ≤ ε_v and ‖ω‖ ≤ ε_ω, V = (v, ω)
            return problem.within(float(np.linalg.norm(V[:3])), float(np.linalg.norm(V[3:])))
        return problem.within(*pose_errors(T, problem.T_target))

    def iterate(problem: PoseProblem, q: np.ndarray, max_iterations: int) -> Attempt:
        robot, frame, n = problem.robot, problem.frame, problem.n
        T, J, e = np.eye(4), np.empty((6, n)), np.empty(6)
        robot.state.kinematics(q, frame, T, J)
        V, J_form = twist_and_jacobian(T, J, problem.T_target)
        history, errors = [q.copy()], [float(np.linalg.norm(V))]
        status = Status.MAX_ITERATIONS
        for _ in range(max_iterations):
            if done(problem, T, V):
                status = Status.CONVERGED
                break
            q_next = problem.project(q + step * (np.linalg.pinv(J_form) @ V))
            if not np.all(np.isfinite(q_next)):
                status = Status.DIVERGED
                break
            q = q_next
            robot.state.kinematics(q, frame, T, J)
            V, J_form = twist_and_jacobian(T, J, problem.T_target)
            history.append(q.copy())
            errors.append(float(np.linalg.norm(V)))
        else:
            if done(problem, T, V):
                status = Status.CONVERGED
        problem.world_error(T, e)
        return Attempt(q, status, history, errors, float(e @ e), J, e)

    return iterate
