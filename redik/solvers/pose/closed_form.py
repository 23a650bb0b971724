"""``solve_all(method="analytic")``: every solution of a robot's closed-form solver as results.

:func:`redik.solvers.analytic.solver_for` gives the solver (the class of the robot's screws
solved by subproblems, or for a general 6R arm the Raghavan–Roth elimination); each of
its solutions becomes an :class:`~redik.core.result.IKResult` like the numeric ones, ordered
by the norm of the body error ``log(T⁻¹ T_d)``.
"""

from __future__ import annotations

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import IKResult, Status
from redik.kinematics.robot import Frame, Robot
from redik.lie import inverse, pose_errors, se3_log
from redik.solvers.cache import solver_cache


def closed_form_solutions(
    robot: Robot,
    T_target: np.ndarray,
    respect_limits: bool,
    frame: str | Frame | None,
    options: dict[str, object],
) -> list[IKResult]:
    """Every solution of the robot's closed-form solver (kept in its
    :func:`~redik.solvers.cache.solver_cache`) for the validated pose ``T_target``;
    ``message`` carries the solution's label (and singularity), ``method`` the solver's
    class (``"analytic:three_parallel_two_intersecting"``, ``"analytic:general"``, …).

    Raises:
        InvalidInput: An option was given (there are none), or ``frame`` is not the
            end-effector the solver was built for.
        ModelError: The robot has no closed-form solver (:func:`solver_for`'s errors).
    """
    from redik.solvers.analytic import solver_for  # on use: the numeric methods need none

    if options:
        raise InvalidInput(f"method 'analytic' takes no options, got {sorted(options)}")
    if frame is not None and robot.frame(frame) != robot.frame(None):
        raise InvalidInput(
            "method 'analytic' solves for the end-effector the closed-form solver was built "
            f"for, not {frame!r}"
        )
    solver = solver_cache(robot).get_or_build("analytic", lambda: solver_for(robot))
    solutions = solver(T_target, limits="robot" if respect_limits else None)
    method = f"analytic:{solver.kind}"
    results = []
    for solution in solutions:
        q = np.array(solution, dtype=float)
        T = robot.fk(q)
        position_error, rotation_error = pose_errors(T, T_target)
        note = solution.label + (f" (singular: {solution.singular})" if solution.singular else "")
        results.append(
            IKResult(
                q=q,
                success=True,
                status=Status.CONVERGED,
                iterations=0,
                error=float(np.linalg.norm(se3_log(inverse(T) @ T_target))),
                position_error=position_error,
                rotation_error=rotation_error,
                history=q[None].copy(),
                method=method,
                message=note,
            )
        )
    return sorted(results, key=lambda r: r.error)
