"""Exploration of a self-motion manifold: seeds, then a component grown through each.

:func:`explore_self_motion` seeds by multi-start IK and grows isolated points, curves
(:mod:`.tracing`) or surfaces (:mod:`.covering`) through the seeds into a
:class:`~redik.solvers.redundancy.selfmotion.result.SelfMotion`. The method is in
:mod:`redik.solvers.redundancy.selfmotion`.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import Status
from redik.core.rotation_policy import as_pose
from redik.core.validate import integer, real_array
from redik.core.validate import seed as check_seed
from redik.solvers.redundancy.corrector import BatchCorrector, Corrector
from redik.solvers.redundancy.scoring import Criterion, default_criteria, evaluate_criteria
from redik.solvers.redundancy.selfmotion.covering import SurfaceCovering
from redik.solvers.redundancy.selfmotion.index import SampleIndex, distance
from redik.solvers.redundancy.selfmotion.result import SelfMotion
from redik.solvers.redundancy.selfmotion.tracing import CurveTracing

if TYPE_CHECKING:
    from redik.kinematics.robot import Frame, Robot

DEFAULT_SPACING = {0: 0.05, 1: 0.05, 2: 0.3}
"""Default ``spacing`` (joint-space distance between neighbouring samples) by dimension."""

MAX_DIMENSION = 2

_DISTINCT_SOLUTIONS = 1e-4  # isolated solutions closer than this (rad) are the same one


def explore_self_motion(
    robot: Robot,
    T_target: np.ndarray,
    frame: str | Frame | None = None,
    spacing: float | None = None,
    seed: int | None = None,
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
            (:mod:`redik.kinematics.robot`) is explored on its chain to ``frame``, the other joints
            held at their current values (``robot.chain(frame)``); the samples are the
            chain's joint values.
        T_target: The pose (4 × 4, world frame).
        frame: Site or body to place; default the end-effector.
        spacing: Largest joint-space distance between neighbouring samples; default
            :data:`DEFAULT_SPACING` for the dimension.
        seed: Seed of the random starts (an integer ≥ 0), or None for fresh entropy.
        n_starts: Random starts of the multi-start IK that seeds the components.
        initial: Extra seed configurations (k × n), e.g. the one ``T_target`` came from.
        max_samples: Budget of points over all components, counting those traced or
            covered outside the limits (which are not kept as samples).
        nominal: Posture of the ``posture_distance`` criterion; default ``robot.home``.
        criteria: Criteria to score samples by; default
            :func:`redik.solvers.redundancy.scoring.default_criteria`.
        exact: For a 7R arm with a spherical shoulder and wrist (iiwa type), take the curves
            from the closed-form arm-angle parameterisation
            (:func:`redik.solvers.analytic.srs.self_motion_curves`) instead of numerical tracing;
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
    n_starts = integer(n_starts, "n_starts")
    max_samples = integer(max_samples, "max_samples")
    rng = np.random.default_rng(check_seed(seed))
    extra = np.empty((0, robot.dof))
    if initial is not None:
        extra = np.atleast_2d(real_array(initial, "initial"))
        if extra.shape[1:] != (robot.dof,) or not np.all(np.isfinite(extra)):
            raise InvalidInput(f"initial must be finite k × {robot.dof} configurations")
    criteria = default_criteria(robot, nominal) if criteria is None else tuple(criteria)

    corrector = Corrector(robot, T_target, resolved)
    seeds, closest = _seed_solutions(corrector, extra, n_starts, rng)

    explorer = Explorer(corrector, dimension, spacing, max_samples)
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
    excess = 0.0 if seeds else _reach_excess(robot, resolved, T_target)
    status, message = _status(explorer, seeds, closest, len(extra) + n_starts, max_samples, excess)
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
    from redik.solvers.analytic.srs import self_motion_curves

    ee = robot.frame(None)  # UnknownFrame, naming the frames, on a robot without one
    if frame.name != ee.name:
        raise InvalidInput(
            f"exact=True follows the arm angle of the end-effector {ee.name!r}, "
            f"not of {frame.name!r}"
        )
    return self_motion_curves(robot, T_target, spacing=spacing)


def _status(
    explorer: Explorer,
    seeds: list[np.ndarray],
    closest: tuple[float | None, float | None],
    attempts: int,
    max_samples: int,
    excess: float,
) -> tuple[Status, str]:
    """The status and message of an exploration (see :class:`SelfMotion`).

    ``excess`` is how far the target lies beyond the chain's reach (0 within it).
    """
    if not seeds:
        if attempts == 0:
            return (
                Status.UNREACHABLE,
                "no start: n_starts is 0 and no initial configuration was given",
            )
        position, rotation = closest
        beyond = (
            f"the target is {excess:.3g} m beyond the reach of the chain from its first joint; "
            if excess > 0.0
            else ""
        )
        return Status.UNREACHABLE, (
            f"{beyond}none of {attempts} IK starts reached the pose (joint limits ignored); the "
            f"closest ended {position:.3g} m and {rotation:.3g} rad away"
        )
    if not explorer.parts:
        return Status.LIMITS, (
            f"{len(seeds)} IK solution(s) reach the pose, but the configurations through them "
            f"leave the joint limits everywhere: no sample inside the limits"
        )
    if any("max_samples" in ends for ends in explorer.ends) or explorer.budget <= 0:
        return Status.MAX_ITERATIONS, (
            f"max_samples={max_samples} ran out before every component was sampled"
        )
    return Status.CONVERGED, ""


def _reach_excess(robot: Robot, frame: Frame, T_target: np.ndarray) -> float:
    """How far the target lies beyond the chain's reach, as :func:`redik.solve_pose` tests it."""
    from redik.solvers.pose.frame import PoseFrame

    return PoseFrame(robot, frame).reach_excess(T_target[:3, 3])


# --------------------------------------------------------------------------------------
# Seeds


def _seed_solutions(
    corrector: Corrector,
    extra: np.ndarray,
    n_starts: int,
    rng: np.random.Generator,
) -> tuple[list[np.ndarray], tuple[float | None, float | None]]:
    """IK solutions of the pose, and the errors of the attempt that came closest.

    The starts are ``extra`` configurations, then ``n_starts`` random ones; the errors are
    the ``(position, rotation)`` of the attempt with the least ``‖e‖``.

    Each start is solved by :func:`redik.solve_pose` (damped least squares) *without* the
    joint limits — curves and surfaces are followed through the limits, so a solution
    outside them still leads to the arcs and patches inside. Every solution is polished by
    the corrector to the sample tolerances.
    """
    from redik.solvers.pose import solve_pose

    robot = corrector.robot
    seeds = []
    closest: tuple[float | None, float | None] = (None, None)
    closest_error = math.inf
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
# Growing components


class Explorer(CurveTracing, SurfaceCovering):
    """Grows components from seeds: isolated points, curves or surfaces.

    Curves are traced (:class:`CurveTracing`), surfaces covered (:class:`SurfaceCovering`).
    """

    def __init__(self, corrector: Corrector, dimension: int, spacing: float, max_samples: int):
        self.corrector = corrector
        self.dimension = dimension
        self.spacing = spacing
        self.max_samples = max_samples
        self.periodic = corrector.periodic
        self.index = SampleIndex(self.periodic, corrector.robot.dof)
        # Curves and surfaces are followed through the joint limits, on the torus of all hinge
        # angles.
        self.torus = np.asarray(corrector.robot.revolute, dtype=bool)
        self.traced = SampleIndex(self.torus, corrector.robot.dof)
        self.batch = BatchCorrector(corrector)
        self.parts: list[list[np.ndarray]] = []
        self.closed: list[bool] = []
        self.ends: list[tuple[str, ...]] = []
        self.exact_curves: list[np.ndarray] = []

    @property
    def budget(self) -> int:
        """Samples still allowed."""
        return self.max_samples - len(self.index) - len(self.traced)

    def distance(self, a: np.ndarray, b: np.ndarray) -> float:
        """The joint-space distance of two configurations, periodic joints modulo 2π."""
        return distance(a, b, self.periodic)

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

    def _append(
        self, part: np.ndarray | list[np.ndarray], closed: bool, ends: tuple[str, ...]
    ) -> None:
        self.index.extend(part)
        self.parts.append(list(part))
        self.closed.append(closed)
        self.ends.append(ends)
