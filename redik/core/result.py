"""The result every redik solver returns, and the one vocabulary of its ``status``.

An ordinary failure (a target out of reach, an iteration budget spent, a singular Jacobian)
is a result with ``success=False`` and a :class:`Status`; exceptions are kept for misuse.
"""

from __future__ import annotations

import dataclasses
from enum import Enum

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput


class Status(str, Enum):
    """How a solve ended: the ``status`` of every redik result.

    A ``str``-valued enum: a member equals its value (``result.status == "converged"``),
    formats as it (``f"{status}"`` is ``"converged"``), hashes as it (a dict keyed by the
    strings finds it) and is written as it by ``json``. Results built from a plain string
    store the member (``IKResult(status="stalled", …).status is Status.STALLED``).

    Which solver produces which member:

    ==================  ========================================================================
    ``CONVERGED``       Every solver, on success: the tolerances are met (for a robot, inside
                        the joint limits when they are respected); for the root finders of
                        :mod:`redik.solvers.iterative` with no error test (``tol`` None or 0),
                        ``q_tol`` or ``rel_tol`` fired. For a closed-form solver
                        (:class:`~redik.solvers.analytic.IKSolutions`): at least one solution.
                        For :func:`~redik.solvers.redundancy.explore_self_motion`: every
                        component found was sampled to its end. For
                        :func:`redik.solve_problem`: level 0's targets are met and every lower
                        level is stationary within ``stationarity_tol``.
    ``SUBOPTIMAL``      :func:`redik.solve_problem` only, a success: level 0's targets are met
                        but a lower level is not stationary within ``stationarity_tol`` (the
                        budget ran out, or no step lowers it further); ``q`` is a solution of
                        level 0, not the constrained optimum of the levels below.
    ``STALLED``         The iteration stopped making progress above the tolerance: the step
                        fell below ``q_tol``, the relative change below ``rel_tol`` (with
                        ``tol`` unmet), or no Armijo step decreased the error (root finders of
                        :mod:`redik.solvers.iterative`); neither the descent nor its escape
                        lowered the error in any attempt (:func:`redik.solve_problem`); an
                        attempt's damped step made no progress (:func:`redik.solve_batch`).
                        ``q`` is then (near) a stationary point of the error, not a root.
    ``MAX_ITERATIONS``  The iteration (or sample) budget ran out: every iterative solver;
                        :func:`redik.solve_pose` when no attempt converged and no better
                        explanation applies; :func:`redik.explore_self_motion` when
                        ``max_samples`` ran out (the manifold may be incomplete).
    ``SINGULAR``        ``σ_min(J) ≤ singular_tol`` (or ``|det J| ≤ singular_tol``) blocked a
                        Newton step (root finders of :mod:`redik.solvers.iterative`, when
                        ``singular_tol`` is given).
    ``DIVERGED``        A NaN or inf (or a blow-up past ``max_growth``) appeared; ``q`` is the
                        last finite iterate (root finders; :func:`redik.solve_pose` when every
                        attempt diverged; :func:`redik.solve_batch`).
    ``UNREACHABLE``     The target lies outside the reachable workspace as far as can be told:
                        beyond the chain's reach, or every attempt stopped at the same error
                        with a vanishing gradient (:func:`redik.solve_pose`,
                        :func:`redik.solve_problem`; beyond the chain's reach for
                        :func:`redik.solve_batch`, per target); no start reached
                        the pose (:func:`redik.explore_self_motion`); no closed-form solution
                        exists (:class:`~redik.solvers.analytic.IKSolutions`).
    ``LIMITS``          The target is reached only outside the joint limits: solutions exist,
                        none inside (:func:`redik.explore_self_motion`,
                        :class:`~redik.solvers.analytic.IKSolutions`); as far as can be told
                        for :func:`redik.solve_pose` with ``respect_limits``: it failed within
                        the limits and one solve without them converged outside them (the
                        message names the joints at and beyond their limits).
    ``INVALID``         The target is not a finite rigid transform and was not solved
                        (:func:`redik.solve_batch`, per target; a single-target solver raises
                        :class:`~redik.core.exceptions.InvalidPose` instead).
    ==================  ========================================================================
    """

    CONVERGED = "converged"
    SUBOPTIMAL = "suboptimal"
    STALLED = "stalled"
    MAX_ITERATIONS = "max_iterations"
    SINGULAR = "singular"
    DIVERGED = "diverged"
    UNREACHABLE = "unreachable"
    LIMITS = "limits"
    INVALID = "invalid"

    def __str__(self) -> str:
        return self.value

    def __format__(self, spec: str) -> str:
        return format(self.value, spec)

    @classmethod
    def coerce(cls, status: object, name: str = "status") -> Status:
        """Convert a member or its string to the member.

        Args:
            status: A :class:`Status` or its value.
            name: The argument's name, for the message.

        Returns:
            The member.

        Raises:
            InvalidInput: ``status`` is neither (the message names the valid values).
        """
        if isinstance(status, cls):
            return status
        try:
            return cls(status)
        except ValueError:
            raise InvalidInput(
                f"{name} must be one of {[member.value for member in cls]}, got {status!r}"
            ) from None


@dataclasses.dataclass
class IKResult:
    """Outcome of an inverse-kinematics solve.

    Attributes:
        q: The final joint vector — always finite.
        success: True when the tolerances (and limits, where asked) are met.
        status: How the solve ended, a :class:`Status` (a plain string given here is
            converted; an unknown one raises :class:`InvalidInput`).
        iterations: Iterations performed (summed over restarts).
        error: Final residual norm ``‖e‖`` the solver drove to zero (for a pose target the
            norm of the body error twist ``log(T⁻¹ T_d)``).
        position_error: ``‖p_d − p‖`` in metres for pose/position targets, else None.
        rotation_error: Angle of ``Rᵀ R_d`` in radians for pose/orientation targets, else None.
        history: ``(k + 1) × n`` iterates of the successful (or last) attempt,
            ``history[0] = q0`` and ``history[k]`` is q after iteration k.
        error_history: ``‖e‖`` at each row of ``history``.
        restarts: How many restarts were used before this result.
        method: The method that produced it.
        message: A human-readable note (e.g. why the target is unreachable).
    """

    q: NDArray[np.float64]
    success: bool
    status: Status
    iterations: int
    error: float
    position_error: float | None = None
    rotation_error: float | None = None
    history: NDArray[np.float64] = dataclasses.field(default_factory=lambda: np.empty((0, 0)))
    error_history: NDArray[np.float64] = dataclasses.field(default_factory=lambda: np.empty(0))
    restarts: int = 0
    method: str = ""
    message: str = ""

    def __post_init__(self) -> None:
        if type(self.status) is not Status:  # a string given: the member (a hot path else)
            self.status = Status.coerce(self.status)

    def summary(self) -> str:
        """One line: status, iterations and errors."""
        parts = [f"{self.method or 'ik'}: {self.status}", f"{self.iterations} it"]
        if self.position_error is not None:
            parts.append(f"pos {self.position_error:.2e} m")
        if self.rotation_error is not None:
            parts.append(f"rot {self.rotation_error:.2e} rad")
        if self.position_error is None and self.rotation_error is None:
            parts.append(f"|e| {self.error:.2e}")
        return ", ".join(parts)
