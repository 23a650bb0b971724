r"""Every solution of a 6R arm with no closed form, by the elimination that is regular for it.

The Raghavan–Roth elimination (:mod:`.elimination`) is exact on a general arm, but special
geometry can make one of its choices degenerate — ``Q`` rank-deficient, or the pencil
singular for every value of the hidden variable — or keep it regular yet lose roots (three
consecutive parallel axes). :func:`general_solver` therefore tries, in order
(:data:`CHOICES`), the standard split with each of the three left angles hidden, forwards
then on the chain run backwards (for ``T⁻¹``), then the split re-based through the target
link the same way (Manocha & Canny 1994, §3; the re-based loop solves arms special at both
ends, such as the Kinova Jaco), and keeps the first that is regular on :data:`PROBES`
targets and returns the configuration that generated each of them. An arm for which none is
raises :class:`~redik.core.exceptions.ModelError` naming what each choice hit.

Labels are ``"root1"``, ``"root2"``, … by increasing first joint angle; a solution whose
Jacobian is singular (two roots meeting: a double root) carries a ``singular`` text.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from redik.core.exceptions import ModelError
from redik.lie import se3_exp, wrap_angle
from redik.solvers.analytic import _checks
from redik.solvers.analytic.elimination import SPLITS, Elimination
from redik.solvers.analytic.finish import select_rows
from redik.solvers.analytic.geometry import Chain
from redik.solvers.analytic.results import (
    DEFAULT_TOL,
    DUPLICATE_TOL,
    IKSolutions,
    SolutionFamily,
    outside_limits,
    unreachable,
)

#: The eliminations tried, in order: ``(split, reversed, hidden)``.
CHOICES = tuple(
    (split, reverse, hidden)
    for split in SPLITS
    for hidden in (0, 1, 2)
    for reverse in (False, True)
)

#: Targets (FK of seeded random q) whose generating configuration an elimination must
#: return before it is used on an arm.
PROBES = 4

#: ``Q``'s smallest |R_ii| over its largest, and the pencil's smallest pivot at ``x0``, below
#: which an elimination counts as degenerate.
RANK_TOL = 1e-9

#: A solution whose Jacobian's Hadamard ratio is below this is reported as singular.
SINGULAR_TOL = 1e-7

REVOLUTE = np.ones(6, bool)


@dataclass(frozen=True)
class GeneralSolver:
    """Every solution of a 6R arm by its elimination.

    Every solution of a 6R arm by its elimination (make one with
    :func:`redik.solvers.analytic.solver_for`).

    Attributes:
        elimination: The elimination chosen for the arm (:func:`general_solver`).
        lower, upper: The joint limits applied by default.
        kind: ``"general"`` (no closed-form class); ``method``: ``"elimination"``.
    """

    elimination: Elimination
    lower: np.ndarray
    upper: np.ndarray
    kind: str = "general"
    method: str = "elimination"

    def __call__(
        self, target: Any, *, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> IKSolutions:
        """Every solution of a world-frame target pose.

        Every solution of a world-frame target pose, labelled ``"root1"``… (``limits``:
        ``"robot"``, None or ``(lower, upper)``; ``tol`` is checked and unused: every solution
        is exact to the elimination's verification, and it is kept for the common
        signature).
        """
        T = _checks.pose(target, "target", strict=strict)
        _checks.length(tol, "tol", allow_zero=True)
        lower, upper = _checks.resolve_limits(limits, (self.lower, self.upper), 6)
        rows = self._rows(T)
        if not len(rows):
            return unreachable(
                6, "no real root of the degree-16 elimination reaches the target (out of reach)"
            )
        q = np.ascontiguousarray(rows[:, :6])
        keep = select_rows(q, REVOLUTE, lower, upper, False, DUPLICATE_TOL)
        if not keep.any():
            return outside_limits(q, lower, upper, REVOLUTE)
        kept = np.flatnonzero(keep)
        texts = [_singular_text(ratio) for ratio in rows[kept, 6]]
        families: list[SolutionFamily | None] = [None] * len(kept)
        return IKSolutions.from_arrays(
            q[kept],
            [f"root{index + 1}" for index in kept],
            singular=texts,
            families=families,
        )

    def raw(
        self, T: Any, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> np.ndarray:
        """Every solution as a (k, 6) array (those of :meth:`__call__`, without labels)."""
        T = _checks.pose(T, "target", strict=strict)
        _checks.length(tol, "tol", allow_zero=True)
        q = np.ascontiguousarray(self._rows(T)[:, :6])
        if limits is None:
            return q
        lower, upper = _checks.resolve_limits(limits, (self.lower, self.upper), 6)
        return q[select_rows(q, REVOLUTE, lower, upper, False, DUPLICATE_TOL)]

    def _rows(self, T: np.ndarray) -> np.ndarray:
        """The elimination's rows (q, Hadamard ratio) by increasing first joint angle."""
        rows = self.elimination.solve(T)[0]
        return rows[np.argsort(rows[:, 0], kind="stable")]

    @cached_property
    def choice(self) -> str:
        """Which elimination the arm uses, in words."""
        e = self.elimination
        direction = "backwards" if e.reversed else "forwards"
        return f"{e.split} split, {direction}, left angle {e.hidden + 1} hidden"


def _singular_text(ratio: float) -> str:
    """The singularity text of a solution.

    The ``singular`` text of a solution whose Jacobian has this Hadamard ratio ('' above
    :data:`SINGULAR_TOL`): two roots of the elimination meet there (a double root) and the
    arm can move without moving the tool, to first order.
    """
    if ratio >= SINGULAR_TOL:
        return ""
    return (
        f"at a singularity (|det J| / ∏‖J_i‖ = {ratio:.1e}): two of the elimination's roots "
        "meet here"
    )


def _probe_targets(S: np.ndarray, M: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(q, T)`` of :data:`PROBES` seeded random configurations (product of exponentials)."""
    rng = np.random.default_rng(1)
    probes = []
    for _ in range(PROBES):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = M
        for i in reversed(range(6)):
            T = se3_exp(np.concatenate([S[3:, i], S[:3, i]]) * q[i]) @ T
        probes.append((q, T))
    return probes


def _fault(elimination: Elimination, probes: list[tuple[np.ndarray, np.ndarray]]) -> str:
    """Why an elimination cannot be trusted on the arm.

    Why an elimination cannot be trusted on the arm ('' if it can): degenerate on a probe,
    or missing a probe's generating configuration.
    """
    for q, T in probes:
        rows, rank, regular = elimination.solve(T)
        if rank < RANK_TOL:
            return "the target's 14 × 8 matrix Q is rank-deficient"
        if regular < RANK_TOL:
            return "the 12 × 12 pencil is singular"
        if not len(rows) or np.abs(wrap_angle(rows[:, :6] - q)).max(axis=1).min() > 1e-6:
            return "it misses the configuration that generated a probe target"
    return ""


def general_solver(
    S: np.ndarray,
    M: np.ndarray,
    lower: np.ndarray | None = None,
    upper: np.ndarray | None = None,
) -> GeneralSolver:
    """The all-solutions solver of a 6R chain.

    The all-solutions solver of the 6R chain with space screws ``S`` (6 × 6, (ω, v)
    columns) and home pose ``M``: the first regular elimination of :data:`CHOICES`.

    Raises:
        ModelError: A joint is prismatic, or no elimination is regular for this geometry and
            finds every probe's configuration (each choice's reason is named).
    """
    S = _checks.finite_array(S, "S", (6, 6))
    M = _checks.pose(M, "M")
    prismatic = np.flatnonzero(np.linalg.norm(S[:3], axis=0) < 0.5)
    if prismatic.size:
        raise ModelError(
            f"joint(s) {(prismatic + 1).tolist()} are prismatic; the elimination takes "
            "revolute joints only"
        )
    chain = Chain.from_screws(S, M)
    probes = _probe_targets(S, M)
    faults = []
    for split, reverse, hidden in CHOICES:
        elimination = Elimination.build(
            chain.reversed() if reverse else chain, reverse, split, hidden
        )
        fault = _fault(elimination, probes)
        if not fault:
            lower = np.full(6, -np.inf) if lower is None else np.asarray(lower, float).copy()
            upper = np.full(6, np.inf) if upper is None else np.asarray(upper, float).copy()
            return GeneralSolver(elimination, lower, upper)
        faults.append(f"{split}/{'backwards' if reverse else 'forwards'}/{hidden + 1}: {fault}")
    raise ModelError(
        "every Raghavan–Roth elimination is degenerate for this 6R arm (split/direction/hidden "
        f"left angle: {'; '.join(faults)})"
    )
