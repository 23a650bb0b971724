r"""The rows of a :class:`~redik.limits.CollisionAvoidanceLimit`, compiled.

The rows are the limit's own (:mod:`redik.limits.collision_avoidance_limit`): for each pair
closer than the detection distance :math:`d_i`, at signed distance :math:`d` with nearest
points :math:`p_1, p_2` and unit normal :math:`n`,

.. math::

    n^\top \bigl(J_{p_1} - J_{p_2}\bigr) Δq \;\le\; ξ\, (d - d_s),

in pair order. The bounds that skip far pairs (bounding spheres, MuJoCo's broad phase
``geom_rbound``, then oriented bounding boxes ``geom_aabb``) and the rows themselves are
compiled, the point Jacobians taken from
``cdof`` (:func:`redik.qp.compiled.frames.point_jacobian`); the distance queries stay
MuJoCo's ``mj_geomDistance``, whose time is in its own C code.
"""

from __future__ import annotations

import math

import mujoco
import numba
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.compiled import COMPILE
from redik.kinematics.robot import Robot
from redik.limits import CollisionAvoidanceLimit
from redik.qp.compiled.frames import pack_chains, point_jacobian


@numba.njit(**COMPILE)
def _box_gap(
    centre_a: NDArray[np.float64],
    centre_b: NDArray[np.float64],
    R_a: NDArray[np.float64],
    R_b: NDArray[np.float64],
    half_a: NDArray[np.float64],
    half_b: NDArray[np.float64],
    axis: NDArray[np.float64],
) -> float:
    r"""The gap of two oriented boxes along ``axis`` (unit): a lower bound on their distance.

    The projections of the boxes onto ``axis`` are intervals of radius
    :math:`\sum_k h_k |R_{:,k}^\top a|` about the projected centres; the distance of two sets is at
    least the gap between their projections on any unit axis (the separating axis theorem's
    bound, Ericson, *Real-Time Collision Detection*, §4.4.1).
    """
    t = 0.0
    radius = 0.0
    for i in range(3):
        t += (centre_b[i] - centre_a[i]) * axis[i]
    for k in range(3):
        projection_a = R_a[0, k] * axis[0] + R_a[1, k] * axis[1] + R_a[2, k] * axis[2]
        projection_b = R_b[0, k] * axis[0] + R_b[1, k] * axis[1] + R_b[2, k] * axis[2]
        radius += half_a[k] * abs(projection_a) + half_b[k] * abs(projection_b)
    return abs(t) - radius


@numba.njit(**COMPILE)
def _boxes_apart(
    a: int,
    b: int,
    geom_xpos: NDArray[np.float64],
    geom_xmat: NDArray[np.float64],
    aabb: NDArray[np.float64],
    distance: float,
    work: NDArray[np.float64],
) -> bool:
    """Whether the bounding boxes of geoms ``a``, ``b`` are at least ``distance`` apart.

    Each geom's box is ``geom_aabb`` (centre and half-sizes in the geom's frame) placed by
    ``geom_xpos``, ``geom_xmat``; the axes tried are the six face normals and the line of the
    centres (:func:`_box_gap`). ``work`` is scratch (≥ 6).
    """
    R_a, R_b = geom_xmat[a].reshape(3, 3), geom_xmat[b].reshape(3, 3)
    centre_a, centre_b = work[0:3], work[3:6]
    for i in range(3):
        centre_a[i] = geom_xpos[a, i]
        centre_b[i] = geom_xpos[b, i]
        for k in range(3):
            centre_a[i] += R_a[i, k] * aabb[a, k]
            centre_b[i] += R_b[i, k] * aabb[b, k]
    half_a, half_b = aabb[a, 3:], aabb[b, 3:]
    axis = work[6:9]
    for i in range(3):
        axis[i] = centre_b[i] - centre_a[i]
    norm = math.sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2])
    if norm > 0.0:
        axis /= norm
        if _box_gap(centre_a, centre_b, R_a, R_b, half_a, half_b, axis) >= distance:
            return True
    for R in (R_a, R_b):
        for k in range(3):
            axis[0], axis[1], axis[2] = R[0, k], R[1, k], R[2, k]
            if _box_gap(centre_a, centre_b, R_a, R_b, half_a, half_b, axis) >= distance:
                return True
    return False


@numba.njit(**COMPILE)
def near_pairs(
    geom_xpos: NDArray[np.float64],
    geom_xmat: NDArray[np.float64],
    pairs: NDArray[np.int64],
    radii: NDArray[np.float64],
    bounded: NDArray[np.bool_],
    aabb: NDArray[np.float64],
    distance: float,
    candidates: NDArray[np.int64],
) -> int:
    """Write the pairs whose bounds are closer than ``distance`` into ``candidates``.

    A pair is skipped when its bounding spheres (MuJoCo's broad phase, ``geom_rbound``) or
    its bounding boxes (``geom_aabb``, :func:`_boxes_apart`) are at least ``distance`` apart:
    both contain the geoms (a mesh's convex hull, which ``mj_geomDistance`` measures), so the
    pair's distance is at least ``distance`` too and it gives no row.

    Args:
        geom_xpos: ``data.geom_xpos``.
        geom_xmat: ``data.geom_xmat``.
        pairs: The geom pairs (P × 2).
        radii: Per pair, the sum of the two ``geom_rbound``.
        bounded: Per pair, whether both geoms are bounded (a plane is not).
        aabb: ``model.geom_aabb``.
        distance: The distance below which a pair is a candidate.
        candidates: Written with the candidates' indices, ascending.

    Returns:
        The number of candidates.
    """
    work = np.empty(9)
    count = 0
    for i in range(pairs.shape[0]):
        a, b = pairs[i, 0], pairs[i, 1]
        if bounded[i]:
            dx = geom_xpos[a, 0] - geom_xpos[b, 0]
            dy = geom_xpos[a, 1] - geom_xpos[b, 1]
            dz = geom_xpos[a, 2] - geom_xpos[b, 2]
            if math.sqrt(dx * dx + dy * dy + dz * dz) - radii[i] >= distance:
                continue
            if _boxes_apart(a, b, geom_xpos, geom_xmat, aabb, distance, work):
                continue
        candidates[count] = i
        count += 1
    return count


@numba.njit(**COMPILE)
def _normal(
    fromto: NDArray[np.float64],
    d: float,
    centre_a: NDArray[np.float64],
    centre_b: NDArray[np.float64],
    normal: NDArray[np.float64],
) -> bool:
    """Write the unit normal from geom 1 to geom 2 (flipped when they penetrate).

    Touching geoms give no direction: the centres' then. ``mju_normalize3``'s arithmetic (a
    multiplication by the inverse norm).

    Returns:
        False when the centres coincide too (no row).
    """
    nx, ny, nz = fromto[3] - fromto[0], fromto[4] - fromto[1], fromto[5] - fromto[2]
    norm = math.sqrt(nx * nx + ny * ny + nz * nz)
    sign = -1.0 if d < 0.0 else 1.0
    if norm < 1e-12:
        nx, ny, nz = centre_b[0] - centre_a[0], centre_b[1] - centre_a[1], centre_b[2] - centre_a[2]
        norm = math.sqrt(nx * nx + ny * ny + nz * nz)
        sign = 1.0
        if norm < 1e-12:
            return False
    inverse = 1.0 / norm
    normal[0], normal[1], normal[2] = nx * inverse * sign, ny * inverse * sign, nz * inverse * sign
    return True


@numba.njit(**COMPILE)
def collision_rows(
    candidates: NDArray[np.int64],
    count: int,
    distances: NDArray[np.float64],
    fromto: NDArray[np.float64],
    pairs: NDArray[np.int64],
    geom_xpos: NDArray[np.float64],
    roots: NDArray[np.int64],
    chains: NDArray[np.int64],
    columns: NDArray[np.int64],
    lengths: NDArray[np.int64],
    cdof: NDArray[np.float64],
    subtree_com: NDArray[np.float64],
    settings: NDArray[np.float64],
    G: NDArray[np.float64],
    h: NDArray[np.float64],
    floor: NDArray[np.float64],
) -> int:
    """Write the rows of the candidates closer than the detection distance (module docstring).

    Args:
        candidates: The candidate pairs (:func:`near_pairs`), ascending.
        count: How many.
        distances: Per pair, its signed distance (candidates only).
        fromto: Per pair, its nearest points ``(p₁, p₂)`` (candidates only).
        pairs: The geom pairs (P × 2).
        geom_xpos: ``data.geom_xpos``.
        roots: Per geom of each pair (2P), the root body of its tree.
        chains: Per geom of each pair, the dof chain of its body.
        columns: Their robot columns.
        lengths: Their lengths.
        cdof: ``data.cdof``.
        subtree_com: ``data.subtree_com``.
        settings: ``(d_s, d_i, ξ)``.
        G: Written: the rows, first ones (≥ P × n).
        h: Written: their bounds.
        floor: Per pair, written: ``min(d_s, d)`` for a row, ``d_s`` else (what
            :meth:`~redik.limits.CollisionAvoidanceLimit.admits` holds a pair to).

    Returns:
        The number of rows.
    """
    minimum, detection, gain = settings[0], settings[1], settings[2]
    n = G.shape[1]
    J1 = np.empty((6, n))
    J2 = np.empty((6, n))
    normal = np.empty(3)
    floor[:] = minimum
    rows = 0
    for c in range(count):
        i = candidates[c]
        d = distances[i]
        if d >= detection:
            continue
        floor[i] = min(minimum, d)
        if not _normal(fromto[i], d, geom_xpos[pairs[i, 0]], geom_xpos[pairs[i, 1]], normal):
            continue
        a, b = 2 * i, 2 * i + 1
        point_jacobian(cdof, subtree_com, roots[a], fromto[i, :3], chains[a], columns[a],
                       lengths[a], J1)  # fmt: skip
        point_jacobian(cdof, subtree_com, roots[b], fromto[i, 3:], chains[b], columns[b],
                       lengths[b], J2)  # fmt: skip
        for j in range(n):
            G[rows, j] = (
                normal[0] * (J1[0, j] - J2[0, j])
                + normal[1] * (J1[1, j] - J2[1, j])
                + normal[2] * (J1[2, j] - J2[2, j])
            )
        h[rows] = gain * (d - minimum)
        rows += 1
    return rows


class CollisionRows:
    """The compiled rows of one bound :class:`~redik.limits.CollisionAvoidanceLimit`.

    Args:
        limit: The limit, bound to ``robot``.
        robot: The robot.
        column_of: Per model dof, its robot column, −1 for a dof the robot holds.

    Attributes:
        size: The number of pairs (the most rows it can give).
    """

    def __init__(
        self, limit: CollisionAvoidanceLimit, robot: Robot, column_of: NDArray[np.int64]
    ) -> None:
        model = robot.model
        self.limit = limit
        self._model = model
        self._data = robot.state.data
        self.pairs = np.ascontiguousarray(limit.pairs, dtype=np.int64)
        self.size = len(self.pairs)
        rbound = model.geom_rbound
        self._radii = rbound[self.pairs[:, 0]] + rbound[self.pairs[:, 1]]
        self._bounded = (rbound[self.pairs[:, 0]] > 0.0) & (rbound[self.pairs[:, 1]] > 0.0)
        bodies = [int(model.geom_bodyid[g]) for g in self.pairs.reshape(-1)]
        self._roots = np.array([int(model.body_rootid[b]) for b in bodies], dtype=np.int64)
        self._chains, self._columns, self._lengths = pack_chains(model, bodies, column_of)
        self._settings = np.array([limit.minimum_distance, limit.detection_distance, limit.gain])
        self._candidates = np.zeros(self.size, dtype=np.int64)
        self._distances = np.zeros(self.size)
        self._fromto = np.zeros((self.size, 6))
        self._pair_list = [(int(a), int(b)) for a, b in self.pairs]

    def rows_into(self, G: NDArray[np.float64], h: NDArray[np.float64]) -> int:
        """Write the active rows at the robot's current kinematics into ``G``, ``h``.

        Args:
            G: The rows' buffer (≥ size × n).
            h: Their bounds.

        Returns:
            The number of rows written.
        """
        data, model, detection = self._data, self._model, self._settings[1]
        count = near_pairs(
            data.geom_xpos, data.geom_xmat, self.pairs, self._radii, self._bounded,
            model.geom_aabb, detection, self._candidates,
        )  # fmt: skip
        distances, fromto, pair_list = self._distances, self._fromto, self._pair_list
        for i in self._candidates[:count].tolist():
            a, b = pair_list[i]
            distances[i] = mujoco.mj_geomDistance(model, data, a, b, detection, fromto[i])
        return collision_rows(
            self._candidates, count, distances, fromto, self.pairs, data.geom_xpos, self._roots,
            self._chains, self._columns, self._lengths, data.cdof, data.subtree_com,
            self._settings, G, h, self.limit.floor,
        )  # fmt: skip
