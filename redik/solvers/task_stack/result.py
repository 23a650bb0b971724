"""What :func:`~redik.solvers.task_stack.solve_problem` returns: :class:`QPResult`."""

from __future__ import annotations

import dataclasses

from redik.core.result import IKResult


@dataclasses.dataclass
class QPResult(IKResult):
    """An :class:`~redik.core.result.IKResult` of a task stack, with its lower levels' optimality.

    ``error``, ``position_error`` and ``rotation_error`` are level 0's (the cost-weighted
    error of its targets, the worst frame errors); ``success`` means level 0 is met
    (``converged`` or ``suboptimal``).

    Attributes:
        stationarity: Per optimised level (the levels below level 0's targets, in priority
            order), the norm of its projected gradient at ``q``
            (:meth:`redik.Problem.stationarity`); empty when there is none or when
            ``stationarity_tol`` is None.
        stationary: True when every value is within ``stationarity_tol``: ``q`` is a
            (first-order) optimum of the lower levels subject to the higher ones and the
            limits, not merely a point where level 0 is met.
        start: Where the returned attempt started: ``"q0"``, ``"chains"`` (the per-chain warm
            start from the previous attempt's end), ``"random+chains"`` or ``"random"``.
    """

    stationarity: list[float] = dataclasses.field(default_factory=list)
    stationary: bool = True
    start: str = "q0"
