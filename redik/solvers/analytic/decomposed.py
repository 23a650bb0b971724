r"""Closed-form IK of any 6R arm with a solvable geometry, by subproblem decomposition.

The arm is read from its screw axes at q = 0 (``robot.jacobian(0, reference="space")``, or
the screws given to :meth:`redik.Robot.from_screws`): ``T(q) = e^{[S_1]q_1} ⋯ e^{[S_6]q_6}
M`` (Modern Robotics §4.1). :func:`classify` finds which axes intersect or are parallel and
picks a decomposition into the Paden–Kahan subproblems of :mod:`.subproblems` (Murray, Li &
Sastry 1994, §3.3; Elias & Wen 2022, "IK-Geo", arXiv 2211.05737, §IV, whose classes these
are):

``spherical_two_intersecting``
    axes 4, 5, 6 meet (spherical wrist) and axes 1, 2 meet (PUMA, Stanford-type shoulders):
    SP3 (elbow), SP2 (shoulder), SP2 + SP1 (wrist). Up to 8 solutions.
``spherical_two_parallel``
    spherical wrist and axes 2 ∥ 3 (elbow arms): SP4, SP3, SP1, then the wrist.
``three_parallel_two_intersecting``
    axes 2 ∥ 3 ∥ 4 and axes 5, 6 meet (Universal Robots): SP4, SP4, SP1, SP1, SP3, SP1.
``spherical``
    spherical wrist, any axes 1–3: a 1-D search on θ1 (every sign change of two continuous
    residuals, refined by bisection, and every local minimum of their magnitude that
    touches zero — a double root, where two arm solutions merge at a singularity — refined
    by golden section), then SP3, SP1 and the wrist.

``spherical_two_intersecting_prismatic``
    axes 1, 2 meeting, joint 3 prismatic, spherical wrist (the Stanford arm, RRPRRR): the
    slide's line meets a sphere about the shoulder point (the prismatic counterpart of SP3:
    d3 ±), SP2 (shoulder ±), the wrist. Up to 8 solutions (4 with d3 ≥ 0).

Arms outside these classes are refused with :class:`~redik.core.exceptions.ModelError`; a
general 6R (no three axes meeting or parallel) has :mod:`redik.solvers.analytic.general`
(an elimination to a degree-16 polynomial, Raghavan & Roth 1993). Each revolute class is
also recognised with the chain run backwards (a spherical *shoulder*, axes
1–3 meeting, solved as the reversed arm's wrist for ``T⁻¹``). The wrist may be any three
axes through one point with consecutive axes not parallel: ZYZ, ZYX, ZXZ and skew ones.

Every solution is checked by forward kinematics of the screw chain before it is returned
(a branch that misses the target by more than :data:`VERIFY_TOL` is dropped). Labels say which
root each subproblem took: ``"s+e-w+"`` is the ``+`` root of the shoulder subproblem (SP2's
``+γ`` or SP4's ``φ + arccos``), the ``−`` root of the elbow SP3 and the ``+`` root of the
wrist (θ5's subproblem); for the searched class ``"arm2-w-"`` is the second arm solution by
increasing θ1, wrist root ``−``. These are branch names, not the left/right words of a
particular arm: compare the PUMA and UR solvers' physical labels.

The compiled path (:meth:`DecomposedSolver.raw`) returns the solutions as a (k, 6) array
with no Python per branch; :meth:`DecomposedSolver.__call__` returns the labelled
:class:`~redik.solvers.analytic.IKSolutions`, with a
:class:`~redik.solvers.analytic.SolutionFamily` when a
subproblem leaves a joint arbitrary (a singularity).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from redik.core.exceptions import InvalidInput, ModelError
from redik.lie import se3_exp
from redik.solvers.analytic import _checks
from redik.solvers.analytic import _decomposed_kernels as kernels
from redik.solvers.analytic._solution import (
    DEFAULT_TOL,
    DUPLICATE_TOL,
    Candidate,
    IKSolutions,
    SolutionFamily,
    finalize,
    unreachable,
)

if TYPE_CHECKING:
    from redik.kinematics.robot import Robot

#: Geometry classes, in the order :func:`classify` tries them (index = kernel id).
KINDS = (
    "spherical_two_intersecting",
    "spherical_two_parallel",
    "spherical",
    "three_parallel_two_intersecting",
    "spherical_two_intersecting_prismatic",
)

#: How close (m; rad for directions) axes must be to intersecting or parallel to count as such.
#: The kernels solve the ideal geometry, so this is what the solutions' FK error may reach.
GEOMETRY_TOL = 1e-10

#: A solution's FK must match the target to this (m, and rotation-matrix entries).
VERIFY_TOL = 1e-9

#: How closely ``robot.fk`` must match the screw chain read from the Jacobian (m).
MATCH_TOL = 1e-9

REVOLUTE = np.ones(6, bool)

_BRANCH_LABELS = tuple(f"s{s}e{e}w{w}" for s in "+-" for e in "+-" for w in "+-")
_SEARCH_LABELS = tuple(f"arm{i + 1}-w{w}" for i in range(8) for w in "+-")
_SLIDE_LABELS = tuple(f"s{s}d{d}w{w}" for s in "+-" for d in "+-" for w in "+-")


@dataclass(frozen=True)
class Chain:
    """A 6R chain as axes and points at q = 0 (world frame): ``h`` (6, 3) unit axes, ``a``
    (6, 3) a point on each, and the home pose ``M`` of the end-effector."""

    h: np.ndarray
    a: np.ndarray
    M: np.ndarray
    prismatic: np.ndarray = field(default_factory=lambda: np.zeros(6, bool))

    @classmethod
    def from_screws(cls, S: np.ndarray, M: np.ndarray) -> Chain:
        """From space screws ``S`` (6 × 6, columns (ω, v), Modern Robotics order): the axis is
        ω and its point nearest the origin is ω × v (v = −ω × a); a prismatic joint
        (ω = 0) slides along v, and its point is the origin (any point would do)."""
        S = np.asarray(S, dtype=float)
        prismatic = np.linalg.norm(S[:3], axis=0) < 0.5
        h = np.where(prismatic[:, None], S[3:].T, S[:3].T)
        a = np.where(prismatic[:, None], 0.0, np.cross(h, S[3:].T))
        return cls(h, a, np.asarray(M, dtype=float), prismatic)

    def reversed(self) -> Chain:
        r"""The chain run backwards: :math:`T^{-1} = M^{-1} e^{-[S_6]q_6} ⋯ e^{-[S_1]q_1}
        = e^{[S'_1]q_6} ⋯ e^{[S'_6]q_1} M^{-1}` with :math:`S'_k = -\mathrm{Ad}_{M^{-1}}
        S_{7-k}`: axes ``−R_Mᵀ h`` through the points ``R_Mᵀ (a − p_M)``, reversed."""
        R, p = self.M[:3, :3], self.M[:3, 3]
        M_inverse = np.eye(4)
        M_inverse[:3, :3], M_inverse[:3, 3] = R.T, -R.T @ p
        return Chain(
            -(self.h @ R)[::-1].copy(),
            ((self.a - p) @ R)[::-1].copy(),
            M_inverse,
            self.prismatic[::-1].copy(),
        )


def _parallel(chain: Chain, i: int, j: int) -> bool:
    return bool(np.linalg.norm(np.cross(chain.h[i], chain.h[j])) <= GEOMETRY_TOL)


def _meeting_point(chain: Chain, i: int, j: int) -> np.ndarray | None:
    """Where axes i and j intersect (None if they do not, or are parallel)."""
    normal = np.cross(chain.h[i], chain.h[j])
    sine = np.linalg.norm(normal)
    if sine <= GEOMETRY_TOL:
        return None
    gap = chain.a[j] - chain.a[i]
    if abs(gap @ normal) / sine > GEOMETRY_TOL * (1.0 + np.linalg.norm(gap)):
        return None
    # a_i + s h_i = a_j + t h_j, least squares in (s, t).
    (s, _), *_ = np.linalg.lstsq(np.stack([chain.h[i], -chain.h[j]], axis=1), gap, rcond=None)
    return chain.a[i] + s * chain.h[i]


def _common_point(chain: Chain, i: int, j: int, k: int) -> np.ndarray | None:
    first, second = _meeting_point(chain, i, j), _meeting_point(chain, j, k)
    if first is None or second is None:
        return None
    if np.linalg.norm(first - second) > GEOMETRY_TOL * (1.0 + np.linalg.norm(first)):
        return None
    return first


def _on_axis(chain: Chain, axis: int, point: np.ndarray) -> bool:
    offset = point - chain.a[axis]
    return bool(np.linalg.norm(offset - chain.h[axis] * (offset @ chain.h[axis])) <= GEOMETRY_TOL)


def _perpendicular(axis: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to ``axis``."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    unit = np.cross(axis, helper)
    return unit / np.linalg.norm(unit)


def _pack(chain: Chain, points: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """The (19, 3) geometry array of :mod:`._decomposed_kernels`."""
    flags = chain.prismatic.astype(float).reshape(2, 3)
    return np.vstack(
        [chain.h, points, chain.M[:3, 3], chain.M[:3, :3], _perpendicular(reference), flags]
    ).copy()


def _classify_chain(chain: Chain) -> tuple[int, np.ndarray] | None:
    """The kernel and packed geometry for a chain run forwards, or None."""
    points = chain.a.copy()
    if chain.prismatic.any():
        return _classify_prismatic(chain)
    wrist_ok = not (_parallel(chain, 3, 4) or _parallel(chain, 4, 5))
    centre = _common_point(chain, 3, 4, 5) if wrist_ok else None
    if centre is not None and not _on_axis(chain, 2, centre):
        points[3:6] = centre
        shoulder = _meeting_point(chain, 0, 1)
        if shoulder is not None and not _on_axis(chain, 2, shoulder):
            points[0:2] = shoulder
            return kernels.SPHERICAL_TWO_INTERSECTING, _pack(chain, points, chain.h[5])
        if _parallel(chain, 1, 2) and not _parallel(chain, 0, 1):
            return kernels.SPHERICAL_TWO_PARALLEL, _pack(chain, points, chain.h[5])
        if not _parallel(chain, 1, 2):
            return kernels.SPHERICAL, _pack(chain, points, chain.h[5])
    elbows_parallel = _parallel(chain, 1, 2) and _parallel(chain, 2, 3)
    if elbows_parallel and not (_parallel(chain, 0, 1) or _parallel(chain, 4, 1)):
        wrist = _meeting_point(chain, 4, 5)
        distinct = all(not _on_axis(chain, i, chain.a[j]) for i, j in ((1, 2), (2, 3)))
        if wrist is not None and distinct:
            points[4:6] = wrist
            return kernels.THREE_PARALLEL_TWO_INTERSECTING, _pack(chain, points, chain.h[1])
    return None


def _classify_prismatic(chain: Chain) -> tuple[int, np.ndarray] | None:
    """The Stanford-type class (axes 1, 2 meeting, joint 3 sliding, spherical wrist), or None."""
    if not np.array_equal(chain.prismatic, [False, False, True, False, False, False]):
        return None
    if _parallel(chain, 3, 4) or _parallel(chain, 4, 5) or _parallel(chain, 0, 1):
        return None
    centre = _common_point(chain, 3, 4, 5)
    shoulder = _meeting_point(chain, 0, 1)
    if centre is None or shoulder is None:
        return None
    points = chain.a.copy()
    points[0:2], points[2], points[3:6] = shoulder, shoulder, centre
    return kernels.SPHERICAL_TWO_INTERSECTING_PRISMATIC, _pack(chain, points, chain.h[5])


def classify(S: np.ndarray, M: np.ndarray) -> tuple[str, bool, np.ndarray] | None:
    """``(kind, reversed, packed geometry)`` of the 6R chain ``(S, M)``, or None when no class
    of the module docstring fits (forwards first, then backwards)."""
    chain = Chain.from_screws(S, M)
    for reverse, candidate in ((False, chain), (True, chain.reversed())):
        found = _classify_chain(candidate)
        if found is not None:
            return KINDS[found[0]], reverse, found[1]
    return None


#: Why a joint is arbitrary, by kernel joint index (the chain's order), per class.
_FREE_REASONS = {
    "spherical_two_intersecting": {
        0: "the wrist centre lies on the first axis",
        1: "the wrist centre lies on the second axis",
        3: "wrist singular: the first and last wrist axes are aligned",
    },
    "spherical_two_parallel": {
        0: "the wrist centre lies on the first axis",
        1: "the wrist centre lies on the second axis",
        3: "wrist singular: the first and last wrist axes are aligned",
    },
    "spherical": {3: "wrist singular: the first and last wrist axes are aligned"},
    "spherical_two_intersecting_prismatic": {
        0: "the wrist centre lies on the first axis",
        1: "the wrist centre lies on the second axis",
        3: "wrist singular: the first and last wrist axes are aligned",
    },
    "three_parallel_two_intersecting": {
        0: "the wrist point lies on the first axis",
        1: "the point after the three parallel axes lies on the second axis",
        5: "wrist singular: the last axis is parallel to the three parallel axes",
    },
}

_STAGES = {
    1: "the shoulder subproblem (θ1 / wrist-centre position) has no solution",
    2: "the elbow subproblem (distance to the wrist point) has no solution",
    3: "the wrist subproblem (orientation) has no solution",
    4: "a branch's forward kinematics missed the target",
}


@dataclass(frozen=True)
class DecomposedSolver:
    """A subproblem-decomposition solver bound to a 6R chain (make one with
    :func:`decomposed_solver` or :func:`redik.solvers.analytic.solver_for`).

    Attributes:
        kind: The geometry class (a key of :data:`KINDS`).
        reversed: Whether the chain is solved backwards (a spherical shoulder).
        geometry: The packed (17, 3) geometry of the (possibly reversed) chain.
        lower, upper: The joint limits applied by default.
        family: ``"decomposed"``, beside :class:`~redik.solvers.analytic.AnalyticSolver`'s families.
    """

    kind: str
    reversed: bool
    geometry: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    family: str = "decomposed"

    @property
    def labels(self) -> tuple[str, ...]:
        """Slot labels (module docstring)."""
        if self.kind == "spherical":
            return _SEARCH_LABELS
        return _SLIDE_LABELS if self.kind.endswith("prismatic") else _BRANCH_LABELS

    def raw(
        self, T: np.ndarray, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> np.ndarray:
        """Every solution as a (k, 6) array, compiled end to end: verified by FK, wrapped to
        (−π, π] (or moved by 2π into the limits), within ``limits`` (``"robot"``, None or
        ``(lower, upper)``), duplicates dropped, in slot order. No labels or families.
        ``strict`` refuses a near-rotation instead of projecting it
        (:mod:`~redik.core.rotation_policy`)."""
        if strict:
            T = np.ascontiguousarray(_checks.pose(T, "target", strict=True))
        plan = self._plan_for(limits, tol)
        try:
            q = kernels.solve_raw(T, plan)
        except (TypeError, ValueError):  # not a C-contiguous float64 array: a list (numba
            # cannot even type an empty one: ValueError), integers, a view, …
            q = _NOTHING
        if q.shape[1] == 0:
            # Raises the error that names what is wrong, or projects a near-rotation (with
            # redik.lie's warning) that is then solved.
            T = _checks.pose(T, "target", strict=strict)
            q = kernels.solve_raw(np.ascontiguousarray(T), plan)
        return q

    def __call__(
        self, target: Any, *, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> IKSolutions:
        """Every solution of a world-frame target pose, labelled, with families at
        singularities (see :meth:`raw` for the arguments).

        The same compiled call as :meth:`raw` (:func:`._decomposed_kernels.solve_labelled`
        also returns each solution's slot); the labels are picked by slot and the Python per
        solution is left to singular slots (their text and family) and to
        :class:`~redik.solvers.analytic.IKSolutions`' lazy rows."""
        T = target
        if strict:
            T = np.ascontiguousarray(_checks.pose(T, "target", strict=True))
        plan = self._plan_for(limits, tol)
        try:
            q, slots, flags = kernels.solve_labelled(T, plan)
        except (TypeError, ValueError):  # not a C-contiguous float64 array (as in raw):
            flags = _NO_FLAGS  # checked and converted below
        if not flags.shape[1]:
            T = np.ascontiguousarray(_checks.pose(T, "target", strict=strict))
            q, slots, flags = kernels.solve_labelled(T, plan)
        if not len(slots):
            return self._nothing(T, plan, flags[0], flags[2])
        labels = self.labels
        kept = slots.tolist()  # Python ints: cheaper to index with than numpy scalars
        names = [labels[slot] for slot in kept]
        codes = flags[0].tolist()
        if kernels.SINGULAR not in codes:
            return IKSolutions.from_arrays(q, names)
        texts, families = [], []
        for slot in kept:
            text, family = self._singular(T, codes[slot], int(flags[1, slot]), slot)
            texts.append(text)
            families.append(family)
        return IKSolutions.from_arrays(q, names, singular=texts, families=families)

    def _nothing(
        self, T: np.ndarray, plan: np.ndarray, status: np.ndarray, stage: np.ndarray
    ) -> IKSolutions:
        """The empty result: unreachable (the stage that failed), or every solution outside
        the limits of ``plan`` (:func:`~._solution.finalize` names the joints)."""
        if not (status != kernels.EMPTY).any():
            worst = int(stage.max())
            return unreachable(6, f"no branch reaches the target: {_STAGES.get(worst, '')}")
        q, status, _, _ = kernels.solve_slots(
            KINDS.index(self.kind), self.reversed, T, self.geometry, -1, 0.0,
            plan[-5 + kernels.TOL], VERIFY_TOL,
        )  # fmt: skip
        labels = self.labels
        candidates = [
            Candidate(q[slot], labels[slot]) for slot in np.flatnonzero(status != kernels.EMPTY)
        ]
        start = kernels.GEOMETRY_SIZE
        return finalize(
            candidates,
            6,
            ~self.geometry[17:19].ravel().astype(bool)[:: -1 if self.reversed else 1],
            (plan[start : start + 6], plan[start + 6 : start + 12]),
        )

    def _plan_for(self, limits: Any, tol: Any) -> np.ndarray:
        """The plan of these limits and tolerance: the common calls take two identity tests
        to a plan made once; anything else is checked."""
        if limits is None and tol is DEFAULT_TOL:
            return self._unbounded_plan
        if limits.__class__ is str and limits == "robot" and tol is DEFAULT_TOL:
            return self._robot_plan
        return self._plan(self._limits(limits), _checks.length(tol, "tol", allow_zero=True))

    def _plan(self, limits: tuple[np.ndarray, np.ndarray], tol: float) -> np.ndarray:
        """The ``plan`` array of :func:`._decomposed_kernels.solve_raw`."""
        settings = np.zeros(5)
        settings[kernels.KIND] = KINDS.index(self.kind)
        settings[kernels.REVERSE] = float(self.reversed)
        settings[kernels.TOL] = tol
        settings[kernels.VERIFY] = VERIFY_TOL
        settings[kernels.DUPLICATE] = DUPLICATE_TOL
        return np.concatenate([self.geometry.ravel(), limits[0], limits[1], settings])

    @cached_property
    def _robot_plan(self) -> np.ndarray:
        return self._plan((self.lower, self.upper), DEFAULT_TOL)

    @cached_property
    def _unbounded_plan(self) -> np.ndarray:
        return self._plan(_UNBOUNDED, DEFAULT_TOL)

    def _singular(
        self, T: np.ndarray, status: int, free: int, slot: int
    ) -> tuple[str, SolutionFamily | None]:
        if status != kernels.SINGULAR:
            return "", None
        if free < 0:
            return "at the edge of a subproblem's reach: two branches coincide", None
        chain_joint = 5 - free if self.reversed else free
        reason = _FREE_REASONS[self.kind].get(chain_joint, "a subproblem is degenerate")
        text = f"θ{free + 1} is arbitrary ({reason})"
        kind = KINDS.index(self.kind)

        def member(t: float) -> np.ndarray:
            return kernels.solve_slots(
                kind, self.reversed, T, self.geometry, free, t, DEFAULT_TOL, VERIFY_TOL
            )[0][slot].copy()

        return text, SolutionFamily((free,), text, member)

    def _limits(self, limits: Any) -> tuple[np.ndarray, np.ndarray]:
        if isinstance(limits, str):
            if limits != "robot":
                raise InvalidInput(
                    f"limits must be 'robot', None or (lower, upper), got {limits!r}"
                )
            return self.lower, self.upper
        if limits is None:
            return _UNBOUNDED
        checked = _checks.limits(limits, 6)
        assert checked is not None
        return checked


_UNBOUNDED = (np.full(6, -np.inf), np.full(6, np.inf))
_NOTHING = np.empty((0, 0))
_NO_FLAGS = np.empty((3, 0), np.int64)


def decomposed_solver(
    S: np.ndarray,
    M: np.ndarray,
    lower: np.ndarray | None = None,
    upper: np.ndarray | None = None,
) -> DecomposedSolver:
    """The solver of the 6-joint chain with space screws ``S`` (6 × 6, (ω, v) columns; a
    prismatic joint has ω = 0) and home pose ``M``, with default limits ``lower``/``upper``
    (none by default).

    Raises:
        ModelError: The geometry fits no class (module docstring; the one class with a
            prismatic joint is the Stanford arm's).
    """
    S = _checks.finite_array(S, "S", (6, 6))
    M = _checks.pose(M, "M")
    prismatic = np.flatnonzero(np.linalg.norm(S[:3], axis=0) < 0.5)
    found = classify(S, M)
    if found is None and prismatic.size:
        raise ModelError(
            f"joint(s) {(prismatic + 1).tolist()} are prismatic and no decomposition fits: "
            "the one class with a prismatic joint is the Stanford arm's (axes 1 and 2 "
            "meeting, joint 3 sliding, a spherical wrist)"
        )
    if found is None:
        raise ModelError(
            "no closed-form decomposition fits this 6R arm: it needs a spherical wrist or "
            "shoulder (three axes through one point) or three parallel axes next to two "
            "intersecting ones (see redik.solvers.analytic.decomposed)"
        )
    kind, reverse, geometry = found
    lower = np.full(6, -np.inf) if lower is None else np.asarray(lower, dtype=float).copy()
    upper = np.full(6, np.inf) if upper is None else np.asarray(upper, dtype=float).copy()
    return DecomposedSolver(kind, reverse, geometry, lower, upper)


def screws_of(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """``(S, M)`` of a robot: the space Jacobian at q = 0 (its columns are the screw axes,
    swapped to (ω, v)) and the end-effector pose there; checked against ``robot.fk`` at two
    other configurations.

    Raises:
        ModelError: ``robot.fk`` is not the product of exponentials of those screws (a
            coupled or non-serial model).
    """
    zero = np.zeros(robot.dof)
    J = robot.jacobian(zero, reference="space")
    S = np.vstack([J[3:], J[:3]])
    M = robot.fk(zero)
    swap = np.r_[3:6, 0:3]
    for q in (np.linspace(0.4, -0.7, robot.dof), np.linspace(-1.1, 0.9, robot.dof)):
        T = M
        for i in reversed(range(robot.dof)):
            T = se3_exp(S[swap, i] * q[i]) @ T
        mismatch = float(np.abs(robot.fk(q) - T).max())
        if mismatch > MATCH_TOL:
            raise ModelError(
                f"{robot.name!r} does not move as the product of exponentials of its screw "
                f"axes at q = 0 (poses differ by {mismatch:.3g})"
            )
    return S, M


def solver_from_robot(robot: Robot) -> DecomposedSolver:
    """:func:`decomposed_solver` for a 6-joint :class:`redik.Robot` and its joint limits."""
    if robot.dof != 6:
        raise ModelError(f"{robot.name!r} has {robot.dof} joints; the decomposition takes 6")
    S, M = screws_of(robot)
    return decomposed_solver(S, M, robot.lower, robot.upper)
