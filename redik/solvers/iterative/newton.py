r"""Newton–Raphson: the one Newton loop of redik (Lynch & Park, *Modern Robotics* §6.2).

.. math:: q_{k+1} = q_k + λ^k\, J^{+}(q_k)\, e(q_k), \qquad e = x_d − f(q),

with ``J⁺ = J⁻¹`` for a square ``J`` and the pseudo-inverse otherwise
(:func:`~redik.solvers.iterative.steps.newton_step`). The residual decides what ``e`` and ``J``
are: a user's ``f`` (:func:`redik.solve_equations`, §6.2.1), or the body error twist
``V_b = log(T_sb⁻¹ T_sd)`` with the body Jacobian ``J_b`` — Algorithm *IKinBody* of §6.2.2,
which :func:`redik.solve_pose` runs with ``method="newton"``, restarts and joint limits
outside the method.
"""

from __future__ import annotations

import numpy as np

from redik.solvers.iterative.iterates import Iterates, P, Residual
from redik.solvers.iterative.rules import Step, StoppingRules
from redik.solvers.iterative.steps import newton_step


def newton_raphson(
    residual: Residual[P], q0: np.ndarray, rules: StoppingRules, step: Step = 1.0
) -> Iterates[P]:
    r"""Newton–Raphson from ``q0``: ``q ← q + λ J⁺ e`` until a stopping rule holds.

    The steps of Lynch & Park §6.2.2 (*IKinBody*), line by line: initialise with ``e(q_0)``;
    while the error test fails (``‖ω_b‖ > ε_ω`` or ``‖v_b‖ > ε_v`` for the body twist; the
    rules of :class:`~redik.solvers.iterative.rules.StoppingRules` in general), take
    ``q_{k+1} = q_k + λ J⁺(q_k) e(q_k)`` and evaluate ``e(q_{k+1})``.

    Args:
        residual: ``e(q)`` and ``J(q)``.
        q0: The initial guess.
        rules: The stopping rules (the error test, the budget, the singularity test…).
        step: ``λ`` (1 is the full Newton step), or ``"armijo"``: backtracking from ``λ = 1``
            on ``½‖e‖²``, which keeps the full step near the root and its quadratic rate.

    Returns:
        The run: its iterates, errors and status.
    """
    with Iterates(residual, q0, rules) as run:
        while run.running():
            J = run.jacobian()
            if J is None or run.singular(J):
                break
            run.advance(newton_step(J, run.e), J, step)
    return run
