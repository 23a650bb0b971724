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
:func:`redik.solvers.redundancy.gradient_projection.gradient_projection_ik` iterates them
into a solver that reaches a pose while climbing a criterion.

Twists and Jacobians follow :mod:`redik.core.conventions`: ``(v, ω)`` order; the manipulability
gradient takes the ``"world"`` Jacobian (origin velocity and angular velocity in world axes),
for which ``det(JJᵀ)`` equals that of the body Jacobian.
"""

from __future__ import annotations

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.validate import as_vector, real_array

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
    """An orthonormal basis of ``ker J`` as the columns of an n × k matrix (… × n × k for a
    stack of Jacobians … × m × n).

    ``k`` is ``n − rank J`` by default (one ``J`` only), or ``dimension`` when given (the
    right-singular vectors of the ``dimension`` smallest singular values: the directions that
    move the task least, which is ``ker J`` itself at full rank; the tangent space of a
    self-motion manifold, :mod:`redik.solvers.redundancy.corrector`).

    Why not ``scipy.linalg.null_space(J, rcond=RANK_TOLERANCE)``, which gives the same basis
    (to 0.0 in absolute value, 200 random 6 × 7 Jacobians): it takes 1.8–2.0× the time
    (60–72 against 33–35 µs per call, same run, load 3.7), and it has neither the stack nor
    the fixed ``dimension``.
    """
    J = np.asarray(J, dtype=float)
    _, s, Vt = np.linalg.svd(J, full_matrices=True)
    if dimension is None:
        rank = int(np.sum(s > RANK_TOLERANCE * (s[0] if s.size else 0.0)))
        dimension = J.shape[1] - rank
    return np.swapaxes(Vt[..., J.shape[-1] - dimension :, :], -1, -2).copy()


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
