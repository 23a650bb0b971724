r"""The transpose-then-Newton hybrid: gradient steps far from the root, Newton steps near it.

The course notes' "final remarks" (002) and Nocedal & Wright §11.2: the Jacobian transpose is
robust where Newton's linearisation is poor or ``J`` near-singular, Newton converges
quadratically near a regular root. The phase is chosen afresh at every iteration from
``‖e‖``; a Newton step that does not lower the merit is not taken, and a transpose step
replaces it.
"""

from __future__ import annotations

import numpy as np

from redik.solvers.iterative import steps
from redik.solvers.iterative.iterates import Iterates, P, Residual
from redik.solvers.iterative.rules import Step, StoppingRules


def transpose_then_newton(
    residual: Residual[P],
    q0: np.ndarray,
    rules: StoppingRules,
    switch_error: float = 0.1,
    transpose_step: Step = "armijo",
    newton_step: Step = 1.0,
    gain: np.ndarray | None = None,
) -> Iterates[P]:
    r"""Transpose steps ``α JᵀKe`` while ``‖e‖ > switch_error``, Newton steps ``λ J⁺e`` below.

    Args:
        residual: ``e(q)`` and ``J(q)``.
        q0: The initial guess.
        rules: The stopping rules; the singularity test is applied before Newton steps only
            (the transpose phase is what is used where ``J`` is ill-conditioned).
        switch_error: The ``‖e‖`` at or below which Newton takes over.
        transpose_step: ``α``, as ``step`` of
            :func:`~redik.solvers.iterative.transpose.jacobian_transpose`.
        newton_step: ``λ``, as ``step`` of
            :func:`~redik.solvers.iterative.newton.newton_raphson`.
        gain: ``K`` of the transpose steps and of the merit, or None for the identity.

    Returns:
        The run: its iterates, errors and status.
    """
    with Iterates(residual, q0, rules, gain) as run:
        while run.running():
            J = run.jacobian()
            if J is None:
                break
            if run.norm <= switch_error:
                if run.singular(J):
                    break
                if run.advance(steps.newton_step(J, run.e), J, newton_step, descent_only=True):
                    continue
            d = steps.transpose_step(J, run.e, gain)
            alpha = steps.linearised_minimiser(J, run.e, d, run.weight)
            run.advance(d, J, transpose_step, first_trial=alpha)
    return run
