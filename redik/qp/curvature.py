r"""The curvature of level 0's optimal set, seen by level 1: the SQP term of a strict stack.

Level 1 moves along the null space of level 0's rows :math:`A(q)` (the stacked weighted
residual rows :math:`r(q)` of its targets), which turns with :math:`q`: level 0's optimal
set is a curved manifold, and a step along its tangent leaves it at second order. Level 1's
own Hessian :math:`H_1` ignores this, and the lower level then converges only linearly. The
reduced Hessian of the Lagrangian :math:`f_1 + λ^\top r`,

.. math::

    N^\top (H_1 + M) N, \qquad M = \sum_i λ_i ∇^2 r_i ,

gives the Newton step of sequential quadratic programming, which converges quadratically
(Nocedal & Wright, *Numerical Optimization*, 2nd ed., §18.1; the null-space form, §18.4).

On the face of the joint box a point lies on, the first-order conditions of level 1 are
:math:`c_1 + A^\top λ + E_a^\top μ = 0` with :math:`E_a` the rows of the active bounds
(§12.3–12.5). Two consequences, each a function here:

- :func:`bound_multipliers` solves for :math:`λ` with the bound rows beside :math:`A`:
  without them, a bound that holds part of :math:`c_1` is credited to :math:`λ`, :math:`M` is
  wrong and the lower level converges linearly;
- :func:`on_free_face` keeps :math:`N^\top M N` on the directions the active bounds leave
  free, :math:`Y(Y^\top N^\top M N Y)Y^\top` with :math:`Y` an orthonormal basis of
  :math:`\{z : E_a N z = 0\}`: the term is used only when the model stays convex, and a
  negative curvature along a blocked direction (which the box stops anyway) would otherwise
  reject all of it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

CURVATURE_STEP = 1e-6
"""Forward-difference step (rad or m) of the derivative of ``Aᵀλ`` along a free direction."""

FACE_RANK_TOL = 1e-10
"""Relative singular value below which a row of ``E_a N`` counts as dependent."""


def bound_multipliers(
    A: NDArray[np.float64], c1: NDArray[np.float64], active: NDArray[np.bool_]
) -> NDArray[np.float64]:
    r"""Level 1's multipliers :math:`λ` of level 0's rows, active bounds taken into account.

    The least-squares solution of :math:`[A; E_a]^\top (λ; μ) ≈ -c_1`, :math:`λ` its first
    ``A.shape[0]`` entries.

    Args:
        A: Level 0's rows (m × n).
        c1: Level 1's gradient (n,).
        active: Per coordinate, True when its bound on ``Δq`` is active.

    Returns:
        :math:`λ` (m,).
    """
    K = np.vstack([A, np.eye(A.shape[1])[active]]) if active.any() else A
    solution: np.ndarray = np.linalg.lstsq(K.T, -c1, rcond=None)[0]
    return solution[: A.shape[0]]


def on_free_face(
    M: NDArray[np.float64], N: NDArray[np.float64], active: NDArray[np.bool_]
) -> NDArray[np.float64]:
    r"""The reduced term ``M = NᵀMN`` kept on the directions the active bounds leave free.

    Args:
        M: The term in the coordinates of ``N`` (r × r, symmetric).
        N: The basis of level 0's free directions (n × r).
        active: Per coordinate, True when its bound on ``Δq`` is active.

    Returns:
        :math:`Y Y^\top M Y Y^\top` with :math:`Y` an orthonormal basis of
        :math:`\{z : E_a N z = 0\}` (``M`` itself when no bound is active).
    """
    if not active.any():
        return M
    _, s, Vt = np.linalg.svd(N[active])
    rank = int(np.sum(s > FACE_RANK_TOL * max(s[0], 1.0))) if s.size else 0
    Y = Vt[rank:].T
    reduced: NDArray[np.float64] = Y @ (Y.T @ M @ Y) @ Y.T
    return reduced
