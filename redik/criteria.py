r"""Secondary criteria of a configuration, value and gradient: the one home of their math.

Three scalar functions of the joint values that a redundant arm can improve without
leaving its task — the classic secondary criteria of gradient projection (Liégeois 1977;
Siciliano, Sciavicco, Villani & Oriolo, *Robotics: Modelling, Planning and Control*, §3.5.1).
The tasks (:class:`redik.JointLimitAvoidanceTask`, :class:`redik.ManipulabilityTask`), the
null-space tools (:mod:`redik.solvers.redundancy.nullspace`) and the self-motion scores
(:mod:`redik.solvers.redundancy.scoring`) all call these functions.

**Joint limits.** With the range scaling :math:`s_i = 1/(u_i - l_i)` and middle
:math:`\bar q_i = \tfrac12 (l_i + u_i)` of each limited joint (:math:`s_i = \bar q_i = 0`
for a joint without finite limits, or with an empty range), the quadratic potential and
its derivatives are

.. math::

    φ(δ) = \sum_i (s_i δ_i)^2, \qquad ∇φ = 2 s^2 ⊙ δ, \qquad ∇^2φ = 2\,\mathrm{diag}(s^2),

with :math:`δ = q - \bar q` (:math:`q \ominus \bar q` across ball and free joints; the
caller forms it). Liégeois' *distance from the limits* to maximise (Siciliano et al.
eq. 3.58) is :math:`w(q) = -φ(q - \bar q) / (2n)`, :math:`n` the number of limited joints.
The *margin* :math:`\min_i \min(q_i - l_i, u_i - q_i)` is the distance to the nearest
limit; its ascent direction is the gradient of the soft minimum
:math:`-τ \log \sum_j e^{-m_j/τ}` of the :math:`2n` limit distances :math:`m`.

**Manipulability** (Yoshikawa 1985; Siciliano et al. eq. 3.56): :math:`w = \sqrt{\det(J
J^\top)}` of the 6 × n ``"world"`` Jacobian of :mod:`redik.core.conventions` (the same for the
space and body Jacobians: they differ by a matrix of determinant 1). From
:math:`∂ \det A = \det A\, \mathrm{tr}(A^{-1} ∂A)` with :math:`A = J J^\top`,

.. math::

    \frac{∂w}{∂q_k} = w\, \mathrm{tr}\!\left(J^\top (J J^\top)^{-1} \frac{∂J}{∂q_k}\right)

(Haviland & Corke, *Manipulator Differential Kinematics, Part I*, 2023, eq. 57), with
:math:`∂J/∂q_k` of :func:`jacobian_derivatives`. Where :math:`w < 10^{-12}` (a
singularity, where the square root is not differentiable) the gradient is taken as zero.

**Posture.** :math:`δ = q - q_{nom}`, wrapped to :math:`(-π, π]` on the periodic joints
(hinges without limits); the distance is :math:`\|δ\|` and the ascent of
:math:`-\tfrac12 \|δ\|^2` is :math:`-δ`.

Every function takes a single configuration (or Jacobian) or a batch stacked along leading
axes, as the self-motion scoring evaluates thousands of samples at once.
"""

from __future__ import annotations

import numpy as np

from redik.lie import wrap_angle

SINGULAR_MANIPULABILITY = 1e-12
"""Below this manipulability the gradient of :func:`manipulability_gradient` is zero."""


def _scalar_or_array(values: np.ndarray) -> float | np.ndarray:
    return float(values) if np.ndim(values) == 0 else values


# --------------------------------------------------------------------------------------
# Joint limits


def joint_limit_scaling(lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""``(s, q̄)``: the range scaling ``1/(u − l)`` and middle ``(l + u)/2`` of each joint.

    Both are 0 for a joint without two finite limits, and ``s`` is 0 for an empty range
    (``u = l``): such joints carry no potential.
    """
    lower = np.asarray(lower, dtype=float)
    upper = np.asarray(upper, dtype=float)
    limited = np.isfinite(lower) & np.isfinite(upper)
    span = np.where(limited, upper - lower, 1.0)
    scale = np.where(limited & (span > 0.0), 1.0 / np.where(span > 0.0, span, 1.0), 0.0)
    middle = 0.5 * (np.where(limited, lower, 0.0) + np.where(limited, upper, 0.0))
    return scale, middle


def joint_limit_potential(deviation: np.ndarray, scale: np.ndarray) -> float | np.ndarray:
    r"""``φ = Σ_i (s_i δ_i)²`` of the deviation ``δ`` from the middle of the ranges (``…, n``)."""
    scaled = np.asarray(deviation, dtype=float) * scale
    return _scalar_or_array(np.einsum("...i,...i->...", scaled, scaled))


def joint_limit_potential_gradient(deviation: np.ndarray, scale: np.ndarray) -> np.ndarray:
    r"""``∇φ = 2 s² ⊙ δ`` (``…, n``), with respect to the joints' tangent coordinates."""
    return 2.0 * scale**2 * np.asarray(deviation, dtype=float)


def joint_limit_potential_hessian(scale: np.ndarray) -> np.ndarray:
    r"""``∇²φ = 2 diag(s²)`` (n × n, constant)."""
    return np.diag(2.0 * np.asarray(scale, dtype=float) ** 2)


def joint_limit_distance(q: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> float:
    r"""Liégeois' distance from the joint limits (Siciliano et al. eq. 3.58), to maximise.

    .. math:: w(q) = -\frac{1}{2n} \sum_i \left(\frac{q_i - \bar q_i}{u_i - l_i}\right)^2
        = -\frac{φ(q - \bar q)}{2n},

    the sum over the ``n`` joints with finite limits (0 when there are none).
    """
    count = int(np.sum(np.isfinite(lower) & np.isfinite(upper)))
    if not count:
        return 0.0
    scale, middle = joint_limit_scaling(lower, upper)
    return float(-joint_limit_potential(np.asarray(q, dtype=float) - middle, scale) / (2 * count))


def joint_limit_distance_gradient(
    q: np.ndarray, lower: np.ndarray, upper: np.ndarray
) -> np.ndarray:
    r"""``∇w`` of :func:`joint_limit_distance`: ``−(q_i − q̄_i) / (n (u_i − l_i)²)``."""
    q = np.asarray(q, dtype=float)
    count = int(np.sum(np.isfinite(lower) & np.isfinite(upper)))
    if not count:
        return np.zeros_like(q)
    scale, middle = joint_limit_scaling(lower, upper)
    return -joint_limit_potential_gradient(q - middle, scale) / (2 * count)


def joint_limit_margin(q: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> float | np.ndarray:
    """Distance of ``q`` (``…, n``) to its nearest joint limit, ``min_i min(q_i − l_i, u_i − q_i)``.

    In joint units (rad or m); negative outside the limits, ``inf`` without limits.
    """
    q = np.asarray(q, dtype=float)
    margins = np.minimum(q - lower, upper - q)
    return _scalar_or_array(np.min(margins, axis=-1, initial=np.inf))


def joint_limit_margin_gradient(
    q: np.ndarray, lower: np.ndarray, upper: np.ndarray, temperature: float = 0.05
) -> np.ndarray:
    r"""Gradient of the soft minimum of the ``2n`` limit distances, to ascend.

    :func:`joint_limit_margin` is a minimum, not differentiable where two distances tie; its
    smooth stand-in ``−τ log Σ_j exp(−m_j / τ)`` over ``m = (q − l, u − q)`` differs from it by
    at most ``τ log 2n`` and has the softmax-weighted gradient returned here.
    """
    q = np.asarray(q, dtype=float)
    margins = np.concatenate([q - lower, upper - q])
    finite = np.isfinite(margins)
    gradient = np.zeros_like(q)
    if not np.any(finite):
        return gradient
    weights = np.zeros_like(margins)
    exponent = -margins[finite] / temperature
    weights[finite] = np.exp(exponent - exponent.max())  # the softmax, shifted not to overflow
    weights /= weights.sum()
    n = q.shape[0]
    return weights[:n] - weights[n:]


# --------------------------------------------------------------------------------------
# Manipulability


def manipulability(J: np.ndarray) -> float | np.ndarray:
    r"""Yoshikawa's manipulability ``w = √det(JJᵀ)`` of a Jacobian (``…, 6, n``)."""
    J = np.asarray(J, dtype=float)
    det = np.linalg.det(J @ np.swapaxes(J, -1, -2))
    return _scalar_or_array(np.sqrt(np.maximum(det, 0.0)))


def jacobian_derivatives(J_world: np.ndarray) -> np.ndarray:
    r"""``∂J/∂q_k`` of the ``"world"`` Jacobian of a serial chain, as an (…,) n × 6 × n array.

    Each column ``J_i = (v_i, ω_i)`` (``ω_i`` the joint axis for a hinge, 0 for a slide)
    moves with the joints upstream of it and with the end point (Haviland & Corke 2023,
    eq. 42 in (v, ω) order):

    .. math::

        \frac{∂J_i}{∂q_k} = \begin{cases}
            (ω_k × v_i,\; ω_k × ω_i) & k ≤ i \\
            (ω_i × v_k,\; 0) & k > i
        \end{cases}
    """
    J_world = np.asarray(J_world, dtype=float)
    v = np.swapaxes(J_world[..., :3, :], -1, -2)  # … × n × 3
    w = np.swapaxes(J_world[..., 3:, :], -1, -2)
    n = v.shape[-2]
    w_cross_v = np.cross(w[..., :, None, :], v[..., None, :, :])  # [k, i] = ω_k × v_i
    w_cross_w = np.cross(w[..., :, None, :], w[..., None, :, :])  # [k, i] = ω_k × ω_i
    upstream = np.triu(np.ones((n, n), dtype=bool))[:, :, None]  # [k, i]: k ≤ i
    dv = np.where(upstream, w_cross_v, np.swapaxes(w_cross_v, -3, -2))
    dw = np.where(upstream, w_cross_w, 0.0)
    return np.concatenate([np.swapaxes(dv, -1, -2), np.swapaxes(dw, -1, -2)], axis=-2)


def manipulability_gradient(J_world: np.ndarray) -> np.ndarray:
    r"""``∇w`` (``…, n``) of ``w = √det(JJᵀ)`` from the ``"world"`` Jacobian (``…, 6, n``).

    ``∂w/∂q_k = w · tr(Jᵀ(JJᵀ)⁻¹ ∂J/∂q_k)`` (Haviland & Corke eq. 57, with ``J⁺`` of a full
    row rank ``J``); zero where ``w <`` :data:`SINGULAR_MANIPULABILITY`.
    """
    J_world = np.asarray(J_world, dtype=float)
    w = np.asarray(manipulability(J_world))
    regular = w >= SINGULAR_MANIPULABILITY
    gradient = np.zeros(J_world.shape[:-2] + J_world.shape[-1:])
    if not np.any(regular):
        return gradient
    J = J_world[regular] if J_world.ndim > 2 else J_world[None]
    JJt = J @ np.swapaxes(J, -1, -2)
    M = np.linalg.solve(JJt, J)  # (JJᵀ)⁻¹ J, so tr(Jᵀ(JJᵀ)⁻¹ ∂J) = Σ M ⊙ ∂J
    values = np.reshape(w[regular], (-1, 1)) * np.einsum("bai,bkai->bk", M, jacobian_derivatives(J))
    if J_world.ndim > 2:
        gradient[regular] = values
        return gradient
    return values[0]


# --------------------------------------------------------------------------------------
# Posture


def posture_difference(
    q: np.ndarray, nominal: np.ndarray, periodic: np.ndarray | None = None
) -> np.ndarray:
    """``q − q_nominal`` (``…, n``), wrapped to (−π, π] on the ``periodic`` joints."""
    delta = np.asarray(q, dtype=float) - nominal
    if periodic is not None and np.any(periodic):
        delta[..., periodic] = wrap_angle(delta[..., periodic])
    return delta


def posture_distance(
    q: np.ndarray, nominal: np.ndarray, periodic: np.ndarray | None = None
) -> float | np.ndarray:
    """``‖q − q_nominal‖`` (periodic joints wrapped), for one configuration or a batch."""
    return _scalar_or_array(np.linalg.norm(posture_difference(q, nominal, periodic), axis=-1))


def posture_gradient(
    q: np.ndarray, nominal: np.ndarray, periodic: np.ndarray | None = None
) -> np.ndarray:
    """``∇w = −(q − q_nominal)`` of ``w = −½‖q − q_nominal‖²``: ascending it nears the posture."""
    return -posture_difference(q, nominal, periodic)
