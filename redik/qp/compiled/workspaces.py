"""DAQP called directly on the QPs of a compiled step that have rows, one workspace per shape.

A QP whose rows bind (collision rows on level 0, the reduced rows of level 1) goes to DAQP
(Arnström, Bemporad & Axehill, *A dual active-set solver for embedded quadratic
programming using recursive LDLᵀ updates*, IEEE TAC 2022) through its own ``daqp.Model``:
set up once per (level, number of rows) and then updated in place (``Model.update``), the
first ``n`` bounds DAQP's simple bounds and the rest the rows — no QP record, no
concatenation of fresh arrays, no ``qpsolvers``. Collision rows come and go, so their count
changes between steps; keeping a workspace per count makes a set-up happen once per count.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import BackendError, InfeasibleProblem
from redik.qp.backends import Backend
from redik.qp.problem_data import QP


class DaqpWorkspaces:
    """DAQP models kept per shape, updated in place.

    Args:
        settings: DAQP settings (``primal_tol``…), applied to every model.
    """

    def __init__(self, settings: dict[str, Any]) -> None:
        import daqp

        self._daqp = daqp
        self._settings = dict(settings)
        self._models: dict[tuple[int, int], Any] = {}  # daqp.Model (daqp ships no types)

    def solve(
        self,
        key: tuple[int, int],
        H: NDArray[np.float64],
        c: NDArray[np.float64],
        upper: NDArray[np.float64],
        lower: NDArray[np.float64],
        A: NDArray[np.float64],
    ) -> NDArray[np.float64] | None:
        """The minimiser of ``½xᵀHx + cᵀx`` s.t. ``lower ≤ (x_{:k}; A x) ≤ upper``.

        Args:
            key: The workspace's shape key, ``(level, rows)``.
            H: The Hessian (n × n), positive definite.
            c: The linear term (n,).
            upper: Upper bounds: the ``k = len(upper) − len(A)`` simple bounds, then the rows.
            lower: Lower bounds, likewise.
            A: The rows (C-contiguous).

        Returns:
            ``x``, or None when DAQP fails or reports the QP infeasible (the workspace is then
            dropped: the caller's general path decides and raises).
        """
        model = self._models.get(key)
        if model is None:
            model = self._daqp.Model()
            exitflag, _ = model.setup(H, c, A, upper, lower, np.zeros(len(upper), dtype=np.int32))
            if exitflag < 0:
                return None
            model.settings = {**model.settings, **self._settings}
            self._models[key] = model
        else:
            exitflag = model.update(
                H=H, f=c, A=A if A.shape[0] else None, bupper=upper, blower=lower
            )
            if exitflag < 0:
                del self._models[key]
                return None
        try:
            x, _, exitflag, _ = model.solve()
        except (RuntimeError, IndexError):  # a state the checks above did not catch
            exitflag = -1
        if exitflag < 1:
            del self._models[key]
            return None
        solution: NDArray[np.float64] = x
        return solution

    def reset(self) -> None:
        """Forget every workspace (and its warm start)."""
        self._models.clear()


class BackendSolves:
    """The same calls as :class:`DaqpWorkspaces`, answered by a problem's own back-ends.

    A plan whose back-end is not DAQP (quadprog) hands the QPs with rows to that back-end, in
    the form :mod:`redik.qp.hierarchy` gives it, so that its steps stay the general path's.

    Args:
        backends: The problem's back-ends, one per level.
    """

    def __init__(self, backends: Sequence[Backend]):
        self._backends = list(backends)

    def solve(
        self,
        key: tuple[int, int],
        H: NDArray[np.float64],
        c: NDArray[np.float64],
        upper: NDArray[np.float64],
        lower: NDArray[np.float64],
        A: NDArray[np.float64],
    ) -> NDArray[np.float64] | None:
        """:meth:`DaqpWorkspaces.solve` by the back-end of level ``key[0]``; None when it fails."""
        k = len(upper) - A.shape[0]
        qp = QP(H, c)
        if k:
            qp.lb, qp.ub = lower[:k], upper[:k]
        if A.shape[0]:
            qp.C, qp.l, qp.u = A, lower[k:], upper[k:]
        try:
            return self._backends[key[0]].solve(qp)[: len(c)]
        except (BackendError, InfeasibleProblem):
            return None

    def reset(self) -> None:
        """Nothing to forget: the back-ends are the problem's, reset by it."""
