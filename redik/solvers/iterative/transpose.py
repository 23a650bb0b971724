r"""The Jacobian transpose: the one gradient loop of redik.

.. math:: q_{k+1} = q_k + α^k\, J^\top(q_k)\, K\, e(q_k),

gradient descent on ``F = ½ eᵀKe`` for a symmetric positive-definite gain ``K`` (``∇F =
−JᵀKe``; Buss 2004, "Introduction to Inverse Kinematics with Jacobian Transpose,
Pseudoinverse and Damped Least Squares methods", §4), and for any ``K`` whose symmetric part
is positive definite the discrete feedback law ``q̇ = Jᵀ K e`` (Siciliano et al., *Robotics:
Modelling, Planning and Control* §3.7.2; the course notes 002, where a rotation-like ``K``
turns ``e`` out of ``ker Jᵀ`` at a stationary point). The residual is a user's ``f``
(:func:`redik.solve_equations`, ``method="transpose"``) or the world pose error of a robot
(:func:`redik.solve_pose`, ``method="transpose"``).
"""

from __future__ import annotations

import numpy as np

from redik.solvers.iterative.iterates import Iterates, P, Residual
from redik.solvers.iterative.rules import Step, StoppingRules
from redik.solvers.iterative.steps import linearised_minimiser, transpose_step


def jacobian_transpose(
    residual: Residual[P],
    q0: np.ndarray,
    rules: StoppingRules,
    step: Step = "armijo",
    gain: np.ndarray | None = None,
) -> Iterates[P]:
    r"""The Jacobian transpose from ``q0``: ``q ← q + α JᵀKe`` until a stopping rule holds.

    Args:
        residual: ``e(q)`` and ``J(q)``.
        q0: The initial guess.
        rules: The stopping rules.
        step: A constant ``α``, or ``"armijo"``: backtracking on the merit ``F = ½ eᵀK_s e``
            (``K_s = (K + Kᵀ)/2``, so ``eᵀKe = eᵀK_s e``) with the slope
            ``∇Fᵀd = −eᵀK_s J d``, from the minimiser of the linearised merit along ``d``
            (Buss's step ``⟨e, JJᵀe⟩/‖JJᵀe‖²`` for ``K = I``); ``F`` never increases.
        gain: ``K`` (checked by :func:`~redik.solvers.iterative.rules.gain_matrix`), or None
            for the identity.

    Returns:
        The run: its iterates, errors and status.
    """
    with Iterates(residual, q0, rules, gain) as run:
        while run.running():
            J = run.jacobian()
            if J is None or run.singular(J):
                break
            d = transpose_step(J, run.e, gain)
            run.advance(d, J, step, first_trial=linearised_minimiser(J, run.e, d, run.weight))
    return run
