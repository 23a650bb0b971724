r"""The exact self-motion of a 7R arm with a spherical shoulder and wrist, by the arm angle.

In an S-R-S arm (KUKA iiwa type) axes 1–3 meet at the shoulder ``S`` and axes 5–7 at the wrist
``W``; the elbow axis 4 passes through neither. For a target pose the wrist centre ``W_t`` is
fixed, so ‖S − W_t‖ fixes θ4 (SP3, two roots) and the elbow point ``E`` (any point of axis 4,
carried by joints 1–3) keeps its distances to S and W: it lies on a circle about the
shoulder–wrist line. The **arm angle** ψ is the angle of ``E`` on that circle (Shimizu,
Kakuya, Yoon, Kitagaki & Kosuge 2008, "Analytical inverse kinematic computation for 7-DOF
redundant manipulators with joint limits and its application to redundancy resolution",
IEEE T-RO 24(5)), measured from the plane of the shoulder–wrist line and axis 1. For each
ψ and each θ4 root:

1. ``R_1 R_2 R_3`` is the rotation that takes the home pair ``(E − S, v_4)``,
   :math:`v_4 = (E - S) + R_4 (W - E)`, to ``(E(ψ) − S, W_t − S)`` (two frames, one product);
2. θ1, θ2 by SP2 on ``R123 h3`` (two roots), θ3 by SP1;
3. ``R_5 R_6 R_7 = (R_{123} R_4)^\top Z``: θ5, θ6 by SP2 (two roots), θ7 by SP1.

So each ψ gives up to 8 configurations (elbow × shoulder × wrist roots), each checked by FK,
and as ψ turns once the 8 branches, followed by continuity, close into the self-motion loops
of the pose (Burdick 1989). :func:`self_motion_curves` returns them sampled at a joint-space
spacing; :func:`redik.explore_self_motion` uses them with ``exact=True``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np

from redik.core.exceptions import ModelError
from redik.core.validate import integer
from redik.kinematics.compiled import COMPILE
from redik.lie import wrap_angle
from redik.solvers.analytic import _checks
from redik.solvers.analytic.geometry import Chain, perpendicular, screws_of
from redik.solvers.analytic.subproblems import FREE, OUT, sp1, sp2_cs, sp3_cs
from redik.solvers.analytic.vectors import (
    add,
    cross,
    dot,
    norm,
    rotate,
    rotate_cs,
    scale,
    sub,
)
from redik.solvers.analytic.vectors import row as _row

if TYPE_CHECKING:
    from redik.kinematics.robot import Robot

#: Configurations per arm angle: elbow × shoulder × wrist roots.
BRANCHES = 8
VERIFY_TOL = 1e-9


@dataclass(frozen=True)
class SRSArm:
    """A 7R chain with a spherical shoulder and wrist, packed for the kernel.

    Attributes:
        geometry: (17, 3): rows 0–6 the axes at q = 0; 7 the shoulder ``S``; 8 a point of
            axis 4; 9 the wrist ``W``; 10 ``p_M``; 11–13 the rows of ``R_M``; 14 the
            reference direction of ψ = 0 (axis 1); 15, 16 unit vectors ⊥ axes 3 and 7.
        points: (7, 3) a point on each axis (for the FK check).
    """

    geometry: np.ndarray
    points: np.ndarray

    @classmethod
    def from_robot(cls, robot: Robot) -> SRSArm:
        """Read the screw axes of a 7R robot (:func:`redik.solvers.analytic.geometry.screws_of`).

        Raises:
            ModelError: The robot is not a 7R arm with a spherical shoulder and wrist.
        """
        if robot.dof != 7 or not robot.revolute.all():
            raise ModelError(f"{robot.name!r} is not a 7R arm (the arm angle needs 7 hinges)")
        S, M = screws_of(robot)
        chain = Chain.from_screws(S, M)
        shoulder = chain.common_point(0, 1, 2)
        wrist = chain.common_point(4, 5, 6)
        if shoulder is None or wrist is None:
            raise ModelError(
                f"{robot.name!r}: axes 1–3 and 5–7 must each meet in one point (a spherical "
                "shoulder and wrist) for the arm-angle parameterisation"
            )
        if chain.on_axis(3, shoulder) or chain.on_axis(3, wrist):
            raise ModelError(f"{robot.name!r}: the elbow axis passes through the shoulder or wrist")
        geometry = np.vstack(
            [
                chain.h,
                shoulder,
                chain.a[3],
                wrist,
                M[:3, 3],
                M[:3, :3],
                chain.h[0],
                perpendicular(chain.h[2]),
                perpendicular(chain.h[6]),
            ]
        )
        return cls(geometry, chain.a.copy())

    def at(self, T: np.ndarray, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The 8 configurations at each arm angle.

        The 8 configurations at each arm angle: ``q`` (N, 8, 7) wrapped to (−π, π] and
        ``valid`` (N, 8) (solved and checked by FK to :data:`VERIFY_TOL`).
        """
        T = _checks.pose(T, "T")
        psi = np.atleast_1d(np.asarray(psi, dtype=float))
        q, valid = _srs_slots(T, self.geometry, self.points, psi)
        return wrap_angle(q), valid


@numba.njit(**COMPILE)
def _frame(a, b):
    """Rows of the orthonormal frame (â, b̂⊥, â × b̂⊥) of two non-parallel vectors."""
    x = scale(a, 1.0 / norm(a))
    y = sub(b, scale(x, dot(x, b)))
    y = scale(y, 1.0 / norm(y))
    return x, y, cross(x, y)


@numba.njit(**COMPILE)
def _map(f, g, v):
    """``Gᵀ F v`` for frames given by rows: the rotation taking frame f to frame g."""
    c = (dot(f[0], v), dot(f[1], v), dot(f[2], v))
    return add(add(scale(g[0], c[0]), scale(g[1], c[1])), scale(g[2], c[2]))


@numba.njit(**COMPILE)
def _fk_error(points, G, q, T):
    """Pose error of the 7R chain at ``q`` (position, and the first two rotation columns)."""
    p = sub(_row(G, 10), points[6])
    x = (G[11, 0], G[12, 0], G[13, 0])
    y = (G[11, 1], G[12, 1], G[13, 1])
    for i in range(6, -1, -1):
        k = _row(G, i)
        c, s = math.cos(q[i]), math.sin(q[i])
        p, x, y = rotate_cs(k, c, s, p), rotate_cs(k, c, s, x), rotate_cs(k, c, s, y)
        if i > 0:
            p = add(p, sub(points[i], points[i - 1]))
    p = add(p, points[0])
    error = norm(sub(p, (T[0, 3], T[1, 3], T[2, 3])))
    for i in range(3):
        error = max(error, max(abs(x[i] - T[i, 0]), abs(y[i] - T[i, 1])))
    return error


@numba.njit(**COMPILE)
def _wrist_target(T, G):
    r"""``(Z, W_t)``: the rows of :math:`Z = R R_M^\top` and the target's wrist centre."""
    m0, m1, m2 = _row(G, 11), _row(G, 12), _row(G, 13)
    rows = [(T[i, 0], T[i, 1], T[i, 2]) for i in range(3)]
    Z = [(dot(r, m0), dot(r, m1), dot(r, m2)) for r in rows]
    offset = sub(_row(G, 10), _row(G, 9))
    centre = (dot(Z[0], offset), dot(Z[1], offset), dot(Z[2], offset))
    return Z, sub((T[0, 3], T[1, 3], T[2, 3]), centre)


@numba.njit(**COMPILE)
def _elbow_circle(G, Wt):
    """The elbow: its two θ4 and the circle its point lies on.

    The two θ4 (SP3) and the circle the elbow point lies on: ``(t4a, t4b, status, centre,
    radius, n, m, sw)``, ``n, m`` the unit vectors of its plane (ψ = 0 along ``n``) and
    ``sw = W_t − S``.
    """
    S, E, W = _row(G, 7), _row(G, 8), _row(G, 9)
    sw = sub(Wt, S)
    d = norm(sw)
    u = scale(sw, 1.0 / d)
    a = sub(E, S)
    t4a, t4b, elbow, _, _, _, _ = sp3_cs(_row(G, 3), sub(W, E), sub(S, E), d, 1e-10)
    # The elbow circle: angle α between E − S and the shoulder–wrist line.
    length = norm(a)
    cos_alpha = (length * length + d * d - norm(sub(W, E)) ** 2) / (2.0 * length * d)
    cos_alpha = min(max(cos_alpha, -1.0), 1.0)
    centre = add(S, scale(u, length * cos_alpha))
    reference = _row(G, 14)
    n = sub(reference, scale(u, dot(u, reference)))
    if norm(n) < 1e-6:  # the wrist on axis 1: measure ψ from axis 2 instead
        n = sub(_row(G, 1), scale(u, dot(u, _row(G, 1))))
    n = scale(n, 1.0 / norm(n))
    radius = length * math.sqrt(1.0 - cos_alpha * cos_alpha)
    return t4a, t4b, elbow, centre, radius, n, cross(u, n), sw


@numba.njit(**COMPILE)
def _branches(G, points, T, Z, target, t4, slot0, q, valid):
    """The four configurations of one elbow root at one arm angle.

    The four configurations (shoulder × wrist roots) of one elbow root at one arm angle,
    into ``q`` (8, 7) and ``valid`` (8,) from slot ``slot0``: ``target`` is the frame of
    the elbow point and the wrist seen from the shoulder (:func:`_frame`).
    """
    S, E, W = _row(G, 7), _row(G, 8), _row(G, 9)
    h1, h2, h3, h4 = _row(G, 0), _row(G, 1), _row(G, 2), _row(G, 3)
    h5, h6, h7, e3, e7 = _row(G, 4), _row(G, 5), _row(G, 6), _row(G, 15), _row(G, 16)
    a = sub(E, S)
    home = _frame(a, add(a, rotate(h4, t4, sub(W, E))))
    x3, y3 = _map(home, target, h3), _map(home, target, e3)
    t1a, t2a, t1b, t2b, shoulder, _, trig = sp2_cs(scale(h1, -1.0), x3, h2, h3, 0.0, 0.0, 1e-10)
    # R5 R6 R7 = (R123 R4)ᵀ Z: apply (R123 R4)ᵀ = R4ᵀ (home → target)ᵀ.
    z7 = rotate(h4, -t4, _map(target, home, (dot(Z[0], h7), dot(Z[1], h7), dot(Z[2], h7))))
    y7 = rotate(h4, -t4, _map(target, home, (dot(Z[0], e7), dot(Z[1], e7), dot(Z[2], e7))))
    t5a, t6a, t5b, t6b, wrist, _, wtrig = sp2_cs(scale(h5, -1.0), z7, h6, h7, 0.0, 0.0, 1e-10)
    if shoulder == OUT or wrist == OUT:
        return
    for s in range(2):
        c1, s1, c2, s2 = trig[4 * s], trig[4 * s + 1], trig[4 * s + 2], trig[4 * s + 3]
        t3, _ = sp1(h3, e3, rotate_cs(h2, c2, -s2, rotate_cs(h1, c1, -s1, y3)))
        for w in range(2):
            c5, s5 = wtrig[4 * w], wtrig[4 * w + 1]
            c6, s6 = wtrig[4 * w + 2], wtrig[4 * w + 3]
            t7, _ = sp1(h7, e7, rotate_cs(h6, c6, -s6, rotate_cs(h5, c5, -s5, y7)))
            slot = slot0 + 2 * s + w
            q[slot, 0], q[slot, 1] = (t1a, t2a) if s == 0 else (t1b, t2b)
            q[slot, 2], q[slot, 3] = t3, t4
            q[slot, 4], q[slot, 5] = (t5a, t6a) if w == 0 else (t5b, t6b)
            q[slot, 6] = t7
            valid[slot] = _fk_error(points, G, q[slot], T) <= VERIFY_TOL


@numba.njit(**COMPILE)
def _srs_slots(T, G, point_rows, psi):
    """The configurations at each arm angle.

    ``q`` (N, 8, 7) and ``valid`` (N, 8): the configurations at each arm angle ψ (module
    docstring), slot ``4·elbow + 2·shoulder + wrist``.
    """
    points = [(point_rows[i, 0], point_rows[i, 1], point_rows[i, 2]) for i in range(7)]
    n = psi.shape[0]
    q = np.zeros((n, 8, 7))
    valid = np.zeros((n, 8), np.bool_)
    Z, Wt = _wrist_target(T, G)
    t4a, t4b, elbow, centre, radius, nref, mref, sw = _elbow_circle(G, Wt)
    if elbow == OUT or elbow == FREE:
        return q, valid
    S = _row(G, 7)
    for k in range(n):
        radial = add(scale(nref, math.cos(psi[k])), scale(mref, math.sin(psi[k])))
        target = _frame(sub(add(centre, scale(radial, radius)), S), sw)
        for el in range(2):
            _branches(G, points, T, Z, target, t4a if el == 0 else t4b, 4 * el, q[k], valid[k])
    return q, valid


def self_motion_curves(
    robot: Robot, T: np.ndarray, spacing: float = 0.05, samples: int = 720
) -> list[np.ndarray]:
    """The self-motion loops of a pose.

    The self-motion loops of ``T`` (limits ignored), each an (N, 7) array of consecutive
    configurations at most ``spacing`` apart (angles compared modulo 2π), closing on itself.

    The 8 branches are evaluated at ``samples`` arm angles, followed by continuity (each
    branch continues with the nearest configuration at the next ψ), refined by bisection in
    ψ where consecutive configurations are farther apart than ``spacing``, and chained: after
    a full turn of ψ a branch continues as the one it ends on, so a loop is one cycle of that
    permutation. Empty when the pose is out of reach.
    """
    spacing = _checks.length(spacing, "spacing")
    samples = integer(samples, "samples", 16)
    arm = SRSArm.from_robot(robot)
    psi = np.linspace(-np.pi, np.pi, samples + 1)
    q, valid = arm.at(T, psi)
    if not valid.any():
        return []
    if not valid.all():
        raise ModelError(
            "some arm angles have no configuration on some branch (a shoulder or wrist subproblem "
            "out of reach): the loops cannot be followed by the arm angle alone"
        )
    tracks = _follow(q)
    # A track ends (ψ = π) on the start (ψ = −π) of the track it continues as.
    successor = [int(np.argmin(_torus(tracks[:, 0], tracks[i, -1]))) for i in range(BRANCHES)]
    curves, seen = [], set()
    for start in range(BRANCHES):
        if start in seen:
            continue
        pieces, branch = [], start
        while branch not in seen:
            seen.add(branch)
            pieces.append(_refine(arm, T, psi, tracks[branch], spacing))
            branch = successor[branch]
        curves.append(_thin(np.concatenate([piece[:-1] for piece in pieces]), spacing))
    return curves


def _thin(curve: np.ndarray, spacing: float) -> np.ndarray:
    """Drop samples closer than the spacing.

    Drop samples while the gap between kept neighbours stays within ``spacing`` (the ψ grid
    is dense where the joints move slowly); the last sample is kept, so the loop still closes
    within one original step.
    """
    kept = [0]
    for k in range(1, len(curve)):
        following = curve[(k + 1) % len(curve)]
        if _torus(curve[kept[-1]], following) > spacing or k == len(curve) - 1:
            kept.append(k)
    return curve[kept]


def _torus(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(wrap_angle(np.asarray(a) - b)).max(axis=-1)


def _follow(q: np.ndarray) -> np.ndarray:
    """Follow each branch by continuity.

    (8, N, 7): each branch followed from ψ = −π by the nearest configuration at each next
    ψ (greedy matching, closest pairs first).
    """
    n = q.shape[0]
    tracks = np.empty((BRANCHES, n, 7))
    tracks[:, 0] = q[0]
    for k in range(1, n):
        distance = _torus(tracks[:, k - 1][:, None, :], q[k][None, :, :])
        taken_rows, taken_cols = set(), set()
        for flat in np.argsort(distance, axis=None):
            row, col = divmod(int(flat), BRANCHES)
            if row in taken_rows or col in taken_cols:
                continue
            tracks[row, k] = q[k, col]
            taken_rows.add(row)
            taken_cols.add(col)
    return tracks


def _refine(
    arm: SRSArm, T: np.ndarray, psi: np.ndarray, track: np.ndarray, spacing: float
) -> np.ndarray:
    """Refine a track until its samples are close enough.

    ``track`` with configurations inserted (bisecting ψ, the branch chosen by nearness)
    until consecutive ones are at most ``spacing`` apart (or ψ steps fall below 1e-9).
    """
    out = [track[0]]
    for k in range(1, len(track)):
        stack = [(psi[k - 1], track[k - 1], psi[k], track[k])]
        while stack:
            left, q_left, right, q_right = stack.pop()
            if _torus(q_left, q_right) <= spacing or right - left < 1e-9:
                out.append(q_right)
                continue
            middle = 0.5 * (left + right)
            candidates, ok = arm.at(T, np.array([middle]))
            distance = _torus(candidates[0][ok[0]], q_left)
            q_middle = candidates[0][ok[0]][int(np.argmin(distance))]
            stack.append((middle, q_middle, right, q_right))
            stack.append((left, q_left, middle, q_middle))
    return np.array(out)
