r"""The self-motion manifold of a pose: every joint configuration that reaches it.

An arm with ``n`` joints reaches a pose (6 constraints) at generic points with a manifold
of dimension ``d = n − 6`` of configurations (∞^(n−6)): a set of closed curves for a 7R
arm (Burdick 1989, *On the inverse kinematics of redundant manipulators*), a surface for
an 8R arm, isolated points for a 6R arm. Joint limits cut curves into arcs and surfaces
into patches. :func:`explore_self_motion` samples that set:

1. **Seeds.** Inverse kinematics from many random starts (:func:`redik.solve_pose`) gives
   points on every component whose basin of attraction one start falls into; each is
   projected onto the pose to full precision by the corrector below.
2. **Corrector.** Gauss–Newton on the pose error with the minimum-norm step, which is
   orthogonal to ``ker J`` so a corrected prediction does not slide along the manifold
   (:mod:`redik.redundancy.corrector`: one point at a time, or a whole covering frontier at
   once with :mod:`redik.batch`'s vectorised kinematics).
3. **Tracing, d = 1** (pseudo-arclength continuation; Allgower & Georg, *Introduction to
   Numerical Continuation Methods*, ch. 2): predictor ``q + h t`` along the unit null
   vector ``t`` of ``J_b`` (its sign kept continuous, ``t_k · t_{k−1} > 0``), corrector back
   onto the pose, step ``h`` adapted so consecutive samples are at most ``spacing`` apart
   and the tangent turns by less than 45°. A branch ends when it returns within ``spacing``
   of its seed heading the same way (a closed loop), or at a joint limit: the last sample
   is then placed *on* the limit by correcting with the offending joint frozen there, and
   the other direction is traced from the seed.
4. **Covering, d = 2**: breadth-first continuation over the tangent plane (in the spirit of
   Henderson's multiple-parameter continuation, 2002), like the curves on the torus of hinge
   angles with the limits ignored, so that one seed anywhere on a surface reaches every
   patch the limits cut from it. Each generation of the frontier predicts points ``h`` away
   in six directions 60° apart of ``ker J``; the predictions not within ``0.75 h`` of a node
   are corrected together, and kept as nodes unless the corrector jumped or a node (or an
   earlier prediction of the same generation) already lies within ``0.75 h``. KD-trees on
   the torus stop re-covering. ``h = 0.7 · spacing`` inside and near the limits, up to
   0.6 rad far outside them (never more than 0.9 × the limit violation, so no patch inside
   the limits fits between coarse nodes). The nodes inside the limits are kept as samples,
   with a point placed *on* the limit between each inside node and its nearest outside
   neighbour; the samples fall into patches (components) joined by neighbours at most
   ``spacing`` apart.
5. **Components.** A seed farther than one step from every node traced or covered so far
   (on the torus) starts new components; one closer is already covered.

Distances are Euclidean in joint space (rad and m), angles of unlimited hinges compared
modulo 2π. A limited hinge whose range spans 2π or more (a UR5e's ±2π) has several
in-range angles for one point of the torus; the manifold is sampled at one of them
(:meth:`Corrector.shift_into_limits <redik.redundancy.corrector.Corrector.shift_into_limits>`),
not at every turn. Frames and twists follow :mod:`redik.conventions`.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, dijkstra
from scipy.spatial import cKDTree

from ..exceptions import InvalidInput
from ..lie import as_pose, real_array, wrap_angle
from ..result import STATUSES
from .corrector import BatchCorrector, Corrector
from .criteria import Criterion, default_criteria, evaluate_criteria

if TYPE_CHECKING:
    from ..robot import Frame, Robot

DEFAULT_SPACING = {0: 0.05, 1: 0.05, 2: 0.3}
"""Default ``spacing`` (joint-space distance between neighbouring samples) by dimension."""

MAX_DIMENSION = 2

_COVER_STEP = 0.7  # prediction distance of the surface covering, × spacing
_COVER_EXCLUSION = 0.75  # a prediction this close (× step) to a sample is already covered
_MIN_TANGENT_COSINE = math.cos(math.radians(45.0))
_MAX_STRIDE = 0.25  # rad: longest tracing step far outside the joint limits
_MAX_COVER_STRIDE = 0.6  # rad: longest covering step far outside the joint limits
_DISTINCT_SOLUTIONS = 1e-4  # isolated solutions closer than this (rad) are the same one


# --------------------------------------------------------------------------------------
# The result


@dataclasses.dataclass
class SelfMotion:
    """Samples of the self-motion manifold of one pose, as returned by :func:`explore_self_motion`.

    **best versus a local optimiser.** :meth:`best` is the optimum over the whole sampled
    manifold, to within the sample spacing; the QP core (a ``PostureTask`` below the pose
    task) and :func:`redik.redundancy.gradient_projection_ik` climb from one start to the
    nearest local optimum. ``examples/selfmotion_panda.py`` compares them on a Panda pose
    (three arcs, 324 samples at spacing 0.05). Distance to the home posture has one
    optimum on the start's arc: the QP reaches 1.6291 rad, gradient projection 1.6291, the
    best sample 1.6292 — sampling costs 1e-4 rad. Manipulability ``√det(JJᵀ)`` has three
    local maxima along the start's arc (0.1105, 0.0982, 0.1200): gradient projection from the
    start (0.0938) stops at the nearest, 0.0982, while the best sample has 0.1200 (22 %
    higher; another arc reaches the same value). Use the local optimisers to polish a
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
            :mod:`redik.redundancy.criteria`).
        maximize: For each criterion, True when larger is better.
        closed: Per component: True for a closed loop (1-D only).
        ends: Per component, why tracing stopped at each end: ``"closed"``,
            ``"joint_limit"``, ``"max_samples"`` or ``"stalled"`` (empty for 0-D and 2-D).
        seeds: The IK solutions the exploration started from.
        periodic: Mask of the joints whose angles are compared modulo 2π.
        elapsed: Wall time of the exploration (s).
        starts: Random starts used for seeding.
        status: One of :data:`redik.result.STATUSES`: ``"converged"`` (the components found
            were sampled to the end), ``"max_iterations"`` (``max_samples`` ran out first,
            the manifold may be incomplete), ``"unreachable"`` (no start reached the pose:
            no sample) or ``"limits"`` (the pose is reached only outside the joint limits:
            no sample).
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
    status: str = "converged"
    message: str = ""
    closest_position_error: float | None = None
    closest_rotation_error: float | None = None

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise InvalidInput(f"status must be one of {STATUSES}, got {self.status!r}")

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
        index = _SampleIndex(self.periodic, self.samples.shape[1])
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
        index = _SampleIndex(self.periodic, points.shape[1])
        index.extend(points)
        pairs = index.pairs(1.01 * self.spacing)
        lengths = np.array([_distance(points[i], points[j], self.periodic) for i, j in pairs])
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
            "status": self.status,
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
        arrays = {f"criterion_{name}": values for name, values in self.criteria.items()}
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


# --------------------------------------------------------------------------------------
# Exploration


def explore_self_motion(
    robot: Robot,
    T_target: np.ndarray,
    frame: str | Frame | None = None,
    spacing: float | None = None,
    seed: int | np.random.Generator | None = None,
    *,
    n_starts: int = 64,
    initial: np.ndarray | None = None,
    max_samples: int = 50_000,
    nominal: np.ndarray | None = None,
    criteria: tuple[Criterion, ...] | None = None,
    exact: bool = False,
) -> SelfMotion:
    """Sample every configuration of ``robot`` that places ``frame`` at ``T_target``.

    See the module docstring for the method.

    Args:
        robot: The arm; its joint limits bound the manifold. A whole-model robot
            (:mod:`redik.robot`) is explored on its chain to ``frame``, the other joints
            held at their current values (``robot.chain(frame)``); the samples are the
            chain's joint values.
        T_target: The pose (4 × 4, world frame).
        frame: Site or body to place; default the end-effector.
        spacing: Largest joint-space distance between neighbouring samples; default
            :data:`DEFAULT_SPACING` for the dimension.
        seed: Seed (or generator) of the random starts.
        n_starts: Random starts of the multi-start IK that seeds the components.
        initial: Extra seed configurations (k × n), e.g. the one ``T_target`` came from.
        max_samples: Budget of points over all components, counting those traced or
            covered outside the limits (which are not kept as samples).
        nominal: Posture of the ``posture_distance`` criterion; default ``robot.home``.
        criteria: Criteria to score samples by; default
            :func:`redik.redundancy.criteria.default_criteria`.
        exact: For a 7R arm with a spherical shoulder and wrist (iiwa type), take the curves
            from the closed-form arm-angle parameterisation
            (:func:`redik.analytic.srs.self_motion_curves`) instead of numerical tracing;
            every loop of the pose is then a component, whether or not a start found it.

    Returns:
        A :class:`SelfMotion`. An out-of-reach pose is an ordinary outcome, not an error: the
        result is empty with ``status="unreachable"`` (no start reached it; ``message`` and
        ``closest_*_error`` say how near the best came) or ``status="limits"`` (reached
        only outside the joint limits).

    Raises:
        InvalidPose: ``T_target`` is not a rigid transform.
        InvalidInput: the manifold would have more than two dimensions, or a bad argument.
        ModelError: ``exact=True`` on an arm that is not a 7R with a spherical shoulder and
            wrist.
    """
    started = time.perf_counter()
    if not robot.is_chain:
        robot, frame = robot.chain(frame), None
    T_target = as_pose(T_target, "T_target")
    resolved = robot.frame(frame)
    dimension = max(robot.dof - 6, 0)
    if dimension > MAX_DIMENSION:
        raise InvalidInput(
            f"{robot.name} has {robot.dof} joints: its self-motion manifolds have dimension "
            f"{dimension}; explore_self_motion samples dimensions up to {MAX_DIMENSION}"
        )
    spacing = DEFAULT_SPACING[dimension] if spacing is None else spacing
    if not (isinstance(spacing, int | float) and math.isfinite(spacing) and spacing > 0):
        raise InvalidInput(f"spacing must be a positive number, got {spacing!r}")
    for name, count in (("n_starts", n_starts), ("max_samples", max_samples)):
        if not (isinstance(count, int | np.integer) and not isinstance(count, bool) and count >= 0):
            raise InvalidInput(f"{name} must be a non-negative integer, got {count!r}")
    try:
        rng = np.random.default_rng(seed)
    except (TypeError, ValueError):
        raise InvalidInput(
            f"seed must be None, an integer ≥ 0 or a Generator, got {seed!r}"
        ) from None
    extra = np.empty((0, robot.dof))
    if initial is not None:
        extra = np.atleast_2d(real_array(initial, "initial"))
        if extra.shape[1:] != (robot.dof,) or not np.all(np.isfinite(extra)):
            raise InvalidInput(f"initial must be finite k × {robot.dof} configurations")
    criteria = default_criteria(robot, nominal) if criteria is None else tuple(criteria)

    corrector = Corrector(robot, T_target, resolved)
    seeds, closest = _seed_solutions(corrector, extra, n_starts, rng)

    explorer = _Explorer(corrector, dimension, spacing, max_samples)
    if exact:
        explorer.exact_curves = _exact_curves(robot, T_target, resolved, spacing)
        seeds = [curve[0] for curve in explorer.exact_curves] + seeds
    for q in seeds:
        explorer.add_component(q)

    samples = (
        np.array([q for part in explorer.parts for q in part])
        if explorer.parts
        else np.empty((0, robot.dof))
    )
    labels = np.concatenate(
        [np.full(len(part), k, dtype=int) for k, part in enumerate(explorer.parts)]
        or [np.empty(0, dtype=int)]
    )
    errors = np.array([corrector.pose_errors(q) for q in samples]).reshape(-1, 2)
    status, message = _status(explorer, seeds, closest, len(extra) + n_starts, max_samples)
    return SelfMotion(
        T_target=T_target.copy(),
        frame=resolved.name,
        joint_names=tuple(robot.joint_names),
        dimension=dimension,
        spacing=spacing,
        samples=samples,
        component=labels,
        position_error=errors[:, 0],
        rotation_error=errors[:, 1],
        criteria=evaluate_criteria(robot, samples, criteria, resolved),
        maximize={c.name: c.maximize for c in criteria},
        closed=np.array(explorer.closed, dtype=bool),
        ends=explorer.ends,
        seeds=np.array(seeds).reshape(-1, robot.dof),
        periodic=corrector.periodic.copy(),
        elapsed=time.perf_counter() - started,
        starts=n_starts,
        status=status,
        message=message,
        closest_position_error=None if seeds else closest[0],
        closest_rotation_error=None if seeds else closest[1],
    )


def _exact_curves(robot: Robot, T_target: np.ndarray, frame: Frame, spacing: float) -> list:
    """The closed-form self-motion loops (``exact=True``), for the robot's end-effector."""
    from ..analytic.srs import self_motion_curves

    if frame.name != robot.ee.name:
        raise InvalidInput(
            f"exact=True follows the arm angle of the end-effector {robot.ee.name!r}, "
            f"not of {frame.name!r}"
        )
    return self_motion_curves(robot, T_target, spacing=spacing)


def _torus_distance(curve: np.ndarray, q: np.ndarray) -> np.ndarray:
    return np.abs(wrap_angle(curve - q)).max(axis=1)


def _status(
    explorer: _Explorer,
    seeds: list[np.ndarray],
    closest: tuple[float | None, float | None],
    attempts: int,
    max_samples: int,
) -> tuple[str, str]:
    """The status and message of an exploration (see :class:`SelfMotion`)."""
    if not seeds:
        if attempts == 0:
            return "unreachable", "no start: n_starts is 0 and no initial configuration was given"
        position, rotation = closest
        return "unreachable", (
            f"none of {attempts} IK starts reached the pose (joint limits ignored); the closest "
            f"ended {position:.3g} m and {rotation:.3g} rad away"
        )
    if not explorer.parts:
        return "limits", (
            f"{len(seeds)} IK solution(s) reach the pose, but the configurations through them "
            f"leave the joint limits everywhere: no sample inside the limits"
        )
    if any("max_samples" in ends for ends in explorer.ends) or explorer.budget <= 0:
        return "max_iterations", (
            f"max_samples={max_samples} ran out before every component was sampled"
        )
    return "converged", ""


# --------------------------------------------------------------------------------------
# Seeds


def _seed_solutions(
    corrector: Corrector,
    extra: np.ndarray,
    n_starts: int,
    rng: np.random.Generator,
) -> tuple[list[np.ndarray], tuple[float | None, float | None]]:
    """IK solutions of the pose: from ``extra`` configurations, then ``n_starts`` random ones,
    and the ``(position, rotation)`` errors of the attempt that came closest (by ``‖e‖``).

    Each start is solved by :func:`redik.solve_pose` (damped least squares) *without* the
    joint limits — curves and surfaces are followed through the limits, so a solution
    outside them still leads to the arcs and patches inside. Every solution is polished by
    the corrector to the sample tolerances.
    """
    from ..pose_ik import solve_pose

    robot = corrector.robot
    seeds = []
    closest, closest_error = (None, None), math.inf
    for q0 in [*extra, *robot.random_q(rng, size=n_starts)]:
        result = solve_pose(
            robot, corrector.T_target, q0, restarts=0, respect_limits=False,
            frame=corrector.frame, pos_tol=1e-6, rot_tol=1e-5,
        )  # fmt: skip
        if result.error < closest_error:
            closest_error = result.error
            closest = (result.position_error, result.rotation_error)
        if not result.success:
            continue
        q, converged = corrector.correct(result.q)
        if converged:
            seeds.append(q)
    return seeds, closest


# --------------------------------------------------------------------------------------
# Tracing and covering


class _Explorer:
    """Grows components from seeds: isolated points, traced curves or covered surfaces."""

    def __init__(self, corrector: Corrector, dimension: int, spacing: float, max_samples: int):
        self.corrector = corrector
        self.dimension = dimension
        self.spacing = spacing
        self.max_samples = max_samples
        self.periodic = corrector.periodic
        self.index = _SampleIndex(self.periodic, corrector.robot.dof)
        # Curves and surfaces are followed through the joint limits, on the torus of all hinge
        # angles.
        self.torus = np.asarray(corrector.robot.revolute, dtype=bool)
        self.traced = _SampleIndex(self.torus, corrector.robot.dof)
        self.batch = BatchCorrector(corrector)
        self.parts: list[list[np.ndarray]] = []
        self.closed: list[bool] = []
        self.ends: list[tuple[str, ...]] = []
        self.exact_curves: list[np.ndarray] = []

    @property
    def budget(self) -> int:
        return self.max_samples - len(self.index) - len(self.traced)

    def distance(self, a: np.ndarray, b: np.ndarray) -> float:
        return _distance(a, b, self.periodic)

    def add_component(self, seed: np.ndarray) -> None:
        """Grow the component through ``seed`` (an IK solution, maybe outside the limits)."""
        if self.budget <= 0:
            return
        if self.dimension == 1:
            if not self.traced.within(seed, self._stride(seed)):
                self._add_curve(seed)
        elif self.dimension == 2:
            if not self.traced.within(seed, self._cover_strides(seed[None])[0]):
                self._cover_surface(seed)
        else:
            q = self.corrector.into_limits(seed)
            if q is not None and not self.index.within(q, _DISTINCT_SOLUTIONS):
                self._append(q[None], closed=False, ends=())

    def _append(self, part: np.ndarray | list[np.ndarray], closed: bool, ends: tuple) -> None:
        self.index.extend(part)
        self.parts.append(list(part))
        self.closed.append(closed)
        self.ends.append(ends)

    # 1-D ------------------------------------------------------------------------------

    def _add_curve(self, seed: np.ndarray) -> None:
        """Trace the whole curve through ``seed`` ignoring the limits, then keep the arcs
        inside them (each a component, its ends placed on the limits).

        Tracing through the limits finds every arc of a loop from one seed anywhere on it,
        so seeds outside the limits (most of them, for a Panda) still count.
        """
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
            self._append(shifted, closed, ends)
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
        """Insert points between consecutive samples outside the limits wherever the curve
        between them may dip inside: an arc shorter than a step would otherwise be missed.

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
        arc = [shifted[k] for k in run]
        end_reasons = []
        for side, outside, inside in ((0, before, run[0]), (1, after, run[-1])):
            if outside is None:
                end_reasons.append(ends[side] if len(ends) == 2 else ends[0])
                continue
            end_reasons.append("joint_limit")
            q_in = shifted[inside]
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
        """Largest step allowed from ``q``: ``spacing`` near or inside the limits, longer
        far outside them, where no sample is kept — a step shorter than the violation
        cannot enter the limits unseen."""
        return max(self.spacing, min(_MAX_STRIDE, 0.9 * self.corrector.limit_violation(q)))

    def _trace_branch(
        self, seed: np.ndarray, tangent: np.ndarray, budget: int
    ) -> tuple[list[np.ndarray], str]:
        """Predictor–corrector steps from ``seed`` along ``tangent`` until the curve returns to
        the seed or the budget runs out (distances on the torus of hinge angles)."""
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
            step = _distance(q, q_new, self.torus) if converged else math.inf
            if step > stride or step < 0.25 * h:
                h *= 0.5  # the corrector jumped or folded back
                continue
            t_new = corrector.tangent_basis(None, 1)[:, 0]
            if t_new @ t < 0.0:
                t_new = -t_new
            if t_new @ t < _MIN_TANGENT_COSINE:
                h *= 0.5  # too sharp a turn for this step
                continue
            closing = _distance(q_new, seed, self.torus)
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

    # 2-D ------------------------------------------------------------------------------

    def _cover_strides(self, q: np.ndarray) -> np.ndarray:
        """Prediction distance of the covering from each row of ``q``: ``0.7 · spacing`` near
        or inside the limits, longer far outside them, where no sample is kept — a surface
        point closer to ``q`` than its violation is outside the limits too."""
        violation = self.corrector.limit_violations(q)
        fine = _COVER_STEP * self.spacing
        return np.maximum(fine, np.minimum(_MAX_COVER_STRIDE, 0.9 * violation))

    def _cover_surface(self, seed: np.ndarray) -> None:
        """Cover the surface through ``seed`` on the torus of hinge angles, limits ignored,
        then keep its samples inside the limits (each patch a component) and add samples on
        the limits where the covering crossed them.

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
            steps = _distances(frontier[parents], corrected, self.torus)
            fit = (steps >= 0.25 * reach) & (steps <= reach / _COVER_STEP)
            corrected, reach = corrected[fit], reach[fit]
            exclusion = _COVER_EXCLUSION * np.minimum(reach, self._cover_strides(corrected))
            fresh = ~self.traced.within_each(corrected, exclusion)
            corrected, exclusion = corrected[fresh], exclusion[fresh]
            frontier = corrected[_spread(corrected, exclusion, self.torus)][: max(self.budget, 0)]
            self.traced.extend(frontier)
            nodes.append(frontier)
        self._keep_inside(np.concatenate(nodes))

    def _keep_inside(self, nodes: np.ndarray) -> None:
        """The covering's nodes inside the limits, with samples on the limits, split into
        patches: connected components of the graph joining samples ≤ ``spacing`` apart.

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
            index = _SampleIndex(self.periodic, nodes.shape[1])
            index.extend(kept)
            step = _COVER_STEP * self.spacing
            near = np.flatnonzero(~inside & (self.corrector.limit_violations(nodes) <= step))
            if len(kept):
                near = near[~index.within_each(shifted[near], np.full(len(near), 0.5 * step))]
            q_out = shifted[near]
            lower, upper = self.corrector.lower, self.corrector.upper
            on_limit, placed = self.batch.limit_points(np.clip(q_out, lower, upper), q_out)
            placed &= _distances(q_out, on_limit, self.periodic) <= self.spacing
            slivers = on_limit[placed]
            slivers = slivers[_spread(slivers, np.full(len(slivers), 0.5 * step), self.periodic)]
            kept = np.concatenate([kept, slivers])
        if not len(kept):
            return
        index = _SampleIndex(self.periodic, kept.shape[1])
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
        graph = _SampleIndex(self.torus, nodes.shape[1])
        graph.extend(nodes)
        pairs = graph.pairs(self.spacing)
        pairs = pairs[inside[pairs[:, 0]] != inside[pairs[:, 1]]]
        pairs = np.where(inside[pairs[:, :1]], pairs, pairs[:, ::-1])  # (inside, outside)
        lengths = _distances(nodes[pairs[:, 0]], nodes[pairs[:, 1]], self.torus)
        order = np.lexsort((lengths, pairs[:, 0]))
        pairs = pairs[order][np.unique(pairs[order, 0], return_index=True)[1]]
        q_in = shifted[pairs[:, 0]]
        delta = nodes[pairs[:, 1]] - nodes[pairs[:, 0]]
        delta[:, self.torus] = wrap_angle(delta[:, self.torus])
        on_limit, placed = self.batch.limit_points(q_in, q_in + delta)
        placed &= _distances(q_in, on_limit, self.periodic) <= self.spacing
        return on_limit[placed]


# --------------------------------------------------------------------------------------
# Joint-space metric and nearest-sample index


def _distances(a: np.ndarray, b: np.ndarray, periodic: np.ndarray) -> np.ndarray:
    """Row-wise :func:`_distance` of two B × n arrays."""
    delta = b - a
    delta[:, periodic] = wrap_angle(delta[:, periodic])
    return np.sqrt(np.einsum("ij,ij->i", delta, delta))


def _spread(points: np.ndarray, exclusion: np.ndarray, periodic: np.ndarray) -> np.ndarray:
    """Indices of a subset of ``points`` (in order) with no point within its ``exclusion``
    radius of an earlier one kept: greedy, each kept point blocking its neighbours."""
    if len(points) < 2:
        return np.arange(len(points))
    index = _SampleIndex(periodic, points.shape[1])
    index.extend(points)
    pairs = index.pairs(float(exclusion.max()))
    pairs = pairs[_distances(points[pairs[:, 0]], points[pairs[:, 1]], periodic)
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


def _distance(a: np.ndarray, b: np.ndarray, periodic: np.ndarray) -> float:
    """``‖b − a‖`` with the differences of ``periodic`` joints wrapped to (−π, π]."""
    delta = b - a
    if np.any(periodic):
        delta[periodic] = wrap_angle(delta[periodic])
    return float(np.linalg.norm(delta))


class _SampleIndex:
    """Nearest-sample queries over a growing set: a KD-tree rebuilt as the set doubles plus a
    brute-force tail. Periodic joints use the tree's toroidal metric (``boxsize``)."""

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
        self.extend(q[None])

    def extend(self, qs) -> None:
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
