r"""Planar 2R and 3R arms: both elbow branches, and the 3R self-motion family.

Forward kinematics (Spong, Hutchinson & Vidyasagar §3.3 example; Craig 3rd ed. §4.4):

.. math::
    x = l_1 c_1 + l_2 c_{12} \;(+\, l_3 c_{123}),\qquad
    y = l_1 s_1 + l_2 s_{12} \;(+\, l_3 s_{123}),\qquad φ = θ_1 + θ_2 + θ_3 .

2R inverse (law of cosines), with :math:`r = \sqrt{x^2 + y^2}`:

.. math::
    \cos θ_2 = \frac{r^2 - l_1^2 - l_2^2}{2 l_1 l_2},\quad
    \sin θ_2 = \pm\frac{\sqrt{((l_1+l_2)^2 - r^2)\,(r^2 - (l_1-l_2)^2)}}{2 l_1 l_2},\quad
    θ_1 = \operatorname{atan2}(y, x) - \operatorname{atan2}(l_2 \sin θ_2,\; l_1 + l_2 \cos θ_2).

The product form of :math:`\sin θ_2` stays accurate at the workspace boundary, where
:math:`\sqrt{1 - \cos^2 θ_2}` loses half the digits. The target is reachable iff
:math:`|l_1 - l_2| \le r \le l_1 + l_2`; within ``tol`` of either circle the two branches
merge into one boundary solution (θ2 = 0 "elbow-straight" or θ2 = π "elbow-folded").

Branch labels: ``"elbow-down"`` has θ2 > 0 and ``"elbow-up"`` θ2 < 0 — for a target on the
+x side, with y up, the elbow is then below (above) the shoulder–target line.

3R with orientation: the wrist point :math:`(x - l_3\cos φ,\; y - l_3 \sin φ)` is solved as
2R and :math:`θ_3 = φ - θ_1 - θ_2`. For position only, φ is a free parameter: the wrist point
is at distance :math:`w(φ)^2 = r^2 + l_3^2 - 2 l_3 r \cos(φ - \operatorname{atan2}(y, x))` from
the shoulder, so the reachable φ form at most two intervals (:func:`planar_3r_family`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from redik.solvers.analytic import _checks
from redik.solvers.analytic._numeric import ARRAY, SCALAR, Numeric, Value
from redik.solvers.analytic.results import (
    DEFAULT_TOL,
    BatchSolutions,
    Candidate,
    IKSolutions,
    SolutionFamily,
    finalize,
    limit_representatives,
    unreachable,
    wrap_angle,
)

#: Slot labels of the 2R solvers: slot 0 has θ2 ≥ 0, slot 1 θ2 ≤ 0.
ELBOW_LABELS = ("elbow-down", "elbow-up")


@dataclass(frozen=True)
class TwoLink:
    """Both branches of a 2R sub-problem, for one target (floats) or a batch ((B,) arrays).

    ``theta1``, ``theta2`` are pairs (slot 0 with θ2 ∈ [0, π], slot 1 with θ2 ∈ [−π, 0]) of
    values shaped like the target's; θ1 is not wrapped (:func:`.finalize` and
    :func:`batch_result` wrap once). On the boundary both slots hold the single solution.
    Unreachable entries hold finite but meaningless angles.
    """

    theta1: tuple[Value, Value]
    theta2: tuple[Value, Value]
    radius: Value
    reachable: Value
    boundary: Value


def two_link(x: Value, y: Value, l1: float, l2: float, tol: float, num: Numeric = ARRAY) -> TwoLink:
    """Both branches of a 2R subproblem.

    Solve :math:`(x, y) = l_1 (c_1, s_1) + l_2 (c_{12}, s_{12})` for ``l1, l2 > 0``
    (law of cosines, module docstring), elementwise in :mod:`._numeric`'s sense.
    """
    radius = num.hypot(x, y)
    outer, inner = l1 + l2, abs(l1 - l2)
    reachable = (radius <= outer + tol) & (radius >= inner - tol)
    at_outer = abs(radius - outer) <= tol
    boundary = at_outer | (abs(radius - inner) <= tol)
    product = (outer - radius) * (outer + radius) * (radius - inner) * (radius + inner)
    s2 = num.where(boundary, 0.0, num.sqrt(num.maximum(product, 0.0)) / (2.0 * l1 * l2))
    c2 = num.clip((radius * radius - l1 * l1 - l2 * l2) / (2.0 * l1 * l2), -1.0, 1.0)
    c2 = num.where(boundary, num.where(at_outer, 1.0, -1.0), c2)
    heading = num.atan2(y, x)
    theta1, theta2 = [], []
    for sine in (s2, -s2):
        theta2.append(num.atan2(sine, c2))
        theta1.append(heading - num.atan2(l2 * sine, l1 + l2 * c2))
    return TwoLink(tuple(theta1), tuple(theta2), radius, reachable, boundary)


def two_link_reason(radius: float, l1: float, l2: float, what: str = "target") -> str:
    """Why a point at ``radius`` from the shoulder is out of a 2R arm's reach."""
    if radius > l1 + l2:
        return (
            f"{what} is {radius:.6g} m from the shoulder, beyond the reach "
            f"{l1:.6g} + {l2:.6g} = {l1 + l2:.6g} m"
        )
    return (
        f"{what} is {radius:.6g} m from the shoulder, inside the unreachable disc of radius "
        f"|{l1:.6g} − {l2:.6g}| = {abs(l1 - l2):.6g} m"
    )


def two_link_candidates(
    solution: TwoLink, l1: float, l2: float, tol: float, labels: tuple[str, str] = ELBOW_LABELS
) -> list[tuple[tuple[float, float], str, str, bool]]:
    """The distinct 2R solutions of one reachable target as ``(q, label, singular, free)``.

    ``free`` is True when θ1 is arbitrary (l1 = l2 and the target at the shoulder).
    """
    theta = list(zip(solution.theta1, solution.theta2, strict=True))
    if not solution.boundary:
        return [(theta[0], labels[0], "", False), (theta[1], labels[1], "", False)]
    radius = float(solution.radius)
    if abs(radius - (l1 + l2)) <= tol:
        text = f"workspace boundary: arm stretched, r = l1 + l2 = {l1 + l2:.6g} m"
        return [(theta[0], "elbow-straight", text, False)]
    if radius <= tol:
        text = "target at the shoulder with l1 = l2: θ2 = π and θ1 is arbitrary"
        return [(theta[0], "elbow-folded", text, True)]
    text = f"workspace boundary: arm folded, r = |l1 − l2| = {abs(l1 - l2):.6g} m"
    return [(theta[0], "elbow-folded", text, False)]


def planar_2r(
    x: float,
    y: float,
    l1: float,
    l2: float,
    *,
    limits: tuple[ArrayLike, ArrayLike] | None = None,
    tol: float = DEFAULT_TOL,
) -> IKSolutions:
    """Every joint vector ``(θ1, θ2)`` of a planar 2R arm that puts its tip at ``(x, y)``.

    Args:
        x: Tip position along the base x axis (metres).
        y: Tip position along the base y axis (metres).
        l1: First link length (metres, > 0).
        l2: Second link length (metres, > 0).
        limits: Optional ``(lower, upper)`` arrays of 2 (angles compared modulo 2π).
        tol: Distance (m) within which a target counts as on the workspace boundary.

    Returns:
        Two solutions (``"elbow-down"``, ``"elbow-up"``); one on the boundary; at the shoulder
        with ``l1 = l2`` one representative whose ``family`` has θ1 free; none, with a
        ``reason``, outside the annulus ``|l1 − l2| ≤ r ≤ l1 + l2``.
    """
    x, y = _checks.scalar(x, "x"), _checks.scalar(y, "y")
    return planar_2r_solutions(x, y, l1, l2, _checks.limits(limits, 2), tol)


def planar_2r_solutions(
    x: float,
    y: float,
    l1: float,
    l2: float,
    limits: tuple[np.ndarray, np.ndarray] | None,
    tol: float = DEFAULT_TOL,
) -> IKSolutions:
    """:func:`planar_2r` on a checked target and limits.

    The lengths are checked here; the target and limits are the caller's, which validates
    them at its own boundary (:class:`redik.solvers.analytic.SmallArmSolver`).
    """
    l1, l2 = _checks.length(l1, "l1"), _checks.length(l2, "l2")
    checked_limits = limits
    solution = two_link(x, y, l1, l2, tol, SCALAR)
    if not solution.reachable:
        return unreachable(2, two_link_reason(float(solution.radius), l1, l2))
    candidates = []
    for q, label, singular, free in two_link_candidates(solution, l1, l2, tol):
        family = None
        if free:
            family = SolutionFamily((0,), singular, lambda t: wrap_angle(np.array([t, np.pi])))
        candidates.append(Candidate(q, label, singular, family))
    return finalize(candidates, 2, np.ones(2, bool), checked_limits)


def planar_2r_batch(
    xy: np.ndarray,
    l1: float,
    l2: float,
    *,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
) -> BatchSolutions:
    """:func:`planar_2r` for a (B, 2) array of tip positions, vectorised.

    Returns a :class:`BatchSolutions` with ``q`` (B, 2, 2), slots ``("elbow-down",
    "elbow-up")``; on the boundary both slots are valid and equal.
    """
    xy = _checks.finite_array(xy, "xy", (None, 2))
    l1, l2 = _checks.length(l1, "l1"), _checks.length(l2, "l2")
    checked_limits = _checks.limits(limits, 2)
    solution = two_link(xy[:, 0], xy[:, 1], l1, l2, tol)
    q = np.stack([np.stack(solution.theta1, axis=-1), np.stack(solution.theta2, axis=-1)], axis=-1)
    valid = np.repeat(solution.reachable[:, None], 2, axis=1)
    singular = np.repeat(solution.boundary[:, None], 2, axis=1)
    return batch_result(q, valid, singular, ELBOW_LABELS, np.ones(2, bool), checked_limits)


def batch_result(
    q: np.ndarray,
    valid: np.ndarray,
    singular: np.ndarray,
    labels: tuple[str, ...],
    revolute: np.ndarray,
    limits: tuple[np.ndarray, np.ndarray] | None,
) -> BatchSolutions:
    """A batch's angles wrapped, limits applied, invalid slots blanked.

    Wrap the angles of a batch to (−π, π], apply the joint limits and blank the invalid
    slots with NaN.
    """
    q = np.where(revolute, wrap_angle(q), q)
    if limits is not None:
        q, inside = limit_representatives(q, limits[0], limits[1], revolute)
        valid = valid & inside.all(axis=-1)
    q = np.where(valid[..., None], q, np.nan)
    return BatchSolutions(q, valid, singular & valid, labels)


def planar_3r(
    x: float,
    y: float,
    phi: float,
    l1: float,
    l2: float,
    l3: float,
    *,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
) -> IKSolutions:
    """Every ``(θ1, θ2, θ3)`` of a planar 3R arm with tip at ``(x, y)`` and heading ``φ``.

    The wrist point ``(x − l3 cos φ, y − l3 sin φ)`` is solved as a 2R arm (see
    :func:`planar_2r` for labels, boundary and singular cases) and ``θ3 = φ − θ1 − θ2``.
    """
    x, y, phi = _checks.scalar(x, "x"), _checks.scalar(y, "y"), _checks.scalar(phi, "phi")
    l1, l2, l3 = (_checks.length(v, n) for v, n in ((l1, "l1"), (l2, "l2"), (l3, "l3")))
    checked_limits = _checks.limits(limits, 3)
    wrist_x, wrist_y = x - l3 * math.cos(phi), y - l3 * math.sin(phi)
    solution = two_link(wrist_x, wrist_y, l1, l2, tol, SCALAR)
    if not solution.reachable:
        what = f"the wrist point ({wrist_x:.6g}, {wrist_y:.6g}) for φ = {phi:.6g} rad"
        return unreachable(3, two_link_reason(float(solution.radius), l1, l2, what))

    def with_theta3(theta12: tuple[float, float] | np.ndarray) -> np.ndarray:
        return wrap_angle(np.append(theta12, phi - theta12[0] - theta12[1]))

    candidates = []
    for q, label, singular, free in two_link_candidates(solution, l1, l2, tol):
        family = None
        if free:
            family = SolutionFamily((0,), singular, lambda t: with_theta3(np.array([t, np.pi])))
        candidates.append(Candidate(with_theta3(q), label, singular, family))
    return finalize(candidates, 3, np.ones(3, bool), checked_limits)


@dataclass(frozen=True)
class Planar3RFamily:
    """The solutions of a planar 3R arm for a tip position alone, as a function of φ.

    Attributes:
        x, y, l1, l2, l3, tol: The problem.
        phi_intervals: The headings φ for which the tip is reachable, as closed intervals
            ``(start, end)`` with ``start ∈ (−π, π]`` and ``end ≥ start`` (read modulo 2π;
            ``(−π, π)`` means every φ). Empty when the position is out of reach.

    Call the family with a heading to get the (up to two) solutions: ``family(phi)``.
    """

    x: float
    y: float
    l1: float
    l2: float
    l3: float
    tol: float
    phi_intervals: tuple[tuple[float, float], ...] = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "phi_intervals", self._intervals())

    def __call__(
        self, phi: float, *, limits: tuple[np.ndarray, np.ndarray] | None = None
    ) -> IKSolutions:
        """The solutions at heading ``phi`` (:func:`planar_3r`)."""
        return planar_3r(
            self.x, self.y, phi, self.l1, self.l2, self.l3, limits=limits, tol=self.tol
        )

    @property
    def reachable(self) -> bool:
        """Whether some heading reaches the point."""
        return bool(self.phi_intervals)

    def contains(self, phi: float) -> bool:
        """Whether the heading ``phi`` is reachable."""
        return any(
            float(np.mod(phi - start, 2.0 * np.pi)) <= end - start + 1e-12
            for start, end in self.phi_intervals
        )

    def _intervals(self) -> tuple[tuple[float, float], ...]:
        # w(φ)² = r² + l3² − 2 l3 r cos(φ − ψ) must lie in [(l1 − l2)², (l1 + l2)²].
        r, l3 = float(np.hypot(self.x, self.y)), self.l3
        outer, inner = self.l1 + self.l2 + self.tol, max(abs(self.l1 - self.l2) - self.tol, 0.0)
        if r <= self.tol:
            return ((-np.pi, np.pi),) if inner <= l3 <= outer else ()
        lowest = (r * r + l3 * l3 - outer * outer) / (2.0 * l3 * r)  # cos(φ − ψ) ≥ lowest
        highest = (r * r + l3 * l3 - inner * inner) / (2.0 * l3 * r)  # cos(φ − ψ) ≤ highest
        if lowest > 1.0 or highest < -1.0 or lowest > highest:
            return ()
        widest = float(np.arccos(np.clip(lowest, -1.0, 1.0)))  # |φ − ψ| ≤ widest
        narrowest = float(np.arccos(np.clip(highest, -1.0, 1.0)))  # |φ − ψ| ≥ narrowest
        psi = float(np.arctan2(self.y, self.x))
        if narrowest == 0.0 and widest == np.pi:
            return ((-np.pi, np.pi),)
        if narrowest == 0.0:
            return (_interval(psi - widest, 2.0 * widest),)
        if widest == np.pi:
            return (_interval(psi + narrowest, 2.0 * (np.pi - narrowest)),)
        width = widest - narrowest
        return (_interval(psi - widest, width), _interval(psi + narrowest, width))


def planar_3r_family(
    x: float, y: float, l1: float, l2: float, l3: float, *, tol: float = DEFAULT_TOL
) -> Planar3RFamily:
    """The one-parameter family of 3R solutions for the tip position ``(x, y)`` alone.

    Returns a :class:`Planar3RFamily`: its ``phi_intervals`` are the reachable end-effector
    headings φ (closed form, module docstring) and ``family(phi)`` gives the solutions for one
    heading.
    """
    x, y = _checks.scalar(x, "x"), _checks.scalar(y, "y")
    l1, l2, l3 = (_checks.length(v, n) for v, n in ((l1, "l1"), (l2, "l2"), (l3, "l3")))
    return Planar3RFamily(x, y, l1, l2, l3, tol)


def _interval(start: float, width: float) -> tuple[float, float]:
    begin = float(wrap_angle(start))
    return begin, begin + width
