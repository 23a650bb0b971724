r"""The steps the iterative methods are built from, each written once.

Every loop of :mod:`redik.solvers.iterative` and the redundancy tools of
:mod:`redik.solvers.redundancy` take their steps from here:

- :func:`newton_step`, the Newton–Raphson step ``Δq = J⁺ e`` (Lynch & Park, *Modern Robotics*
  §6.2.1);
- :func:`transpose_step`, the Jacobian-transpose step ``Δq = Jᵀ K e`` (Buss 2004, §4;
  Siciliano et al., *Robotics: Modelling, Planning and Control* §3.7.2);
- :func:`nullspace_projection`, ``(I − J⁺J) v`` (Siciliano et al. §3.5.1, eq. 3.54);
- :func:`armijo_backtrack`, the one backtracking line search (Nocedal & Wright, *Numerical
  Optimization* Alg. 3.1), and :func:`linearised_minimiser`, its first trial for a gradient
  direction.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

RANK_TOLERANCE = 1e-10
"""Singular values below ``RANK_TOLERANCE · σ_max`` count as zero where a rank-deficient
``J`` falls back to least squares (and in :func:`redik.solvers.redundancy.pseudo_inverse`)."""

ARMIJO_SUFFICIENT_DECREASE = 1e-4
"""Armijo constant ``c``: accept ``λ`` when ``F`` drops by at least ``c λ |∇Fᵀd|``."""

ARMIJO_SHRINK = 0.5
"""Backtracking factor applied to ``λ`` after each rejected trial."""

ARMIJO_MAX_TRIALS = 60
"""Halvings tried before a line search gives up, when no restart follows: ``λ`` then is
``2⁻⁶⁰ ≈ 8.7·10⁻¹⁹`` of the first trial, below the double-precision spacing (``2⁻⁵² ≈
2.2·10⁻¹⁶``) relative to a unit step, so a longer search would only re-evaluate ``q`` itself."""

ARMIJO_ATTEMPT_TRIALS = 30
"""Halvings tried by a line search inside one attempt of a restarting solver (the
``"transpose"`` and ``"hybrid"`` methods of :func:`redik.solve_pose`): ``λ`` then is ``2⁻³⁰ ≈
9.3·10⁻¹⁰`` of the first trial, itself the minimiser of the linearised error along the
direction. No decrease at a billionth of that step is a stalled attempt (a stationary point
of ``‖e‖²`` or a limit-blocked direction), and a random restart is a better use of the
evaluations that the 30 smaller trials would spend on moves far below the pose tolerances."""


def newton_step(J: np.ndarray, e: np.ndarray) -> np.ndarray:
    r"""The Newton–Raphson step ``Δq = J⁺ e`` (Lynch & Park §6.2.1).

    .. math::

        Δq = \begin{cases} J^{-1} e & r = n \\ J^\top (J J^\top)^{-1} e & r < n
        \text{ (the least-norm step)} \end{cases}

    and the least-squares, least-norm step ``argmin ‖J Δq − e‖`` (by SVD, singular values
    below :data:`RANK_TOLERANCE` ``· σ_max`` dropped) for a tall ``J`` or a singular
    ``JJᵀ``. A square ``J`` near a singularity gives the step its inverse gives, however
    large: the singularity test of the stopping rules is what guards against it (as in the
    course notes, where an unchecked Newton run from a singular start diverges).

    Args:
        J: The ``r × n`` Jacobian.
        e: The residual (``r``).

    Returns:
        ``Δq`` (``n``).
    """
    r, n = J.shape
    try:
        if r == n:
            return np.linalg.solve(J, e)
        if r < n:
            return J.T @ np.linalg.solve(J @ J.T, e)
    except np.linalg.LinAlgError:
        pass  # exactly singular: the least-squares step below
    return np.linalg.lstsq(J, e, rcond=RANK_TOLERANCE)[0]


def transpose_step(J: np.ndarray, e: np.ndarray, K: np.ndarray | None = None) -> np.ndarray:
    r"""The Jacobian-transpose step ``Δq = Jᵀ K e`` (``Jᵀe`` without a gain ``K``).

    With a symmetric positive-definite ``K`` it is the steepest-descent direction of
    ``F = ½ eᵀKe`` (``∇F = −JᵀKe`` for ``e = x_d − f(q)``, ``J = ∂f/∂q``); with any ``K``
    whose symmetric part is positive definite, the feedback law ``q̇ = Jᵀ K e`` of Siciliano
    et al. §3.7.2, where a rotation-like ``K`` turns ``e`` out of ``ker Jᵀ``.

    Args:
        J: The ``r × n`` Jacobian.
        e: The residual (``r``).
        K: The ``r × r`` gain, or None for the identity.

    Returns:
        ``Δq`` (``n``).
    """
    return J.T @ (e if K is None else K @ e)


def nullspace_projection(J: np.ndarray, v: np.ndarray) -> np.ndarray:
    r"""``(I − J⁺J) v = v − J⁺(J v)``: the part of ``v`` that leaves the task unchanged.

    The orthogonal projection onto ``ker J`` (Siciliano et al. §3.5.1, eq. 3.54), computed
    with :func:`newton_step` so that the two terms of the gradient-projection step
    ``J⁺e + (I − J⁺J) v`` share one pseudo-inverse.

    Args:
        J: The ``r × n`` Jacobian.
        v: A joint-space vector (``n``).

    Returns:
        The projection (``n``); ``J`` times it is zero when ``J`` has full row rank.
    """
    return v - newton_step(J, J @ v)


def linearised_minimiser(
    J: np.ndarray, e: np.ndarray, d: np.ndarray, weight: np.ndarray | None = None
) -> float:
    r"""The step ``α`` that minimises the linearised merit along ``d``.

    .. math:: α_0 = \frac{e^\top W J d}{(J d)^\top W (J d)}
        = \arg\min_α ½ (e − α J d)^\top W (e − α J d),

    Buss's step for the Jacobian transpose (Buss 2004, §4, with ``d = Jᵀe``, ``W = I``); 1 for
    a Newton direction of a ``J`` of full row rank. 1 where ``J d = 0``.

    Args:
        J: The Jacobian.
        e: The residual.
        d: The search direction.
        weight: ``W``, the symmetric weight of the merit, or None for the identity.

    Returns:
        ``α₀ > 0`` when ``d`` is a descent direction.
    """
    Jd = J @ d
    WJd = Jd if weight is None else weight @ Jd
    curvature = float(Jd @ WJd)
    return float(e @ WJd) / curvature if curvature > 0.0 else 1.0


def armijo_backtrack(
    merit_at: Callable[[float], float],
    F: float,
    slope: float,
    alpha: float = 1.0,
    *,
    trials: int = ARMIJO_MAX_TRIALS,
    min_alpha: float = 0.0,
) -> tuple[float | None, str]:
    r"""Backtracking line search: the first ``λ = α₀ ρᵏ`` (``k < trials``) with sufficient decrease.

    The Armijo condition ``F(λ) ≤ F + c λ ∇Fᵀd`` (Nocedal & Wright Alg. 3.1; ``c`` =
    :data:`ARMIJO_SUFFICIENT_DECREASE`, ``ρ`` = :data:`ARMIJO_SHRINK`). The one Armijo
    search of redik: every iterative method with ``step="armijo"`` uses it.

    Args:
        merit_at: ``λ ↦ F(q + λ d)``; NaN or inf for a trial that cannot be used (it is
            rejected).
        F: The merit at ``q``.
        slope: ``∇Fᵀd < 0``.
        alpha: The first trial ``α₀``.
        trials: Trials before giving up.
        min_alpha: Give up once ``λ`` falls to it or below (the step is negligible).

    Returns:
        ``(λ, "accepted")``; ``(None, "too_small")`` when ``λ`` fell to ``min_alpha`` before a
        trial was accepted; or ``(None, "exhausted")`` after ``trials`` rejections.
    """
    for _ in range(trials):
        if alpha <= min_alpha:
            return None, "too_small"
        if merit_at(alpha) <= F + ARMIJO_SUFFICIENT_DECREASE * alpha * slope:
            return alpha, "accepted"
        alpha *= ARMIJO_SHRINK
    return None, "exhausted"
