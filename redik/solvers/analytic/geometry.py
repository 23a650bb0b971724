r"""The geometry of a 6-joint arm from its screw axes, and the closed-form class it belongs to.

The arm is read from its screws at q = 0 (:func:`screws_of`): ``robot.jacobian(0,
reference="space")`` gives the columns :math:`S_i = (ω_i, v_i)`, so :math:`T(q) =
e^{[S_1]q_1} ⋯ e^{[S_6]q_6} M` (Modern Robotics §4.1). :func:`classify` finds which
consecutive axes intersect or are parallel and names the IK-Geo class that solves the arm in
closed form (Elias & Wen 2022, "IK-Geo", arXiv 2211.05737, §IV), with the chain run forwards
or, for an arm whose special axes sit at the base (a spherical *shoulder*), backwards:

``spherical_two_intersecting``
    axes 4, 5, 6 meet (a spherical wrist) and axes 1, 2 meet (PUMA, KUKA): SP3, SP2, wrist.
``spherical_two_parallel``
    a spherical wrist and axes 2 ∥ 3 (offset elbows): SP4, SP3, SP1, wrist.
``spherical``
    a spherical wrist and any axes 1–3: SP5, wrist.
``three_parallel_two_intersecting``
    axes 2 ∥ 3 ∥ 4 and axes 5, 6 meet (Universal Robots): SP4, SP4, SP1, SP1, SP3, SP1.
``three_parallel``
    axes 2 ∥ 3 ∥ 4 and any axes 1, 5, 6: SP6, SP1, SP1, SP3, SP1.
``spherical_two_intersecting_prismatic``
    axes 1, 2 meet, joint 3 slides, a spherical wrist (the Stanford arm): the slide's line
    meets a sphere about the shoulder (d3 ±), SP2, wrist.

An arm that fits none has the general elimination (:mod:`.general`). Nothing here reads a
model's name: the class is the screws'.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from redik.core.exceptions import ModelError
from redik.lie import se3_exp

if TYPE_CHECKING:
    from redik.kinematics.robot import Robot

#: The closed-form classes (module docstring), in the order :func:`classify` tries them.
KINDS = (
    "spherical_two_intersecting",
    "spherical_two_parallel",
    "spherical",
    "three_parallel_two_intersecting",
    "three_parallel",
    "spherical_two_intersecting_prismatic",
)

#: How close (m; rad for directions) axes must be to intersecting or parallel to count as
#: such. The kernels solve the ideal geometry, so this is what their FK error may reach.
GEOMETRY_TOL = 1e-10

#: How closely ``robot.fk`` must match the screw chain read from the Jacobian (m).
MATCH_TOL = 1e-9


@dataclass(frozen=True)
class Chain:
    """A 6-joint chain as axes and points at q = 0 (world frame).

    Attributes:
        h: (6, 3) unit axes (a slide's direction for a prismatic joint).
        a: (6, 3) a point on each axis.
        M: The home pose of the end-effector.
        prismatic: (6,) which joints slide.
    """

    h: np.ndarray
    a: np.ndarray
    M: np.ndarray
    prismatic: np.ndarray = field(default_factory=lambda: np.zeros(6, bool))

    @classmethod
    def from_screws(cls, S: np.ndarray, M: np.ndarray) -> Chain:
        """The chain of space screws.

        From space screws ``S`` (6 × 6, columns (ω, v), Modern Robotics order): the axis is
        ω and its point nearest the origin ω × v (v = −ω × a); a prismatic joint (ω = 0)
        slides along v through the origin (any point would do).
        """
        S = np.asarray(S, dtype=float)
        prismatic = np.linalg.norm(S[:3], axis=0) < 0.5
        h = np.where(prismatic[:, None], S[3:].T, S[:3].T)
        a = np.where(prismatic[:, None], 0.0, np.cross(h, S[3:].T))
        return cls(h, a, np.asarray(M, dtype=float), prismatic)

    def reversed(self) -> Chain:
        r"""The chain run backwards.

        The chain run backwards: :math:`T^{-1} = M^{-1} e^{-[S_6]q_6} ⋯ e^{-[S_1]q_1}
        = e^{[S'_1]q_6} ⋯ e^{[S'_6]q_1} M^{-1}` with :math:`S'_k = -\mathrm{Ad}_{M^{-1}}
        S_{7-k}`: axes ``−R_Mᵀ h`` through the points ``R_Mᵀ (a − p_M)``, reversed.
        """
        R, p = self.M[:3, :3], self.M[:3, 3]
        M_inverse = np.eye(4)
        M_inverse[:3, :3], M_inverse[:3, 3] = R.T, -R.T @ p
        return Chain(
            -(self.h @ R)[::-1].copy(),
            ((self.a - p) @ R)[::-1].copy(),
            M_inverse,
            self.prismatic[::-1].copy(),
        )

    def parallel(self, i: int, j: int) -> bool:
        """Whether axes i and j are parallel."""
        return bool(np.linalg.norm(np.cross(self.h[i], self.h[j])) <= GEOMETRY_TOL)

    def meeting_point(self, i: int, j: int) -> np.ndarray | None:
        """Where axes i and j intersect (None if they do not, or are parallel)."""
        normal = np.cross(self.h[i], self.h[j])
        sine = np.linalg.norm(normal)
        if sine <= GEOMETRY_TOL:
            return None
        gap = self.a[j] - self.a[i]
        if abs(gap @ normal) / sine > GEOMETRY_TOL * (1.0 + np.linalg.norm(gap)):
            return None
        # a_i + s h_i = a_j + t h_j, least squares in (s, t).
        (s, _), *_ = np.linalg.lstsq(np.stack([self.h[i], -self.h[j]], axis=1), gap, rcond=None)
        return self.a[i] + s * self.h[i]

    def common_point(self, i: int, j: int, k: int) -> np.ndarray | None:
        """Where axes i, j, k meet (None if they do not)."""
        first, second = self.meeting_point(i, j), self.meeting_point(j, k)
        if first is None or second is None:
            return None
        if np.linalg.norm(first - second) > GEOMETRY_TOL * (1.0 + np.linalg.norm(first)):
            return None
        return first

    def on_axis(self, axis: int, point: np.ndarray) -> bool:
        """Whether ``point`` lies on the axis."""
        offset = point - self.a[axis]
        along = self.h[axis] * (offset @ self.h[axis])
        return bool(np.linalg.norm(offset - along) <= GEOMETRY_TOL)

    def scaled(self, length: float) -> Chain:
        """The same chain with every length divided by ``length``."""
        M = self.M.copy()
        M[:3, 3] /= length
        return Chain(self.h, self.a / length, M, self.prismatic)

    def length(self) -> float:
        """A length of the arm (m).

        A length of the arm (m): the largest distance of an axis point or the tip from the
        first axis point (at least 1e-6).
        """
        points = np.vstack([self.a, self.M[:3, 3]])
        return max(float(np.abs(points - self.a[0]).max()), 1e-6)


def perpendicular(axis: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to ``axis``."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    unit = np.cross(axis, helper)
    return unit / np.linalg.norm(unit)


def pack(chain: Chain, points: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """The packed geometry ``G`` of :mod:`.chain`.

    The (19, 3) array ``G`` of :mod:`.chain`: axes, the kernel's points, ``p_M``, ``R_M``,
    a unit vector perpendicular to ``reference``, and the prismatic flags.
    """
    flags = chain.prismatic.astype(float).reshape(2, 3)
    return np.ascontiguousarray(
        np.vstack(
            [chain.h, points, chain.M[:3, 3], chain.M[:3, :3], perpendicular(reference), flags]
        )
    )


@dataclass(frozen=True)
class Classification:
    """What :func:`classify` finds.

    Attributes:
        kind: The class (a name of :data:`KINDS`).
        reversed: Whether the chain is solved backwards (for ``T⁻¹``).
        geometry: The packed (19, 3) geometry of the chain as solved.
    """

    kind: str
    reversed: bool
    geometry: np.ndarray


def _wrist_classes(chain: Chain) -> tuple[str, np.ndarray] | None:
    """The classes with a spherical wrist (axes 4, 5, 6 meeting off axis 3), or None."""
    if chain.parallel(3, 4) or chain.parallel(4, 5):
        return None
    centre = chain.common_point(3, 4, 5)
    if centre is None or chain.on_axis(2, centre):
        return None
    points = chain.a.copy()
    points[3:6] = centre
    shoulder = chain.meeting_point(0, 1)
    if shoulder is not None and not chain.on_axis(2, shoulder):
        points[0:2] = shoulder
        return "spherical_two_intersecting", pack(chain, points, chain.h[5])
    if chain.parallel(1, 2) and not chain.parallel(0, 1):
        return "spherical_two_parallel", pack(chain, points, chain.h[5])
    return "spherical", pack(chain, points, chain.h[5])


def _parallel_classes(chain: Chain) -> tuple[str, np.ndarray] | None:
    """The classes with axes 2 ∥ 3 ∥ 4 (distinct lines, axes 1 and 5 across them), or None."""
    if not (chain.parallel(1, 2) and chain.parallel(2, 3)):
        return None
    if chain.parallel(0, 1) or chain.parallel(4, 1):
        return None
    if chain.on_axis(1, chain.a[2]) or chain.on_axis(2, chain.a[3]):
        return None
    points = chain.a.copy()
    wrist = chain.meeting_point(4, 5)
    if wrist is not None:
        points[4:6] = wrist
        return "three_parallel_two_intersecting", pack(chain, points, chain.h[1])
    return "three_parallel", pack(chain, points, chain.h[1])


def _prismatic_class(chain: Chain) -> tuple[str, np.ndarray] | None:
    """The Stanford arm's class (axes 1, 2 meeting, joint 3 sliding, spherical wrist), or None."""
    if not np.array_equal(chain.prismatic, [False, False, True, False, False, False]):
        return None
    if chain.parallel(3, 4) or chain.parallel(4, 5) or chain.parallel(0, 1):
        return None
    centre, shoulder = chain.common_point(3, 4, 5), chain.meeting_point(0, 1)
    if centre is None or shoulder is None:
        return None
    points = chain.a.copy()
    points[0:3], points[3:6] = shoulder, centre
    return "spherical_two_intersecting_prismatic", pack(chain, points, chain.h[5])


def classify(S: np.ndarray, M: np.ndarray) -> Classification | None:
    """The closed-form class of a 6-joint chain.

    The closed-form class of the 6-joint chain ``(S, M)`` (module docstring), forwards
    first, then backwards; None when no class fits.
    """
    chain = Chain.from_screws(S, M)
    for reverse, candidate in ((False, chain), (True, chain.reversed())):
        if candidate.prismatic.any():
            found = _prismatic_class(candidate)
        else:
            found = _wrist_classes(candidate) or _parallel_classes(candidate)
        if found is not None:
            return Classification(found[0], reverse, found[1])
    return None


def screws_of(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """The screw axes and home pose of a robot.

    ``(S, M)`` of a robot: the space Jacobian at q = 0 (its columns are the screw axes,
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


def random_arm(kind: str, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A random arm of class ``kind``, as ik-geo's own setups make one.

    Unit axes ``h`` (6 × 3) and offsets ``p`` (7 × 3) uniform in [−1, 1]³, axis ``i`` through
    ``p_0 + … + p_{i−1}``, with the equal axes and zero offsets the class needs (:data:`KINDS`,
    and ik-geo's searched classes ``two_parallel``, ``two_intersecting`` and ``gen_six_dof``).
    """
    h = rng.normal(size=(6, 3))
    h /= np.linalg.norm(h, axis=1)[:, None]
    p = rng.uniform(-1.0, 1.0, (7, 3))
    if kind in ("spherical_two_parallel", "two_parallel"):
        h[2] = h[1]
    if kind.startswith("three_parallel"):
        h[2] = h[3] = h[1]
    if kind.startswith("spherical"):
        p[4] = p[5] = 0.0
    if kind.startswith("spherical_two_intersecting"):
        p[1] = 0.0
    if kind in ("three_parallel_two_intersecting", "two_intersecting"):
        p[5] = 0.0
    return h, p


def arm_screws(
    h: np.ndarray, p: np.ndarray, prismatic: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Screws ``S`` (6 × 6, columns ``(ω, v)``) and home pose ``M`` of the arm ``(h, p)``.

    The home rotation is the identity; with ``prismatic``, joint 3 slides along its axis.
    """
    points = np.cumsum(p[:6], axis=0)
    S = np.vstack([h.T, np.cross(-h, points).T])
    if prismatic:
        S[:, 2] = np.r_[np.zeros(3), h[2]]
    M = np.eye(4)
    M[:3, 3] = p.sum(axis=0)
    return S, M
