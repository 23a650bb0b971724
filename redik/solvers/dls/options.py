"""The settings of damped least squares, validated once and packed for the compiled kernel."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.rotation_policy import ROTATION_TOLERANCE
from redik.core.validate import fraction, integer

# Indices into the float and integer settings arrays (few arguments keep the call cheap).
(POS_TOL, ROT_TOL, DAMPING, MIN_DAMPING, MAX_DAMPING, REQUIRED, REACH, TARGET_TOL,
 POLISH_ERROR, POLISH_DAMPING) = range(10)  # fmt: skip
MAX_ITERATIONS, RESTARTS, PATIENCE, BOUNDED, CANDIDATES, POLISH_ITERATIONS = range(6)


@dataclasses.dataclass(frozen=True)
class DLSOptions:
    """Settings of damped least squares (:mod:`redik.solvers.dls`).

    Attributes:
        pos_tol: Position tolerance (m).
        rot_tol: Rotation tolerance (rad).
        max_iterations: Iterations per attempt before a target is re-seeded.
        restarts: Random re-seeds per target after its first attempt.
        damping: ``μ`` at the start of each attempt (``λ = μ‖e‖² + λ_min``).
        min_damping: ``λ_min``, which keeps the system regular at ``e → 0``.
        max_damping: The ``λ`` past which an attempt has stalled.
        patience: Iterations over which an attempt must make ``progress``.
        progress: An attempt whose ``‖e‖²`` fell by less than this fraction (in (0, 1)) over
            the last ``patience`` iterations has stalled.
        candidates: Each restart starts from the nearest in pose of this many random
            configurations (1: a uniform random start), or around the best ``q`` found
            (:func:`redik.solvers.dls.kernel._restart_seed`).
        polish_iterations: Gauss–Newton steps of the polish stage that follows an attempt
            which ended short of the tolerances (0: no polish).
        polish_error: The polish runs when the attempt ended with ``‖e‖`` below this.
        polish_damping: ``λ`` of the polish steps, which only keeps their system regular.

    The defaults are those that solve the random reachable targets of ``redik bench batch``
    (panda, iiwa14, ur5e) in the fewest iterations at full success: a small initial ``μ``
    trusts the Gauss–Newton step from the start, and a start near the target in pose
    converges more often than a uniform one.

    Raises:
        InvalidInput: A tolerance or damping that is not a positive number, a count below its
            minimum, or ``progress`` outside (0, 1).
    """

    pos_tol: float = 1e-6
    rot_tol: float = 1e-5
    max_iterations: int = 60
    restarts: int = 200
    damping: float = 0.1
    min_damping: float = 1e-9
    max_damping: float = 1e6
    patience: int = 8
    progress: float = 0.5
    candidates: int = 16
    polish_iterations: int = 30
    polish_error: float = 1e-3
    polish_damping: float = 1e-12

    def __post_init__(self) -> None:
        fraction(self.progress, "progress")  # 1 would ask ‖e‖² to reach 0
        for name in (
            "pos_tol",
            "rot_tol",
            "damping",
            "min_damping",
            "max_damping",
            "polish_error",
            "polish_damping",
        ):
            value = getattr(self, name)
            if isinstance(value, bool) or not (
                isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0
            ):
                raise InvalidInput(f"{name} must be a positive number, got {value!r}")
        integers = (
            ("max_iterations", 1), ("restarts", 0), ("patience", 1), ("candidates", 1),
            ("polish_iterations", 0),
        )  # fmt: skip
        for name, minimum in integers:
            integer(getattr(self, name), name, minimum)

    @property
    def history_length(self) -> int:
        """The most iterates one attempt records: its start, its iterations and its polish."""
        return 1 + self.max_iterations + self.polish_iterations

    def kernel_settings(self, bounded: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """The float and integer settings arrays of the compiled kernel.

        The reach excess ``REACH`` is 0 (:func:`redik.solvers.dls.kernel.solve_one` sets it
        per target in a copy); a target is valid within
        :data:`~redik.core.rotation_policy.ROTATION_TOLERANCE`, as
        :func:`~redik.core.rotation_policy.as_pose` checks one pose.

        Args:
            bounded: Keep every iterate inside the joint limits.

        Returns:
            ``(floats, counts)``, indexed by this module's constants.
        """
        settings = np.empty(10)
        settings[POS_TOL] = self.pos_tol
        settings[ROT_TOL] = self.rot_tol
        settings[DAMPING] = self.damping
        settings[MIN_DAMPING] = self.min_damping
        settings[MAX_DAMPING] = self.max_damping
        settings[REQUIRED] = math.sqrt(1.0 - self.progress)
        settings[REACH] = 0.0
        settings[TARGET_TOL] = ROTATION_TOLERANCE
        settings[POLISH_ERROR] = self.polish_error
        settings[POLISH_DAMPING] = self.polish_damping
        counts = np.empty(6, dtype=np.int64)
        counts[CANDIDATES] = self.candidates
        counts[MAX_ITERATIONS] = self.max_iterations
        counts[RESTARTS] = self.restarts
        counts[PATIENCE] = self.patience
        counts[BOUNDED] = int(bounded)
        counts[POLISH_ITERATIONS] = self.polish_iterations
        return settings, counts
