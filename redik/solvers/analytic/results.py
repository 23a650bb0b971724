r"""Result types shared by the closed-form solvers, and the steps every solver ends with.

Every solver in :mod:`redik.solvers.analytic` returns an :class:`IKSolutions`: a sequence of
:class:`JointSolution` (a joint vector that carries a ``label``), with ``reachable``, a
``status`` in the vocabulary of every redik result (:class:`redik.Status`) and, when empty, a
``reason``. A configuration at a singularity is still returned once, as a
representative, with its ``singular`` text and, where the solutions form a continuum, the
:class:`SolutionFamily` that generates the others. The batch solvers return a
:class:`BatchSolutions` with a fixed label per slot.

Angles are wrapped to (−π, π] (:func:`redik.lie.wrap_angle`); prismatic joints are left as they are.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple, cast, overload

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import Status
from redik.lie import wrap_angle
from redik.solvers.analytic.finish import select_rows

#: Default tolerance (metres) by which a target may lie outside the workspace and still be
#: solved, clipped onto the boundary; also the size of a sine below which a configuration is
#: reported as singular. A solution then reproduces the pose to about this tolerance.
DEFAULT_TOL = 1e-10

#: Two solutions closer than this (radians or metres, per joint, angles modulo 2π) are one.
DUPLICATE_TOL = 1e-9


class JointSolution(np.ndarray):
    """A joint vector (a 1-D numpy array) with the name of its branch.

    Attributes:
        label: Branch name, e.g. ``"left-up-noflip"`` or ``"elbow-down"``.
        singular: Empty for a regular solution, else what is singular about it.
        family: The continuum this representative belongs to, when there is one.

    Arithmetic on a solution returns a plain array: the label describes only the solution.
    """

    label: str = ""
    singular: str = ""
    family: SolutionFamily | None = None

    def __new__(
        cls,
        q: np.ndarray,
        label: str,
        singular: str = "",
        family: SolutionFamily | None = None,
    ) -> JointSolution:
        """A copy of ``q`` (float) carrying the label, singularity text and family."""
        solution = np.array(q, dtype=float).view(cls)
        solution.label = label
        solution.singular = singular
        solution.family = family
        return solution

    def __array_finalize__(self, obj: object) -> None:
        # A view of a plain array keeps the class defaults.
        if isinstance(obj, JointSolution):
            self.label, self.singular, self.family = obj.label, obj.singular, obj.family

    def __array_wrap__(  # type: ignore[override]  # numpy's stub ties the result to Self's shape
        self, array: np.ndarray, context: object = None, return_scalar: bool = False
    ) -> np.ndarray:
        plain = np.asarray(array)
        return plain[()] if return_scalar else plain

    def __reduce__(self) -> tuple:
        # Keep the label through pickling (multiprocessing); a family holds a closure and is
        # not pickled.
        rebuild, args, state = cast(tuple[Any, Any, Any], super().__reduce__())
        return rebuild, args, (state, self.label, self.singular)

    def __setstate__(self, state: tuple) -> None:
        array_state, self.label, self.singular = state
        self.family = None
        super().__setstate__(array_state)

    @property
    def q(self) -> np.ndarray:
        """The joint vector as a plain array."""
        return np.asarray(self)

    def __repr__(self) -> str:
        text = np.array2string(np.asarray(self), precision=6, separator=", ")
        extra = f", singular={self.singular!r}" if self.singular else ""
        return f"JointSolution({text}, label={self.label!r}{extra})"


@dataclass(frozen=True)
class SolutionFamily:
    """A continuum of solutions ``q(t)`` through one representative.

    Attributes:
        free: Indices of the joints whose values may be chosen (one per parameter of ``at``).
        description: What is determined and what is not, e.g. ``"θ4 + θ6 = 0.5236"``.
        invariants: The quantities every member shares, e.g. ``{"theta4+theta6": 0.5236}``.
        generator: ``generator(*t) -> q``; use :meth:`at`.
    """

    free: tuple[int, ...]
    description: str
    generator: Callable[..., np.ndarray] = field(repr=False)
    invariants: dict[str, float] = field(default_factory=dict)

    def at(self, *t: float) -> np.ndarray:
        """The member whose free joints take the values ``t`` (one value per free joint)."""
        if len(t) != len(self.free):
            raise InvalidInput(
                f"this family has {len(self.free)} free parameter(s) (joints {self.free}), "
                f"got {len(t)} value(s)"
            )
        return self.generator(*(float(v) for v in t))


class IKSolutions(Sequence[JointSolution]):
    """Every closed-form solution of one target, as a sequence of :class:`JointSolution`.

    Attributes:
        solutions: The solutions, distinct modulo 2π, in the solver's slot order.
        n_joints: Length of each joint vector (so an empty result still has a shape).
        reachable: Whether the target lies in the workspace (joint limits aside).
        reason: Why there is no solution, when there is none; else empty.
        status: A :class:`redik.Status`: ``CONVERGED`` (solutions), ``UNREACHABLE`` or
            ``LIMITS`` (none, and why); ``success`` is True with a solution.
        preferred: Label of the branch conventionally used by the hardware (e.g. a hexapod's
            ``"knee-up"``), or empty.

    A solver hands over the (k, n) array with the labels (:meth:`from_arrays`); the
    :class:`JointSolution` objects are made on first use of :attr:`solutions` (indexing,
    iteration), so that ``len``, :attr:`labels` and :meth:`as_array` take no Python step per
    solution. The public attributes are read-only.
    """

    __slots__ = (
        "_families",
        "_labels",
        "_n_joints",
        "_preferred",
        "_q",
        "_reachable",
        "_reason",
        "_singular",
        "_solutions",
    )

    def __init__(
        self,
        solutions: Sequence[JointSolution],
        n_joints: int,
        reachable: bool,
        reason: str = "",
        preferred: str = "",
    ) -> None:
        """From :class:`JointSolution` objects (:meth:`from_arrays` is the fast way)."""
        self._q = np.array([np.asarray(s) for s in solutions], dtype=float).reshape(-1, n_joints)
        self._labels = tuple(s.label for s in solutions)
        self._singular = tuple(s.singular for s in solutions)
        self._families = tuple(s.family for s in solutions)
        self._n_joints, self._reachable = n_joints, reachable
        self._reason, self._preferred = reason, preferred
        self._solutions: tuple[JointSolution, ...] | None = tuple(solutions)

    @classmethod
    def from_arrays(
        cls,
        q: np.ndarray,
        labels: Sequence[str],
        *,
        singular: Sequence[str] | None = None,
        families: Sequence[SolutionFamily | None] | None = None,
        reachable: bool = True,
        reason: str = "",
        preferred: str = "",
    ) -> IKSolutions:
        """The result holding a (k, n) array of solutions.

        The result holding ``q`` (k, n; kept, not copied) with a label per row, and where
        given a singularity text and family per row.
        """
        result = cls.__new__(cls)
        result._q, result._labels = q, tuple(labels)
        k = len(result._labels)
        result._singular = ("",) * k if singular is None else tuple(singular)
        result._families = (None,) * k if families is None else tuple(families)
        result._n_joints, result._reachable = q.shape[1], reachable
        result._reason, result._preferred = reason, preferred
        result._solutions = None
        return result

    @property
    def n_joints(self) -> int:
        """Length of each joint vector."""
        return self._n_joints

    @property
    def reachable(self) -> bool:
        """Whether the target lies in the workspace (joint limits aside)."""
        return self._reachable

    @property
    def reason(self) -> str:
        """Why there is no solution, when there is none."""
        return self._reason

    @property
    def preferred(self) -> str:
        """The label of the hardware's conventional branch, or empty."""
        return self._preferred

    def __reduce__(self) -> tuple:
        # A family holds a closure and is not pickled (as for JointSolution).
        return _rebuild, (
            self._q,
            self._labels,
            self._singular,
            self.reachable,
            self.reason,
            self.preferred,
        )

    @property
    def solutions(self) -> tuple[JointSolution, ...]:
        """The solutions as :class:`JointSolution` rows (made once, on first use)."""
        if self._solutions is None:
            block = self._q.view(JointSolution)
            made = []
            for index in range(len(self._labels)):
                solution = block[index]
                solution.label = self._labels[index]
                solution.singular = self._singular[index]
                solution.family = self._families[index]
                made.append(solution)
            self._solutions = tuple(made)
        return self._solutions

    @overload
    def __getitem__(self, index: int) -> JointSolution: ...
    @overload
    def __getitem__(self, index: slice) -> tuple[JointSolution, ...]: ...
    def __getitem__(self, index: int | slice) -> JointSolution | tuple[JointSolution, ...]:
        return self.solutions[index]

    def __len__(self) -> int:
        return len(self._labels)

    def __iter__(self) -> Iterator[JointSolution]:
        return iter(self.solutions)

    def __repr__(self) -> str:
        extra = "" if self.reachable else f", reachable=False, reason={self.reason!r}"
        if self.reachable and self.reason:
            extra = f", reason={self.reason!r}"
        return f"IKSolutions({len(self)} solution(s), labels={list(self._labels)}{extra})"

    @property
    def labels(self) -> tuple[str, ...]:
        """The label of each solution."""
        return self._labels

    @property
    def success(self) -> bool:
        """Whether there is at least one solution (within the limits, when given)."""
        return len(self) > 0

    @property
    def status(self) -> Status:
        """Whether and why the target has solutions.

        :class:`~redik.core.result.Status` ``CONVERGED`` with a solution, else
        ``UNREACHABLE`` (the target is outside the workspace) or ``LIMITS`` (solutions exist,
        none within the joint limits); :attr:`reason` says why in words.
        """
        if len(self):
            return Status.CONVERGED
        return Status.LIMITS if self.reachable else Status.UNREACHABLE

    @property
    def singular(self) -> bool:
        """Whether any returned solution is at a singularity."""
        return any(self._singular)

    @property
    def families(self) -> tuple[SolutionFamily, ...]:
        """The continua of solutions, one per singular representative that has one."""
        return tuple(family for family in self._families if family is not None)

    def as_array(self) -> np.ndarray:
        """The solutions stacked as a (k, n) array (k = 0 when there is none); a copy."""
        return self._q.copy()

    def by_label(self, label: str) -> JointSolution:
        """The solution with this label; raises :class:`InvalidInput` naming the labels."""
        if label not in self._labels:
            raise InvalidInput(
                f"no solution labelled {label!r}; the labels are {list(self._labels)}"
            )
        return self.solutions[self._labels.index(label)]

    def nearest(self, q_ref: np.ndarray, revolute: np.ndarray | None = None) -> JointSolution:
        """The solution closest to a configuration.

        The solution closest to ``q_ref`` (angles compared modulo 2π, all joints if
        ``revolute`` is None): the branch to follow along a trajectory.
        """
        if not len(self):
            raise InvalidInput(f"there is no solution to choose from: {self.reason}")
        q_ref = np.asarray(q_ref, dtype=float)
        if q_ref.shape != (self.n_joints,):
            raise InvalidInput(f"q_ref must have shape ({self.n_joints},), got {q_ref.shape}")
        mask = np.ones(self.n_joints, bool) if revolute is None else np.asarray(revolute, bool)
        difference = self._q - q_ref
        difference[:, mask] = wrap_angle(difference[:, mask])
        return self.solutions[int(np.argmin(np.linalg.norm(difference, axis=1)))]


def _rebuild(
    q: np.ndarray,
    labels: tuple[str, ...],
    singular: tuple[str, ...],
    reachable: bool,
    reason: str,
    preferred: str,
) -> IKSolutions:
    """Unpickle an :class:`IKSolutions` (without its families)."""
    return IKSolutions.from_arrays(
        q, labels, singular=singular, reachable=reachable, reason=reason, preferred=preferred
    )


@dataclass(frozen=True)
class BatchSolutions:
    """Closed-form solutions of B targets at once, slot by slot.

    Attributes:
        q: (B, S, n) joint vectors; a slot that is not ``valid`` holds NaN.
        valid: (B, S) whether the slot holds a solution (reachable and within the limits).
        singular: (B, S) whether that solution is at (within the tolerance of) a singularity;
            two valid slots of one target may then hold the same configuration.
        labels: The S slot labels, the same for every target.
    """

    q: np.ndarray
    valid: np.ndarray
    singular: np.ndarray
    labels: tuple[str, ...]

    def __len__(self) -> int:
        return self.q.shape[0]

    @property
    def n_solutions(self) -> np.ndarray:
        """(B,) number of valid slots per target (duplicates at singularities included)."""
        return self.valid.sum(axis=1)


def limit_representatives(
    q: np.ndarray, lower: np.ndarray, upper: np.ndarray, revolute: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Move each revolute angle by a multiple of 2π into ``[lower, upper]`` when one exists.

    Returns ``(q_shifted, inside)`` for ``q`` of shape (..., n): the shift is the smallest that
    brings the angle into range (none if it is already in range), and ``inside`` (..., n) says
    which joints are then in range. A value outside by less than :data:`DUPLICATE_TOL` is
    clipped onto the limit.
    """
    two_pi = 2.0 * np.pi
    # The turns k with lower ≤ q + 2πk ≤ upper run from ceil((lower − q)/2π) to
    # floor((upper − q)/2π); the one nearest 0 is the smallest shift (0 when q is in range, as
    # an infinite limit gives ∓inf). When the range is empty no shift puts q inside.
    turns = np.minimum(
        np.maximum(np.ceil((lower - q) / two_pi), 0.0), np.floor((upper - q) / two_pi)
    )
    shifted = q + np.where(revolute, two_pi * turns, 0.0)
    clipped = np.minimum(np.maximum(shifted, lower), upper)
    return clipped, np.abs(clipped - shifted) <= DUPLICATE_TOL


class Candidate(NamedTuple):
    """A solution before :func:`finalize`.

    A solution before :func:`finalize`: its joint values and what the solver knows of it
    (the fields of a :class:`JointSolution`, without building the array subclass).
    """

    q: Sequence[float] | np.ndarray
    label: str
    singular: str = ""
    family: SolutionFamily | None = None


def finalize(
    candidates: Sequence[Candidate | JointSolution],
    n_joints: int,
    revolute: np.ndarray,
    limits: tuple[np.ndarray, np.ndarray] | None,
    preferred: str = "",
) -> IKSolutions:
    """The small solvers' selection: wrap, drop duplicates, filter by limits.

    Wrap angles, drop duplicates (modulo 2π, the first of equals is kept) and filter by
    joint limits, by the one selection rule of :func:`redik.solvers.analytic.finish.select_rows`.

    The candidates come from a reachable target; if the limits exclude all of them the result
    is empty with a reason naming the joints that are out of range. Regular solutions differ
    by construction (in the sign of a non-zero square root, or by π in an angle), so only when
    a candidate is singular are the candidates compared for duplicates.
    """
    q = np.array([c.q for c in candidates], dtype=float).reshape(-1, n_joints)
    singular = [c.singular for c in candidates]
    if limits is None:
        lower, upper = np.full(n_joints, -np.inf), np.full(n_joints, np.inf)
    else:
        lower, upper = limits
    work = q.copy()  # q stays as it is for the explanation of an empty result below
    keep = select_rows(work, np.asarray(revolute, bool), lower, upper, any(singular), DUPLICATE_TOL)
    kept = np.flatnonzero(keep)
    reason = ""
    if limits is not None and not len(kept) and len(q):
        reason = _outside_reason(q, revolute, limits, any(singular))
    return _kept(work, kept, candidates, singular, reason, preferred)


def _outside_reason(
    q: np.ndarray, revolute: np.ndarray, limits: tuple[np.ndarray, np.ndarray], dedupe: bool
) -> str:
    """Why no candidate is kept.

    Why no candidate is kept: how many distinct solutions, and which joints are out of
    range in some of them.
    """
    wrapped = np.where(revolute, wrap_angle(q), q)
    distinct = np.ones(len(q), bool)
    if dedupe:
        difference = wrapped[:, None, :] - wrapped[None, :, :]
        difference[..., revolute] = wrap_angle(difference[..., revolute])
        same = np.all(np.abs(difference) < DUPLICATE_TOL, axis=-1)
        distinct = ~np.any(np.tril(same, k=-1), axis=1)
    return outside_limits(wrapped[distinct], limits[0], limits[1], revolute).reason


def _kept(
    q: np.ndarray,
    kept: np.ndarray,
    candidates: Sequence[Candidate | JointSolution],
    singular: list[str],
    reason: str,
    preferred: str,
) -> IKSolutions:
    """The result of :func:`finalize`: rows ``kept`` of ``q`` with their candidates' fields."""
    rows = kept.tolist()
    texts = [singular[index] for index in rows]
    return IKSolutions.from_arrays(
        q[kept],
        [candidates[index].label for index in rows],
        singular=texts,
        families=[candidates[index].family for index in rows] if any(texts) else None,
        reason=reason,
        preferred=preferred,
    )


def outside_limits(
    q: np.ndarray, lower: np.ndarray, upper: np.ndarray, revolute: np.ndarray
) -> IKSolutions:
    """The empty result when every solution ``q`` (k, n) lies outside the joint limits.

    Its reason counts the solutions and names the joints out of range in some of them (after
    :func:`limit_representatives`' turns by 2π).
    """
    _, inside = limit_representatives(q, lower, upper, revolute)
    outside = np.flatnonzero(~inside.all(axis=0)).tolist()
    reason = (
        f"none of the {len(q)} solutions lies within the joint limits "
        f"(joints out of range in some solution: {outside})"
    )
    return IKSolutions.from_arrays(np.empty((0, q.shape[-1])), (), reason=reason)


def unreachable(n_joints: int, reason: str) -> IKSolutions:
    """The empty result for a target outside the workspace."""
    return IKSolutions.from_arrays(np.empty((0, n_joints)), (), reachable=False, reason=reason)
