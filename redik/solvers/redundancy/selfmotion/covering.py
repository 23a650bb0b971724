r"""Surface covering (self-motion of dimension 2, an 8R arm): breadth-first continuation.

In the spirit of Henderson's multiple-parameter continuation (2002): each generation of the
frontier predicts points ``h`` away in six directions 60° apart of ``ker J``, corrects the
ones not yet covered together (:class:`~redik.solvers.redundancy.corrector.BatchCorrector`), and
keeps them as nodes unless the corrector jumped or a node already lies within ``0.75 h``;
the surface is covered on the torus of hinge angles, limits ignored, then its nodes inside
the limits are kept, with points placed on the limits, and split into patches. See
:mod:`redik.solvers.redundancy.selfmotion`.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from redik.lie import wrap_angle
from redik.solvers.redundancy.selfmotion.index import SampleIndex, distances, spread
from redik.solvers.redundancy.selfmotion.part import ExplorerPart

_COVER_STEP = 0.7  # prediction distance of the surface covering, × spacing
_COVER_EXCLUSION = 0.75  # a prediction this close (× step) to a sample is already covered
_MAX_COVER_STRIDE = 0.6  # rad: longest covering step far outside the joint limits


class SurfaceCovering(ExplorerPart):
    """The 2-D growth of an :class:`~redik.solvers.redundancy.selfmotion.explore.Explorer`.

    This class is mixed into the explorer: it reads the explorer's corrector, batch corrector,
    spacing, indices and budget, and appends components through ``_append``.
    """

    def _cover_strides(self, q: np.ndarray) -> np.ndarray:
        """Prediction distance of the covering from each row of ``q``.

        ``0.7 · spacing`` near or inside the limits, longer far outside them, where no sample is
        kept — a surface point closer to ``q`` than its violation is outside the limits too.
        """
        violation = self.corrector.limit_violations(q)
        fine = _COVER_STEP * self.spacing
        return np.maximum(fine, np.minimum(_MAX_COVER_STRIDE, 0.9 * violation))

    def _cover_surface(self, seed: np.ndarray) -> None:
        """Cover the surface through ``seed``, then keep what lies inside the limits.

        The covering runs on the torus of hinge angles, limits ignored; its samples inside the
        limits are kept (each patch a component), with samples on the limits where the
        covering crossed them.

        Breadth-first, one generation of the frontier at a time: every node predicts six
        points ``h`` away in its tangent plane; those farther than ``0.75 h`` from every node
        are corrected together (:class:`BatchCorrector`) and kept as new nodes unless the
        corrector jumped (a step outside ``[h/4, h/0.7]``) or a node already lies within
        ``0.75 h``.
        """
        batch, n = self.batch, self.corrector.robot.dof
        angles = np.arange(6) * (np.pi / 3.0)
        directions = np.stack([np.cos(angles), np.sin(angles)])  # 2 × 6, in the tangent plane
        self.traced.add(seed)
        frontier = seed[None]
        nodes = [frontier]
        while len(frontier) and self.budget > 0:
            strides = self._cover_strides(frontier)
            bases = batch.tangent_bases(frontier, 2)
            predictions = frontier[:, None] + strides[:, None, None] * np.einsum(
                "bnk,kd->bdn", bases, directions
            )
            parents = np.repeat(np.arange(len(frontier)), len(angles))
            predictions = predictions.reshape(-1, n)
            fresh = ~self.traced.within_each(predictions, _COVER_EXCLUSION * strides[parents])
            corrected, converged = batch.correct(predictions[fresh])
            parents = parents[fresh][converged]
            corrected = corrected[converged]
            reach = strides[parents]
            steps = distances(frontier[parents], corrected, self.torus)
            fit = (steps >= 0.25 * reach) & (steps <= reach / _COVER_STEP)
            corrected, reach = corrected[fit], reach[fit]
            exclusion = _COVER_EXCLUSION * np.minimum(reach, self._cover_strides(corrected))
            fresh = ~self.traced.within_each(corrected, exclusion)
            corrected, exclusion = corrected[fresh], exclusion[fresh]
            frontier = corrected[spread(corrected, exclusion, self.torus)][: max(self.budget, 0)]
            self.traced.extend(frontier)
            nodes.append(frontier)
        self._keep_inside(np.concatenate(nodes))

    def _keep_inside(self, nodes: np.ndarray) -> None:
        """The covering's nodes inside the limits, with samples on the limits, in patches.

        A patch is a connected component of the graph joining samples ≤ ``spacing`` apart.

        A limit sample is placed where the surface crosses a limit between an inside node
        and its nearest outside neighbour, and from every outside node near the limits with
        no sample close by — a sliver of the surface inside the limits, narrower than a
        step, may lie between such nodes.
        """
        shifted, inside = self.corrector.shift_into_limits(nodes)
        kept = shifted[inside]
        if not inside.all():
            if inside.any():
                kept = np.concatenate([kept, self._crossings(nodes, shifted, inside)])
            index = SampleIndex(self.periodic, nodes.shape[1])
            index.extend(kept)
            step = _COVER_STEP * self.spacing
            near = np.flatnonzero(~inside & (self.corrector.limit_violations(nodes) <= step))
            if len(kept):
                near = near[~index.within_each(shifted[near], np.full(len(near), 0.5 * step))]
            q_out = shifted[near]
            lower, upper = self.corrector.lower, self.corrector.upper
            on_limit, placed = self.batch.limit_points(np.clip(q_out, lower, upper), q_out)
            placed &= distances(q_out, on_limit, self.periodic) <= self.spacing
            slivers = on_limit[placed]
            slivers = slivers[spread(slivers, np.full(len(slivers), 0.5 * step), self.periodic)]
            kept = np.concatenate([kept, slivers])
        if not len(kept):
            return
        index = SampleIndex(self.periodic, kept.shape[1])
        index.extend(kept)
        pairs = index.pairs(1.01 * self.spacing)
        _, labels = connected_components(
            coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(kept),) * 2),
            directed=False,
        )
        for label in range(labels.max() + 1):
            self._append(kept[labels == label], closed=False, ends=())

    def _crossings(self, nodes: np.ndarray, shifted: np.ndarray, inside: np.ndarray) -> np.ndarray:
        """Points on the limits between each inside node and its nearest outside neighbour."""
        graph = SampleIndex(self.torus, nodes.shape[1])
        graph.extend(nodes)
        pairs = graph.pairs(self.spacing)
        pairs = pairs[inside[pairs[:, 0]] != inside[pairs[:, 1]]]
        pairs = np.where(inside[pairs[:, :1]], pairs, pairs[:, ::-1])  # (inside, outside)
        lengths = distances(nodes[pairs[:, 0]], nodes[pairs[:, 1]], self.torus)
        order = np.lexsort((lengths, pairs[:, 0]))
        pairs = pairs[order][np.unique(pairs[order, 0], return_index=True)[1]]
        q_in = shifted[pairs[:, 0]]
        delta = nodes[pairs[:, 1]] - nodes[pairs[:, 0]]
        delta[:, self.torus] = wrap_angle(delta[:, self.torus])
        on_limit, placed = self.batch.limit_points(q_in, q_in + delta)
        placed &= distances(q_in, on_limit, self.periodic) <= self.spacing
        return on_limit[placed]
