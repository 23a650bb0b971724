"""The result every redik solver returns: data, not prints or exceptions.

An ordinary failure (a target out of reach, an iteration budget spent, a singular Jacobian)
is a result with ``success=False`` and a ``status``; exceptions are kept for misuse.
"""

from __future__ import annotations

import dataclasses

import numpy as np

STATUSES = (
    "converged",  # the error is within tolerance (and, for a Robot, q is inside the limits)
    "stalled",  # the step ‖Δq‖ fell below q_tol while the error is still above tol
    "max_iterations",  # the iteration budget ran out
    "singular",  # σ_min(J) ≤ singular_tol blocked a Newton step
    "diverged",  # a NaN or inf appeared; q is the last finite iterate
    "unreachable",  # the target lies outside the reachable workspace (as far as can be told)
    "limits",  # converged only outside the joint limits (respect_limits=True rejects it)
)
"""Every ``status`` a solver may report."""


@dataclasses.dataclass
class IKResult:
    """Outcome of an inverse-kinematics solve.

    Attributes:
        q: The final joint vector — always finite.
        success: True when the tolerances (and limits, where asked) are met.
        status: One of :data:`STATUSES`.
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

    q: np.ndarray
    success: bool
    status: str
    iterations: int
    error: float
    position_error: float | None = None
    rotation_error: float | None = None
    history: np.ndarray = dataclasses.field(default_factory=lambda: np.empty((0, 0)))
    error_history: np.ndarray = dataclasses.field(default_factory=lambda: np.empty(0))
    restarts: int = 0
    method: str = ""
    message: str = ""

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"status must be one of {STATUSES}, got {self.status!r}")

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
