r"""The residual an iterative method runs on, and the record of one run: :class:`Iterates`.

A method is a short loop (:mod:`~redik.solvers.iterative.newton`,
:mod:`~redik.solvers.iterative.transpose`, :mod:`~redik.solvers.iterative.hybrid`) over a
:class:`Residual` — a user's task function (:mod:`~redik.solvers.iterative.equations`) or
the pose error of a robot's frame (:mod:`~redik.solvers.iterative.pose_residual`). What
every loop shares lives in :class:`Iterates`: the current point and the history, the step
(constant or Armijo), and the stopping rules of :mod:`~redik.solvers.iterative.rules`.
"""

from __future__ import annotations

import math
from typing import Any, Generic, Protocol, TypeVar

import numpy as np

from redik.core.result import Status
from redik.solvers.iterative.rules import Step, StoppingRules
from redik.solvers.iterative.steps import armijo_backtrack


class Point(Protocol):
    """What a residual evaluated at ``q``: the loops read ``q``, ``e`` and ``‖e‖``."""

    q: np.ndarray
    e: np.ndarray
    norm: float


P = TypeVar("P", bound=Point)
"""The point type of one residual (its own fields beside ``q``, ``e`` and ``‖e‖``)."""


class Residual(Protocol[P]):
    r"""A residual ``e(q)`` and its Jacobian, as the iterative methods use them.

    ``e(q) = x_d − f(q)`` and ``J = ∂f/∂q``, so that the Newton step ``J⁺e`` and the transpose
    step ``Jᵀe`` decrease ``‖e‖`` (Lynch & Park §6.2).
    """

    def start(self, q: np.ndarray) -> P:
        """The point at the start ``q``; raises when ``q`` cannot be a start."""

    def evaluate(self, q: np.ndarray) -> P | None:
        """The point at ``q``, or None when ``e(q)`` is not finite."""

    def jacobian(self, point: P) -> np.ndarray | None:
        """``J`` (``r × n``) at the point, or None when it is not finite."""

    def errors(self, point: P) -> tuple[float, float]:
        """The position and orientation parts ``(e_p, e_R)`` tested by a pair ``tol``."""

    def project(self, q: np.ndarray) -> np.ndarray:
        """``q`` brought into the feasible set (the joint limits), or ``q`` itself."""

    def task_value(self, point: P) -> np.ndarray:
        """``f(q)`` at the point, for the relative-change rule."""


class Iterates(Generic[P]):
    """The state and record of one run of an iterative method on a residual.

    ``history[0]`` is the start and ``history[k]`` the iterate after step ``k``;
    ``errors[k] = ‖e(history[k])‖``. :attr:`status` is None while the run goes on, then the
    :class:`~redik.core.result.Status` of the rule that stopped it, with :attr:`message`.

    A run is a context: inside it floating-point overflow is not warned about, because it
    shows as a non-finite value that the rules turn into a rejected trial or ``"diverged"``.

    Args:
        residual: The residual.
        q0: The start.
        rules: The stopping rules.
        gain: The gain ``K`` of the merit ``F = ½ eᵀKe`` (its symmetric part is used), or
            None for ``F = ½‖e‖²``.
    """

    def __init__(
        self,
        residual: Residual[P],
        q0: np.ndarray,
        rules: StoppingRules,
        gain: np.ndarray | None = None,
    ) -> None:
        self.residual = residual
        self.rules = rules
        self.weight = None if gain is None else 0.5 * (gain + gain.T)
        self.point = residual.start(q0)
        self.history = [self.point.q.copy()]
        self.errors = [self.point.norm]
        self.status: Status | None = None
        self.message = ""
        self._q_bound = rules.max_growth * max(1.0, float(np.max(np.abs(self.point.q))))
        self._e_bound = rules.max_growth * max(1.0, self.point.norm)

    @property
    def final_status(self) -> Status:
        """The status of the finished run (every loop stops with one)."""
        if self.status is None:
            raise RuntimeError("the run is still going: it has no final status")
        return self.status

    def __enter__(self) -> Iterates[P]:
        self._errstate = np.errstate(over="ignore", invalid="ignore")
        self._errstate.__enter__()
        return self

    def __exit__(self, *exc_info: Any) -> None:
        self._errstate.__exit__(*exc_info)

    @property
    def q(self) -> np.ndarray:
        """The current iterate."""
        return self.point.q

    @property
    def e(self) -> np.ndarray:
        """The residual at the current iterate."""
        return self.point.e

    @property
    def norm(self) -> float:
        """``‖e‖`` at the current iterate."""
        return self.point.norm

    @property
    def iterations(self) -> int:
        """Steps taken."""
        return len(self.history) - 1

    def running(self) -> bool:
        """Whether the run goes on; stops it on the error test or the budget."""
        if self.status is not None:
            return False
        if self.rules.stops_early and self._error_test():
            self.stop(Status.CONVERGED)
        elif self.iterations >= self.rules.max_iterations:
            met = self.rules.tol is not None and self._error_test()
            self.stop(Status.CONVERGED if met else Status.MAX_ITERATIONS)
        return self.status is None

    def jacobian(self) -> np.ndarray | None:
        """``J`` at the current iterate; None, the run stopped as diverged, if not finite."""
        J = self.residual.jacobian(self.point)
        if J is None:
            self.stop(Status.DIVERGED, "the Jacobian holds NaN or inf")
        return J

    def singular(self, J: np.ndarray) -> bool:
        """The singularity test at ``J`` (stops the run as singular when it holds)."""
        bound = self.rules.singular_tol
        if bound is None:
            return False
        if self.rules.singular_test == "det":
            name, value = "|det J|", abs(float(np.linalg.det(J)))
        else:
            name = "σ_min(J)"
            value = float(np.linalg.svd(J, compute_uv=False)[-1]) if J.size else 0.0
        if value > bound:
            return False
        self.stop(Status.SINGULAR, f"{name} = {value:.3g} ≤ singular_tol = {bound:g}")
        return True

    def advance(
        self,
        d: np.ndarray,
        J: np.ndarray,
        step: Step,
        first_trial: float = 1.0,
        descent_only: bool = False,
    ) -> bool:
        r"""Take the step ``q ← q + λ d`` and apply the rules that follow a step.

        Args:
            d: The direction.
            J: The Jacobian at the current iterate (for the slope ``∇Fᵀd = −eᵀWJd``).
            step: ``λ``, or ``"armijo"``: backtracking from ``first_trial`` on the merit
                ``F = ½ eᵀWe`` (``W`` the symmetric part of the gain).
            first_trial: The first ``λ`` of an Armijo search.
            descent_only: Take the step only if it lowers ``F``; otherwise leave the run
                as it was and return False (a fallback follows).

        Returns:
            Whether the step was taken (the run may have stopped even so).
        """
        if step == "armijo":
            point = self._line_search(d, J, first_trial, descent_only)
        else:
            point, reason = self._trial(self.q + step * d)
            if descent_only and (point is None or not self._merit(point) < self._merit(self.point)):
                return False
            if point is None:
                self.stop(Status.DIVERGED, reason)
        if point is None:
            return False
        previous = self.point
        self.point = point
        self.history.append(point.q.copy())
        self.errors.append(point.norm)
        self._after_step(previous)
        return True

    def stop(self, status: Status, message: str = "") -> None:
        """End the run with ``status``."""
        self.status, self.message = status, message

    # ----------------------------------------------------------------------------------

    def _error_test(self) -> bool:
        tol = self.rules.tol
        if tol is None:  # no error test asked
            return False
        if isinstance(tol, tuple):
            position, orientation = self.residual.errors(self.point)
            return position <= tol[0] and orientation <= tol[1]
        return self.norm <= tol

    def _merit(self, point: P) -> float:
        """``F = ½ eᵀWe`` (inf where it overflows: such a trial is never accepted)."""
        if self.weight is None:
            return 0.5 * point.norm * point.norm
        return 0.5 * float(point.e @ (self.weight @ point.e))

    def _trial(self, q: np.ndarray) -> tuple[P | None, str]:
        """The point at ``q`` (projected), or None and why it cannot be used.

        ``q`` is tested against the growth bound before the residual sees it.
        """
        q = self.residual.project(q)
        largest = float(np.abs(q).max())
        if not math.isfinite(largest):
            return None, "the step produced NaN or inf"
        if largest > self._q_bound:
            return None, (
                f"the step blew up (‖q‖_∞ = {largest:.3g}; max_growth = "
                f"{self.rules.max_growth:g} × the start)"
            )
        point = self.residual.evaluate(q)
        if point is None:
            return None, "the step produced NaN or inf"
        if point.norm > self._e_bound:
            return None, (
                f"the step blew up (‖e‖ = {point.norm:.3g}; max_growth = "
                f"{self.rules.max_growth:g} × the start)"
            )
        return point, ""

    def _line_search(
        self, d: np.ndarray, J: np.ndarray, first_trial: float, descent_only: bool
    ) -> P | None:
        """The point Armijo's rule accepts along ``d``, or None.

        On None the run has stopped, unless ``descent_only``.
        """
        e, Jd = self.e, J @ d
        slope = -float(e @ (Jd if self.weight is None else self.weight @ Jd))  # ∇Fᵀd
        if not slope < 0.0:
            if not descent_only:
                status = Status.STALLED if math.isfinite(slope) else Status.DIVERGED
                self.stop(status, f"the direction does not decrease the merit (slope {slope:.3g})")
            return None
        accepted: list[P | None] = [None]

        def merit_at(alpha: float) -> float:
            accepted[0] = self._trial(self.q + alpha * d)[0]
            return math.inf if accepted[0] is None else self._merit(accepted[0])

        alpha, outcome = armijo_backtrack(
            merit_at, self._merit(self.point), slope, first_trial, trials=self.rules.armijo_trials,
            min_alpha=self._smallest_step(d),
        )  # fmt: skip
        if alpha is not None or descent_only:
            return accepted[0] if alpha is not None else None
        if outcome == "too_small":
            self._stop_by_rule(f"‖q_k+1 − q_k‖ < q_tol = {self.rules.q_tol:g}")
        else:
            self.stop(Status.STALLED, f"no Armijo step decreases ‖e‖ = {self.norm:.3g}")
        return None

    def _smallest_step(self, d: np.ndarray) -> float:
        """The ``λ`` below which ``‖λ d‖`` is under ``q_tol``: the increment rule's bound."""
        q_tol = self.rules.q_tol
        if q_tol is None:
            return 0.0
        norm = float(np.linalg.norm(d))
        return math.inf if norm <= q_tol else q_tol / norm

    def _after_step(self, previous: P) -> None:
        """The relative-change and increment rules, after a step from ``previous``."""
        rules = self.rules
        if rules.rel_tol is not None:
            x, x_previous = self.residual.task_value(self.point), self.residual.task_value(previous)
            change = float(np.linalg.norm(x - x_previous))
            if change <= rules.rel_tol * float(np.linalg.norm(x_previous)):
                self._stop_by_rule(
                    f"relative change ‖f(q_k+1) − f(q_k)‖ = {change:.3g} ≤ rel_tol ‖f(q_k)‖"
                )
                return
        if rules.q_tol is not None:
            increment = float(np.linalg.norm(self.q - previous.q))
            if increment < rules.q_tol:
                self._stop_by_rule(f"‖q_k+1 − q_k‖ = {increment:.3g} < q_tol = {rules.q_tol:g}")

    def _stop_by_rule(self, message: str) -> None:
        """Stop on the relative change or the increment.

        Converged if the error test holds or none was asked (``tol`` None or 0), else stalled.
        """
        if not self.rules.stops_early or self._error_test():
            self.stop(Status.CONVERGED, message)
        else:
            self.stop(Status.STALLED, f"{message}, with ‖e‖ = {self.norm:.3g} above tol")
