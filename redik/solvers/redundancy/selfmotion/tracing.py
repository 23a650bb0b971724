r"""Curve tracing (self-motion of dimension 1, a 7R arm): pseudo-arclength continuation.

Predictor ``q + h t`` along the unit null vector ``t`` of ``J_b`` (its sign kept continuous,
``t_k · t_{k−1} > 0``), corrector back onto the pose, step ``h`` adapted so consecutive
samples are at most ``spacing`` apart and the tangent turns by less than 45° (Allgower &
Georg, *Introduction to Numerical Continuation Methods*, ch. 2). A branch ends when it
returns within ``spacing`` of its seed heading the same way (a closed loop), or at a joint
limit: the curve is traced through the limits on the torus of hinge angles, then cut into
the arcs inside them, each end placed *on* the limit. See
:mod:`redik.solvers.redundancy.selfmotion`.
"""

from __future__ import annotations

import math

import numpy as np

from redik.lie import wrap_angle
from redik.solvers.redundancy.selfmotion.index import distance
from redik.solvers.redundancy.selfmotion.part import ExplorerPart

_MIN_TANGENT_COSINE = math.cos(math.radians(45.0))
_MAX_STRIDE = 0.25  # rad: longest tracing step far outside the joint limits


def _torus_distance(curve: np.ndarray, q: np.ndarray) -> np.ndarray:
    return np.abs(wrap_angle(curve - q)).max(axis=1)


class CurveTracing(ExplorerPart):
    """The 1-D growth of an :class:`~redik.solvers.redundancy.selfmotion.explore.Explorer`.

    This class is mixed into the explorer: it reads the explorer's corrector, spacing, indices
    and budget, and appends components through ``_append``.
    """

    def _add_curve(self, seed: np.ndarray) -> None:
        """Trace the whole curve through ``seed``, then keep the arcs inside the limits.

        The tracing ignores the limits; each arc inside them is a component, its ends placed
        on the limits.

        Tracing through the limits finds every arc of a loop from one seed anywhere on it,
        so seeds outside the limits (most of them, for a Panda) still count.
        """
        ends: tuple[str, ...]
        if self.exact_curves:
            nearest = min(self.exact_curves, key=lambda c: _torus_distance(c, seed).min())
            curve, closed, ends = list(nearest), True, ("closed",)
        else:
            curve, closed, ends = self._trace_curve(seed)
        self.traced.extend(curve)
        curve = self._refine_near_limits(curve, closed)
        shifted = [self.corrector.into_limits(q) for q in curve]
        valid = np.array([q is not None for q in shifted])
        if valid.all():
            self._append([q for q in shifted if q is not None], closed, ends)
            return
        n = len(curve)
        # Walk a loop from just after an invalid sample, so that no arc wraps around the end.
        first = int(np.flatnonzero(~valid)[0]) + 1 if closed else 0
        order = [(first + k) % n for k in range(n)]
        runs: list[list[int]] = []
        for position, k in enumerate(order):
            if valid[k]:
                if position == 0 or not valid[order[position - 1]]:
                    runs.append([])
                runs[-1].append(position)
        for run in runs:
            before = order[run[0] - 1] if run[0] > 0 else (order[-1] if closed else None)
            after = order[run[-1] + 1] if run[-1] + 1 < n else (order[0] if closed else None)
            self._append_arc(curve, shifted, [order[p] for p in run], before, after, ends)

    def _refine_near_limits(self, curve: list[np.ndarray], closed: bool) -> list[np.ndarray]:
        """Insert points where the curve between two samples outside the limits may dip inside.

        An arc shorter than a step would otherwise be missed.

        The limit violation changes by at most the distance travelled, so the curve between
        samples ``a`` and ``b`` (length ≈ ``‖b − a‖``) stays outside when
        ``violation(a) + violation(b) > ‖b − a‖``; otherwise the pair is bisected.
        """
        violation = self.corrector.limit_violation
        refined: list[np.ndarray] = []
        pairs = len(curve) if closed else len(curve) - 1
        for k in range(len(curve)):
            refined.append(curve[k])
            if k < pairs:
                refined.extend(self._bisect(curve[k], curve[(k + 1) % len(curve)], violation, 0))
        return refined

    def _bisect(self, a: np.ndarray, b: np.ndarray, violation, depth: int) -> list[np.ndarray]:
        va, vb = violation(a), violation(b)
        delta = b - a
        delta[self.torus] = wrap_angle(delta[self.torus])
        if va == 0.0 or vb == 0.0 or va + vb > np.linalg.norm(delta) or depth >= 10:
            return []
        middle, converged = self.corrector.correct(a + 0.5 * delta)
        if not converged:
            return []
        if violation(middle) == 0.0:
            return [middle]
        return [
            *self._bisect(a, middle, violation, depth + 1),
            middle,
            *self._bisect(middle, b, violation, depth + 1),
        ]

    def _append_arc(
        self,
        curve: list[np.ndarray],
        shifted: list[np.ndarray | None],
        run: list[int],
        before: int | None,
        after: int | None,
        ends: tuple[str, ...],
    ) -> None:
        """One arc inside the limits, extended onto the limit at each cut end."""
        arc = [q for q in (shifted[k] for k in run) if q is not None]  # a run is all valid
        end_reasons = []
        for side, outside, inside, q_in in (
            (0, before, run[0], arc[0]),
            (1, after, run[-1], arc[-1]),
        ):
            if outside is None:
                end_reasons.append(ends[side] if len(ends) == 2 else ends[0])
                continue
            end_reasons.append("joint_limit")
            q_out = curve[outside] + (q_in - curve[inside])  # the same 2π shifts
            q_end = self.corrector.limit_point(q_in, q_out)
            if q_end is not None and self.distance(q_in, q_end) <= self.spacing:
                if side == 0:
                    arc.insert(0, q_end)
                else:
                    arc.append(q_end)
        self._append(arc, closed=False, ends=tuple(end_reasons))

    def _trace_curve(self, seed: np.ndarray) -> tuple[list[np.ndarray], bool, tuple[str, ...]]:
        tangent = self.corrector.tangent_basis(seed, 1)[:, 0]
        forward, end = self._trace_branch(seed, tangent, self.budget - 1)
        if end == "closed":
            return [seed, *forward], True, ("closed",)
        backward, other_end = self._trace_branch(seed, -tangent, self.budget - 1 - len(forward))
        return [*backward[::-1], seed, *forward], False, (other_end, end)

    def _stride(self, q: np.ndarray) -> float:
        """Largest step allowed from ``q``.

        ``spacing`` near or inside the limits, longer far outside them, where no sample is kept — a
        step shorter than the violation cannot enter the limits unseen.
        """
        return max(self.spacing, min(_MAX_STRIDE, 0.9 * self.corrector.limit_violation(q)))

    def _trace_branch(
        self, seed: np.ndarray, tangent: np.ndarray, budget: int
    ) -> tuple[list[np.ndarray], str]:
        """Predictor–corrector steps from ``seed`` along ``tangent``.

        Until the curve returns to the seed or the budget runs out (distances on the torus of
        hinge angles).
        """
        corrector, spacing = self.corrector, self.spacing
        points: list[np.ndarray] = []
        q, t = seed, tangent
        stride = self._stride(q)
        h = 0.9 * stride
        min_step = 1e-4 * spacing
        # The loop closes when the curve, having left the seed's neighbourhood, comes back.
        neighbourhood = stride
        departed = False
        while len(points) < budget:
            if h < min_step:
                return points, "stalled"
            q_new, converged = corrector.correct(q + h * t)
            step = distance(q, q_new, self.torus) if converged else math.inf
            if step > stride or step < 0.25 * h:
                h *= 0.5  # the corrector jumped or folded back
                continue
            t_new = corrector.tangent_basis(None, 1)[:, 0]
            if t_new @ t < 0.0:
                t_new = -t_new
            if t_new @ t < _MIN_TANGENT_COSINE:
                h *= 0.5  # too sharp a turn for this step
                continue
            closing = distance(q_new, seed, self.torus)
            departed = departed or closing > 2.0 * neighbourhood
            if departed and closing <= max(stride, neighbourhood) and t_new @ tangent > 0.0:
                if closing > 1e-3 * spacing:  # else q_new is the seed again
                    points.append(q_new)
                return points, "closed"
            points.append(q_new)
            q, t = q_new, t_new
            stride = self._stride(q)
            h = min(stride, h * min(2.0, max(0.5, 0.9 * stride / step)))
        return points, "max_samples"
