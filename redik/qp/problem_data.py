r"""The quadratic program handed to a back-end.

.. math::

    \min_x \; \tfrac12 x^\top H x + c^\top x
    \quad\text{s.t.}\quad
    l_b \le x \le u_b, \qquad l \le C x \le u, \qquad A x = b

Bounds and two-sided rows are the compact form of :math:`G x \le h` (one row per finite
side); back-ends that take only :math:`G x \le h` get :meth:`QP.one_sided`. Infinite
entries of ``lb``/``ub``/``l``/``u`` mean "no bound".
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput


@dataclasses.dataclass
class QP:
    """One convex QP. ``H`` must be symmetric positive semi-definite (definite for daqp).

    The bounds ``lb ≤ x ≤ ub``, the rows ``l ≤ C x ≤ u`` and the equalities ``A x = b`` are
    each given whole or not at all.

    Raises:
        InvalidInput: A part of the bounds, rows or equalities is given without the rest.
    """

    H: NDArray[np.float64]
    c: NDArray[np.float64]
    lb: NDArray[np.float64] | None = None
    ub: NDArray[np.float64] | None = None
    C: NDArray[np.float64] | None = None
    l: NDArray[np.float64] | None = None
    u: NDArray[np.float64] | None = None
    A: NDArray[np.float64] | None = None
    b: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        for names, parts in (
            ("lb, ub", (self.lb, self.ub)),
            ("C, l, u", (self.C, self.l, self.u)),
            ("A, b", (self.A, self.b)),
        ):
            given = [part is not None for part in parts]
            if any(given) and not all(given):
                raise InvalidInput(f"a QP's {names} are given together or not at all")

    @property
    def n(self) -> int:
        """Number of variables."""
        return int(self.c.shape[0])

    @property
    def n_rows(self) -> int:
        """Number of two-sided inequality rows of ``C``."""
        return 0 if self.C is None else self.C.shape[0]

    @property
    def n_eq(self) -> int:
        """Number of equality rows."""
        return 0 if self.A is None else self.A.shape[0]

    def size(self) -> str:
        """``"n=7 variables, 7 bounds, 0 inequality rows, 0 equalities"`` for messages."""
        bounds = 0 if self.lb is None else self.n
        return (
            f"n={self.n} variables, {bounds} bounds, {self.n_rows} inequality rows, "
            f"{self.n_eq} equalities"
        )

    def one_sided(
        self, bounds: bool = False
    ) -> tuple[NDArray[np.float64] | None, NDArray[np.float64] | None]:
        """``(G, h)``: the rows (and bounds) as one-sided rows ``G x ≤ h``.

        ``(G, h)`` of the rows ``l ≤ C x ≤ u`` (and of the bounds, if ``bounds``) as ``G x ≤ h``,
        finite sides only.
        """
        blocks: list[NDArray[np.float64]] = []
        sides: list[NDArray[np.float64]] = []
        if bounds and self.lb is not None and self.ub is not None:
            eye = np.eye(self.n)
            blocks += [eye, -eye]
            sides += [self.ub, -self.lb]
        if self.C is not None and self.l is not None and self.u is not None:
            blocks += [self.C, -self.C]
            sides += [self.u, -self.l]
        if not blocks:
            return None, None
        G, h = np.vstack(blocks), np.concatenate(sides)
        finite = np.isfinite(h)
        if not np.any(finite):
            return None, None
        return G[finite], h[finite]

    def max_violation(self, x: NDArray[np.float64]) -> float:
        """Largest violation of any constraint at ``x`` (0 when feasible)."""
        violation = 0.0
        if self.lb is not None and self.ub is not None:
            violation = max(violation, float(np.max(self.lb - x, initial=0.0)))
            violation = max(violation, float(np.max(x - self.ub, initial=0.0)))
        if self.C is not None and self.l is not None and self.u is not None:
            Cx = self.C @ x
            violation = max(violation, float(np.max(self.l - Cx, initial=0.0)))
            violation = max(violation, float(np.max(Cx - self.u, initial=0.0)))
        if self.A is not None and self.b is not None:
            violation = max(violation, float(np.max(np.abs(self.A @ x - self.b), initial=0.0)))
        return violation
