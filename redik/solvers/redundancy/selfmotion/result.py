"""The result of :func:`redik.solvers.redundancy.explore_self_motion`.

Samples of a self-motion manifold.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from redik.core.exceptions import InvalidInput
from redik.core.result import Status
from redik.solvers.redundancy.selfmotion.index import SampleIndex, distance


@dataclasses.dataclass
class SelfMotion:
    """Samples of the self-motion manifold of one pose, as returned by :func:`explore_self_motion`.

    **best versus a local optimiser.** :meth:`best` is the optimum over the whole sampled
    manifold, to within the sample spacing; the QP core (a ``PostureTask`` below the pose
    task) and :func:`redik.solvers.redundancy.gradient_projection_ik` climb from one start to the
    nearest local optimum. Where a criterion has one optimum on the start's arc (distance to
    a posture) they agree to the sample spacing; where it has several (manipulability along a
    Panda arc), the local optimisers stop at the nearest and :meth:`best` finds the highest
    (``examples/selfmotion_panda.py`` compares them). Use the local optimisers to polish a
    sample, :meth:`best` to choose which basin to polish in.

    Attributes:
        T_target: The pose (4 × 4) every sample reaches.
        frame: Name of the frame placed at ``T_target``.
        joint_names: The robot's chain joints (columns of ``samples``).
        dimension: 0 (isolated solutions), 1 (curves) or 2 (surfaces): ``max(n − 6, 0)``.
        spacing: Largest joint-space distance between neighbouring samples.
        samples: N × n configurations. A 1-D component's rows are in order along the curve.
        component: Component label (0, 1, …) of each sample: an arc (1-D) or a patch (2-D,
            samples joined by neighbours at most ``spacing`` apart) inside the limits.
        position_error: ``‖p_d − p‖`` (m) of each sample.
        rotation_error: ``angle(Rᵀ R_d)`` (rad) of each sample.
        criteria: Per-sample values of each criterion, by name (see
            :mod:`redik.solvers.redundancy.scoring`).
        maximize: For each criterion, True when larger is better.
        closed: Per component: True for a closed loop (1-D only).
        ends: Per component, why tracing stopped at each end: ``"closed"``,
            ``"joint_limit"``, ``"max_samples"`` or ``"stalled"`` (empty for 0-D and 2-D).
        seeds: The IK solutions the exploration started from.
        periodic: Mask of the joints whose angles are compared modulo 2π (the robot's
            :attr:`~redik.Robot.periodic`).
        elapsed: Wall time of the exploration (s).
        starts: Random starts used for seeding.
        status: A :class:`redik.Status`: ``CONVERGED`` (the components found were sampled to
            the end), ``MAX_ITERATIONS`` (``max_samples`` ran out first, the manifold may be
            incomplete), ``UNREACHABLE`` (no start reached the pose: no sample) or ``LIMITS``
            (the pose is reached only outside the joint limits: no sample).
        message: Why, in words, when the status is not ``"converged"``.
        closest_position_error: When no start reached the pose, the position error (m) of
            the start that came closest (by the norm of the pose error); None otherwise.
        closest_rotation_error: The rotation error (rad) of that start; None otherwise.
    """

    T_target: np.ndarray
    frame: str
    joint_names: tuple[str, ...]
    dimension: int
    spacing: float
    samples: np.ndarray
    component: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    criteria: dict[str, np.ndarray]
    maximize: dict[str, bool]
    closed: np.ndarray
    ends: list[tuple[str, ...]]
    seeds: np.ndarray
    periodic: np.ndarray
    elapsed: float
    starts: int
    status: Status = Status.CONVERGED
    message: str = ""
    closest_position_error: float | None = None
    closest_rotation_error: float | None = None

    def __post_init__(self) -> None:
        self.status = Status.coerce(self.status)

    @property
    def success(self) -> bool:
        """True when at least one sample reaches the pose inside the joint limits."""
        return len(self.samples) > 0

    @property
    def n_components(self) -> int:
        """Number of connected components found."""
        return len(self.closed)

    def __len__(self) -> int:
        return len(self.samples)

    def component_samples(self, index: int) -> np.ndarray:
        """The samples of one component (in curve order for 1-D)."""
        return self.samples[self.component == index]

    def best_index(self, criterion: str) -> int:
        """Index of the best sample by ``criterion`` (e.g. ``"manipulability"``)."""
        if criterion not in self.criteria:
            raise InvalidInput(
                f"unknown criterion {criterion!r}; this exploration scored {list(self.criteria)}"
            )
        if len(self.samples) == 0:
            raise InvalidInput("the exploration found no sample")
        values = self.criteria[criterion]
        return int(np.argmax(values) if self.maximize[criterion] else np.argmin(values))

    def best(self, criterion: str) -> np.ndarray:
        """The best sample by ``criterion``: the (sampled) optimum over the whole manifold."""
        return self.samples[self.best_index(criterion)].copy()

    def distance_to(self, q: np.ndarray) -> np.ndarray:
        """Joint-space distance from each row of ``q`` (… × n) to the nearest sample."""
        q = np.atleast_2d(np.asarray(q, dtype=float))
        index = SampleIndex(self.periodic, self.samples.shape[1])
        index.extend(self.samples)
        return np.array([index.nearest(x) for x in q])

    def walk(self, component: int = 0) -> np.ndarray:
        """Indices of a path through one component, consecutive samples ≤ ``spacing`` apart.

        A 1-D component is walked in curve order (once around a loop). A 2-D patch is crossed
        along the shortest path in the neighbour graph between two samples far apart (a
        double sweep of Dijkstra's algorithm); 0-D components are single points.
        """
        members = np.flatnonzero(self.component == component)
        if self.dimension < 2 or len(members) < 3:
            return members
        points = self.samples[members]
        index = SampleIndex(self.periodic, points.shape[1])
        index.extend(points)
        pairs = index.pairs(1.01 * self.spacing)
        lengths = np.array([distance(points[i], points[j], self.periodic) for i, j in pairs])
        graph = coo_matrix(
            (lengths, (pairs[:, 0], pairs[:, 1])), shape=(len(points), len(points))
        ).tocsr()
        start = 0
        for _ in range(2):
            far, predecessors = dijkstra(
                graph, directed=False, indices=start, return_predecessors=True
            )
            reachable = np.isfinite(far)
            end = int(np.argmax(np.where(reachable, far, -1.0)))
            start, end = end, start
        far, predecessors = dijkstra(graph, directed=False, indices=start, return_predecessors=True)
        path = [end]
        while path[-1] != start and predecessors[path[-1]] >= 0:
            path.append(int(predecessors[path[-1]]))
        return members[np.array(path[::-1])]

    def summary(self) -> dict:
        """A JSON-serialisable summary: status, sizes, errors, components and the best samples.

        ``max_position_error`` and ``max_rotation_error`` are over the samples, None when
        there is none; ``closest_*_error`` say how near the best start came then.
        """
        best = {}
        for name, values in self.criteria.items():
            if len(values):
                k = self.best_index(name)
                best[name] = {"value": float(values[k]), "q": self.samples[k].tolist()}
        empty = len(self.samples) == 0
        return {
            "status": self.status.value,
            "message": self.message,
            "frame": self.frame,
            "joint_names": list(self.joint_names),
            "T_target": self.T_target.tolist(),
            "dimension": self.dimension,
            "spacing": self.spacing,
            "samples": len(self.samples),
            "components": [
                {
                    "samples": int(np.sum(self.component == k)),
                    "closed": bool(self.closed[k]),
                    "ends": list(self.ends[k]),
                }
                for k in range(self.n_components)
            ],
            "max_position_error": None if empty else float(np.max(self.position_error)),
            "max_rotation_error": None if empty else float(np.max(self.rotation_error)),
            "closest_position_error": self.closest_position_error,
            "closest_rotation_error": self.closest_rotation_error,
            "best": best,
            "seeds": len(self.seeds),
            "starts": self.starts,
            "elapsed_s": self.elapsed,
        }

    def save(self, path: str | Path) -> None:
        """Write the samples, labels, errors and criteria to an ``.npz`` file."""
        arrays: dict[str, Any] = {
            f"criterion_{name}": values for name, values in self.criteria.items()
        }
        np.savez_compressed(
            path,
            samples=self.samples,
            component=self.component,
            position_error=self.position_error,
            rotation_error=self.rotation_error,
            T_target=self.T_target,
            closed=self.closed,
            seeds=self.seeds,
            joint_names=np.array(self.joint_names),
            summary=np.array(json.dumps(self.summary())),
            **arrays,
        )
