"""The joint-space metric of the self-motion samples and a growing nearest-sample index.

Distances are Euclidean in joint space (rad and m), the differences of ``periodic`` joints
(hinges compared modulo 2π) wrapped to (−π, π]; :class:`SampleIndex` answers nearest-sample
and fixed-radius queries over a set that grows while a manifold is traced or covered.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy.spatial import cKDTree

from redik.lie import wrap_angle


def distances(a: np.ndarray, b: np.ndarray, periodic: np.ndarray) -> np.ndarray:
    """Row-wise :func:`_distance` of two B × n arrays."""
    delta = b - a
    delta[:, periodic] = wrap_angle(delta[:, periodic])
    return np.sqrt(np.einsum("ij,ij->i", delta, delta))


def spread(points: np.ndarray, exclusion: np.ndarray, periodic: np.ndarray) -> np.ndarray:
    """Indices of a subset of ``points`` (in order) that keep their distances.

    No kept point lies within its ``exclusion`` radius of an earlier one: greedy, each kept
    point blocking its neighbours.
    """
    if len(points) < 2:
        return np.arange(len(points))
    index = SampleIndex(periodic, points.shape[1])
    index.extend(points)
    pairs = index.pairs(float(exclusion.max()))
    pairs = pairs[distances(points[pairs[:, 0]], points[pairs[:, 1]], periodic)
                  <= exclusion[pairs[:, 1]]]  # fmt: skip
    neighbours: list[list[int]] = [[] for _ in points]
    for i, j in pairs[np.argsort(pairs[:, 0], kind="stable")]:
        neighbours[i].append(j)
    blocked = np.zeros(len(points), dtype=bool)
    kept = []
    for i in range(len(points)):
        if not blocked[i]:
            kept.append(i)
            blocked[neighbours[i]] = True
    return np.array(kept, dtype=int)


def distance(a: np.ndarray, b: np.ndarray, periodic: np.ndarray) -> float:
    """``‖b − a‖`` with the differences of ``periodic`` joints wrapped to (−π, π]."""
    delta = b - a
    if np.any(periodic):
        delta[periodic] = wrap_angle(delta[periodic])
    return float(np.linalg.norm(delta))


class SampleIndex:
    """Nearest-sample queries over a growing set.

    A KD-tree rebuilt as the set doubles, plus a brute-force tail. Periodic joints use the
    tree's toroidal metric (``boxsize``).
    """

    _BOX = 1e4  # box side of non-periodic coordinates: far larger than any joint range

    def __init__(self, periodic: np.ndarray, dof: int):
        self.periodic = np.asarray(periodic, dtype=bool)
        self._wrapped = bool(np.any(self.periodic))
        self._points = np.empty((256, dof))
        self._count = 0
        self._tree: cKDTree | None = None
        self._tree_count = 0

    def __len__(self) -> int:
        return self._count

    def _embed(self, q: np.ndarray) -> np.ndarray:
        """Coordinates inside the tree's box: periodic angles in ``[0, 2π)``.

        ``np.mod(x, 2π)`` rounds to exactly ``2π`` for ``x`` a hair below a multiple of
        ``2π`` (``q`` one ulp below ``−π``, as tracing through a hinge's ``±π`` produces);
        ``cKDTree`` rejects a coordinate equal to its box size, so that value wraps to 0.
        """
        if not self._wrapped:
            return q
        x = np.array(q, dtype=float) + 0.5 * self._BOX
        angles = np.mod(q[..., self.periodic] + np.pi, 2 * np.pi)
        x[..., self.periodic] = np.where(angles >= 2 * np.pi, 0.0, angles)
        return x

    def add(self, q: np.ndarray) -> None:
        """Add one sample."""
        self.extend(q[None])

    def extend(self, qs: np.ndarray | Sequence[np.ndarray]) -> None:
        """Add the rows of ``qs``."""
        x = self._embed(np.asarray(qs, dtype=float).reshape(-1, self._points.shape[1]))
        while self._count + len(x) > len(self._points):
            self._points = np.concatenate([self._points, np.empty_like(self._points)])
        self._points[self._count : self._count + len(x)] = x
        self._count += len(x)
        if self._count - self._tree_count > max(64, self._tree_count // 8):
            self._rebuild()

    def _rebuild(self) -> None:
        if self._tree is not None and self._tree_count == self._count:
            return
        boxsize = None
        if self._wrapped:
            boxsize = np.where(self.periodic, 2 * np.pi, self._BOX)
        self._tree = cKDTree(self._points[: self._count].copy(), boxsize=boxsize)
        self._tree_count = self._count

    def _tail_distances(self, x: np.ndarray) -> np.ndarray:
        delta = self._points[self._tree_count : self._count] - x
        if self._wrapped:
            delta[:, self.periodic] = wrap_angle(delta[:, self.periodic])
        return np.sqrt(np.einsum("ij,ij->i", delta, delta))

    def nearest(self, q: np.ndarray) -> float:
        """Distance to the nearest sample (inf when empty)."""
        x = self._embed(q)
        best = math.inf
        if self._tree is not None:
            best = float(self._tree.query(x, k=1)[0])
        tail = self._tail_distances(x)
        return min(best, float(np.min(tail))) if tail.size else best

    def within(self, q: np.ndarray, radius: float) -> bool:
        """True when a sample lies within ``radius`` of ``q``."""
        x = self._embed(q)
        tail = self._tail_distances(x)
        if tail.size and np.min(tail) <= radius:
            return True
        return self._tree is not None and bool(
            self._tree.query(x, k=1, distance_upper_bound=radius)[0] <= radius
        )

    def within_each(self, q: np.ndarray, radius: np.ndarray) -> np.ndarray:
        """:meth:`within` for every row of ``q`` (B × n), each with its own ``radius``."""
        if not len(q):
            return np.zeros(0, dtype=bool)
        self._rebuild()
        assert self._tree is not None
        distances, _ = self._tree.query(self._embed(q), k=1, distance_upper_bound=radius.max())
        return distances <= radius

    def pairs(self, radius: float) -> np.ndarray:
        """All index pairs ``(i, j)``, ``i < j``, closer than ``radius`` (an m × 2 array)."""
        self._rebuild()
        assert self._tree is not None
        return self._tree.query_pairs(radius, output_type="ndarray").reshape(-1, 2)
