r"""The closed-form solver of a 6-joint arm: one class of :mod:`.geometry`, one compiled call.

:class:`SixJointSolver` binds the class kernel (:mod:`.kernels`) to an arm's packed geometry
and joint limits. A call validates the target once, runs the class's compiled entry (kernel,
FK verification and polish, limits and duplicates, label codes: :mod:`.finish`) and maps the
label codes to words (:mod:`.labels`); only a singular solution takes Python of its own (its
text and the :class:`~redik.solvers.analytic.results.SolutionFamily` of its free joint).
:meth:`SixJointSolver.raw` returns the solutions as a plain (k, 6) array and
:meth:`SixJointSolver.batch` solves a stack of targets on every core.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numba
import numpy as np

from redik.solvers.analytic import _checks
from redik.solvers.analytic.finish import (
    DUPLICATE,
    FIX_JOINT,
    FIX_VALUE,
    FREE,
    GEOMETRY_SIZE,
    KEEP_ALL,
    LABEL,
    LABELLED,
    LOWER,
    PLAN_SIZE,
    REVERSE,
    SINGULAR_CODE,
    SLOT,
    STAGE,
    STATUS,
    TOL,
    UPPER,
    VERIFY,
)
from redik.solvers.analytic.kernels.slots import EMPTY, SINGULAR, STAGES
from redik.solvers.analytic.labels import VOCABULARIES
from redik.solvers.analytic.results import (
    DEFAULT_TOL,
    DUPLICATE_TOL,
    BatchSolutions,
    IKSolutions,
    SolutionFamily,
    outside_limits,
    unreachable,
)

#: A solution's FK must match the target to this (m, and rotation-matrix entries).
VERIFY_TOL = 1e-9

#: The module of each class's entries (``solve_<class>``, ``batch_<class>``).
_MODULES = {
    "spherical_two_intersecting": "spherical",
    "spherical_two_parallel": "spherical",
    "spherical": "spherical",
    "spherical_two_intersecting_prismatic": "spherical",
    "three_parallel_two_intersecting": "parallel",
    "three_parallel": "parallel",
}

_WRIST = "wrist singular: the first and last wrist axes are aligned"

#: Why a joint is arbitrary, by the chain's joint index, per class.
_FREE_REASONS = {
    "spherical_two_intersecting": {
        0: "the wrist centre lies on the first axis",
        1: "the wrist centre lies on the second axis",
        3: _WRIST,
    },
    "spherical_two_parallel": {
        0: "the wrist centre lies on the first axis",
        1: "the wrist centre lies on the second axis",
        3: _WRIST,
    },
    "spherical": {3: _WRIST},
    "spherical_two_intersecting_prismatic": {
        0: "the wrist centre lies on the first axis",
        1: "the wrist centre lies on the second axis",
        3: _WRIST,
    },
    "three_parallel_two_intersecting": {
        0: "the wrist point lies on the first axis",
        1: "the point after the three parallel axes lies on the second axis",
        5: "wrist singular: the last axis is parallel to the three parallel axes",
    },
    "three_parallel": {
        1: "the point after the three parallel axes lies on the second axis",
        5: "wrist singular: the last axis is parallel to the three parallel axes",
    },
}


_REFUSED = np.empty((0, 0))

#: The argument types of an entry: a C-contiguous float64 matrix and a plan.
_SIGNATURE = (numba.float64[:, ::1], numba.float64[::1])


def entry(kind: str, name: str = "solve") -> Any:
    """The compiled entry ``<name>_<kind>`` of a class, imported and compiled on first use.

    ``solve`` entries are compiled for :data:`_SIGNATURE` alone: any other argument raises
    ``TypeError`` at the call instead of compiling another specialisation, and the solver
    converts it after its checks.
    """
    module = importlib.import_module(f"redik.solvers.analytic.kernels.{_MODULES[kind]}")
    dispatcher = getattr(module, f"{name}_{kind}")
    if name == "solve" and not dispatcher.signatures:
        dispatcher.compile(_SIGNATURE)
        dispatcher.disable_compile()
    return dispatcher


@dataclass(frozen=True)
class SixJointSolver:
    """The closed form of a 6-joint arm (make one with :func:`redik.solvers.analytic.solver_for`).

    Attributes:
        kind: The class (:data:`redik.solvers.analytic.geometry.KINDS`).
        reversed: Whether the chain is solved backwards (a spherical shoulder).
        geometry: The packed (19, 3) geometry of the chain as solved.
        lower, upper: The joint limits applied by default.
    """

    kind: str
    reversed: bool
    geometry: np.ndarray
    lower: np.ndarray
    upper: np.ndarray

    @property
    def method(self) -> str:
        """``"closed_form"``: every solution by the class's subproblems."""
        return "closed_form"

    @property
    def labels(self) -> tuple[str, ...]:
        """The names of the label codes (:mod:`.labels`)."""
        return VOCABULARIES[self.kind]

    def raw(
        self, T: Any, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> np.ndarray:
        """Every solution as a (k, 6) array.

        Every solution as a (k, 6) array: verified by FK, wrapped to (−π, π] (or moved by
        2π into the limits), within ``limits`` (``"robot"``, None or ``(lower, upper)``),
        duplicates dropped. No labels or families. ``strict`` refuses a near-rotation instead
        of projecting it (:mod:`~redik.core.rotation_policy`).
        """
        return self._solve(T, self._plan_for(limits, tol, False), strict)[1]

    def __call__(
        self, target: Any, *, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> IKSolutions:
        """Every solution of a world-frame target pose, labelled.

        Every solution of a world-frame target pose, labelled, with families at
        singularities (see :meth:`raw` for the arguments).
        """
        plan = self._plan_for(limits, tol)
        T, out = self._solve(target, plan, strict)
        if not len(out):
            return self._nothing(T, plan)
        try:
            names = list(map(self._names.__getitem__, out[:, LABEL].tolist()))
        except KeyError:  # a singular row (its code carries SINGULAR)
            return self._singular_result(T, out)
        return IKSolutions.from_arrays(out[:, :6], names)

    def batch(
        self, T: Any, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> BatchSolutions:
        """Every solution of a (B, 4, 4) stack of targets, threaded over the targets.

        Returns:
            ``q`` (B, S, 6) indexed by label code (S = ``len(self.labels)``), a (B, S)
            ``valid`` mask and a (B, S) ``singular`` mask; at a singularity two branches may
            give one configuration, which then fills one of their codes.
        """
        T = np.ascontiguousarray(_checks.poses(T, "T", strict=strict))
        plan = self._plan_for(limits, tol)
        count = len(self.labels)
        q = np.full((len(T), count, 6), np.nan)
        valid = np.zeros((len(T), count), bool)
        singular = np.zeros((len(T), count), bool)
        entry(self.kind, "batch")(T, plan, q, valid, singular)
        return BatchSolutions(q, valid, singular, self.labels)

    def _solve(self, target: Any, plan: np.ndarray, strict: bool) -> tuple[np.ndarray, np.ndarray]:
        """The compiled entry's rows for a target.

        ``(T, rows)`` of the compiled entry, the target checked only when the entry cannot
        take it as it is (then a near-rotation is projected, or the error names what is
        wrong).
        """
        try:
            out = self._entry(target, plan)
        except (TypeError, ValueError):  # not a C-contiguous float64 array (no other is
            # compiled; numba cannot even type an empty list: ValueError)
            out = _REFUSED
        if out.shape[1]:
            return target, out
        T = np.ascontiguousarray(_checks.pose(target, "target", strict=strict))
        return T, self._entry(T, plan)

    @cached_property
    def _entry(self) -> Any:
        return entry(self.kind)

    @cached_property
    def _names(self) -> dict[float, str]:
        """Label code (as the float the entry returns) → name."""
        return {float(code): name for code, name in enumerate(self.labels)}

    def _plan_for(self, limits: Any, tol: Any, labels: bool = True) -> np.ndarray:
        """The plan of these limits and tolerance.

        The plan of these limits and tolerance, with or without labels: the common calls
        take two identity tests to a plan made once; anything else is checked.
        """
        if tol is DEFAULT_TOL:
            if limits is None:
                return self._unbounded_plan if labels else self._raw_unbounded_plan
            if limits.__class__ is str and limits == "robot":
                return self._robot_plan if labels else self._raw_robot_plan
        bounds = _checks.resolve_limits(limits, (self.lower, self.upper), 6)
        return self._plan(bounds, _checks.length(tol, "tol", allow_zero=True), labels)

    def _plan(
        self, limits: tuple[np.ndarray, np.ndarray], tol: float, labels: bool = True
    ) -> np.ndarray:
        """The ``plan`` array of :mod:`.finish`."""
        plan = np.zeros(PLAN_SIZE)
        plan[:GEOMETRY_SIZE] = self.geometry.ravel()
        plan[LOWER : LOWER + 6], plan[UPPER : UPPER + 6] = limits
        plan[REVERSE], plan[TOL] = float(self.reversed), tol
        plan[VERIFY], plan[DUPLICATE] = VERIFY_TOL, DUPLICATE_TOL
        plan[FIX_JOINT], plan[LABELLED] = -1.0, float(labels)
        return plan

    def _every_slot(self, T: np.ndarray, fix_joint: int = -1, value: float = 0.0) -> np.ndarray:
        """Every slot of the entry, unfiltered.

        Every slot of the entry, unfiltered and in slot order, without limits; joint
        ``fix_joint`` (a family's free joint) held at ``value``.
        """
        plan = self._unbounded_plan.copy()
        plan[FIX_JOINT], plan[FIX_VALUE], plan[KEEP_ALL] = fix_joint, value, 1.0
        return self._entry(T, plan)

    @cached_property
    def _robot_plan(self) -> np.ndarray:
        return self._plan((self.lower, self.upper), DEFAULT_TOL)

    @cached_property
    def _unbounded_plan(self) -> np.ndarray:
        return self._plan((np.full(6, -np.inf), np.full(6, np.inf)), DEFAULT_TOL)

    @cached_property
    def _raw_robot_plan(self) -> np.ndarray:
        return self._plan((self.lower, self.upper), DEFAULT_TOL, False)

    @cached_property
    def _raw_unbounded_plan(self) -> np.ndarray:
        return self._plan((np.full(6, -np.inf), np.full(6, np.inf)), DEFAULT_TOL, False)

    def _singular_result(self, T: np.ndarray, out: np.ndarray) -> IKSolutions:
        """The labelled result when a row is singular: its text and family."""
        names, texts, families = [], [], []
        for row in out:
            names.append(self.labels[int(row[LABEL]) % SINGULAR_CODE])
            text, family = self._singular(T, row)
            texts.append(text)
            families.append(family)
        return IKSolutions.from_arrays(out[:, :6], names, singular=texts, families=families)

    def _singular(self, T: np.ndarray, row: np.ndarray) -> tuple[str, SolutionFamily | None]:
        """The ``singular`` text and family of one row ('' and None for a regular one)."""
        if int(row[STATUS]) != SINGULAR:
            return "", None
        free, slot = int(row[FREE]), int(row[SLOT])
        if free < 0:
            return "at the edge of a subproblem's reach: two branches coincide", None
        chain_joint = 5 - free if self.reversed else free
        reason = _FREE_REASONS[self.kind].get(chain_joint, "a subproblem is degenerate")
        text = f"θ{free + 1} is arbitrary ({reason})"

        def member(t: float) -> np.ndarray:
            return self._every_slot(T, free, t)[slot, :6].copy()

        return text, SolutionFamily((free,), text, member)

    def _nothing(self, T: np.ndarray, plan: np.ndarray) -> IKSolutions:
        """The empty result and why.

        The empty result: unreachable (the stage that failed), or every solution outside
        the limits of ``plan`` (the joints out of range named).
        """
        every = self._every_slot(T)
        solved = every[every[:, STATUS] != EMPTY]
        if not len(solved):
            worst = int(every[:, STAGE].max(initial=0))
            return unreachable(6, f"no branch reaches the target: {STAGES.get(worst, '')}")
        revolute = self.geometry[17:19].ravel() == 0.0
        if self.reversed:
            revolute = revolute[::-1]
        q = solved[:, :6]
        return outside_limits(q, plan[LOWER : LOWER + 6], plan[UPPER : UPPER + 6], revolute)
