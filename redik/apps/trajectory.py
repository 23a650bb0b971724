r"""Cartesian paths and IK along them: warm-started, continuity-checked joint trajectories.

A :class:`CartesianPath` passes through timed waypoint poses. Between two waypoints the
position moves on the straight line and the orientation by SLERP (constant angular speed
about one axis), both driven by the same path parameter ``s(τ)`` (Modern Robotics §9.2):

.. math::

    T(t) = \bigl(R_a \exp(s\,\log(R_a^T R_b)),\; (1 - s)\,p_a + s\,p_b\bigr), \qquad
    τ = \frac{t - t_a}{t_b - t_a}

with the time scaling ``s(τ) = τ`` (``"linear"``, constant speed), ``3τ² − 2τ³``
(``"cubic"``, zero velocity at the waypoints) or ``10τ³ − 15τ⁴ + 6τ⁵`` (``"quintic"``, zero
velocity and acceleration: rest-to-rest motion with bounded jerk), MR eqs. (9.9)–(9.13).

:func:`follow_path` samples the path at a rate and solves IK at every sample, starting from
the previous sample's solution. On a smooth path the previous solution is within the
quadratic-convergence basin of the next, so a Newton-type solver needs one or two
iterations per point; the result reports them. It then checks the joint trajectory:

* **continuity** — the largest joint change between consecutive samples,
  ``max_k ‖q_{k+1} − q_k‖_∞``; a jump above ``jump_tol`` means the solver switched branch
  (or the path crossed a singularity too fast) and the trajectory is flagged discontinuous;
* **singular crossings** — intervals where ``σ_min(J)`` of the 6 × n world Jacobian
  (:mod:`redik.core.conventions`) falls below ``singular_tol``;
* **limit contacts** — intervals where a joint lies within ``limit_margin`` of a limit.

Poses, units and the error metrics are those of :mod:`redik.core.conventions`.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable, Sequence

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import IKResult
from redik.core.rotation_policy import as_pose
from redik.core.validate import MAX_COORDINATE, as_vector, positive, real_array
from redik.kinematics.robot import Robot
from redik.lie import interpolate_pose, pose_errors, so3_exp
from redik.solvers.pose import solve_pose

TIME_SCALINGS = ("linear", "cubic", "quintic")

MAX_SAMPLES = 10_000_000
"""Most samples :meth:`Path.sample_times` returns (10⁷: 16 GB of poses, a day at 100 Hz)."""

Solver = Callable[[np.ndarray, np.ndarray], IKResult]
"""``solver(T_target, q_start) -> IKResult``: one IK solve warm-started at ``q_start``."""


def time_scaling(tau: float, kind: str) -> float:
    """``s(τ)`` on ``[0, 1]`` for a ``"linear"``, ``"cubic"`` or ``"quintic"`` scaling."""
    if kind == "linear":
        return tau
    if kind == "cubic":
        return tau * tau * (3.0 - 2.0 * tau)
    return tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau))


class PosePath:
    """A timed pose path: :meth:`pose` at any time from ``start_time`` to ``end_time``.

    Subclasses define :meth:`pose`, ``start_time`` and ``end_time``; sampling is shared.
    """

    start_time: float
    end_time: float

    def pose(self, t: float) -> np.ndarray:  # pragma: no cover - abstract
        """The 4 × 4 pose at time ``t`` (s), clamped to the path's ends."""
        raise NotImplementedError

    @property
    def duration(self) -> float:
        """``end_time − start_time`` (s)."""
        return float(self.end_time - self.start_time)

    def sample_times(self, rate: float) -> np.ndarray:
        """Times at ``rate`` Hz from the start to the end, both included."""
        rate = positive(rate, "rate", unit="Hz")
        count = float(np.ceil(self.duration * rate - 1e-9))
        if not count < MAX_SAMPLES:
            raise InvalidInput(
                f"{self.duration:g} s at {rate:g} Hz is {count:.3g} samples, more than "
                f"MAX_SAMPLES = {MAX_SAMPLES:g}"
            )
        count = int(count)
        return np.linspace(self.start_time, self.end_time, count + 1)

    def sample(self, rate: float) -> tuple[np.ndarray, np.ndarray]:
        """``(times, poses)``: the path sampled at ``rate`` Hz, poses as an (N, 4, 4) array."""
        times = self.sample_times(rate)
        return times, np.array([self.pose(t) for t in times])


class CartesianPath(PosePath):
    """A path through timed waypoint poses: straight lines in position, SLERP in rotation.

    Args:
        poses: Two or more 4 × 4 waypoint poses ``T_wf`` (world frame).
        times: Their times in seconds, strictly increasing (default ``0, 1, 2, …``).
        time_scaling: ``"linear"``, ``"cubic"`` or ``"quintic"``, applied on every segment.

    Raises:
        InvalidInput: fewer than two poses, a pose that is not a rigid transform, times not
            strictly increasing or of the wrong length, or an unknown time scaling.
    """

    def __init__(
        self,
        poses: Sequence[np.ndarray],
        times: Sequence[float] | None = None,
        time_scaling: str = "linear",
    ):
        try:
            count = -1 if isinstance(poses, str | bytes) else len(poses)
        except TypeError:  # None, a number, a 0-d array
            count = -1
        if count < 2:
            raise InvalidInput(f"a path needs at least two waypoint poses (4 × 4), got {poses!r}")
        self.poses = np.array([as_pose(T, name=f"poses[{i}]") for i, T in enumerate(poses)])
        self.times = (
            np.arange(len(poses), dtype=float) if times is None else real_array(times, "times")
        )
        if self.times.shape != (len(poses),) or not np.all(np.isfinite(self.times)):
            raise InvalidInput(
                f"times must be {len(poses)} finite numbers (one per pose), got {times!r}"
            )
        if np.any(np.diff(self.times) <= 0.0):
            raise InvalidInput(f"waypoint times must increase strictly, got {self.times.tolist()}")
        if not isinstance(time_scaling, str) or time_scaling not in TIME_SCALINGS:
            raise InvalidInput(f"time_scaling must be one of {TIME_SCALINGS}, got {time_scaling!r}")
        self.time_scaling = time_scaling
        self.start_time, self.end_time = float(self.times[0]), float(self.times[-1])

    @classmethod
    def line(
        cls, T_start: np.ndarray, T_end: np.ndarray, duration: float, time_scaling: str = "quintic"
    ) -> CartesianPath:
        """A single segment from ``T_start`` to ``T_end`` in ``duration`` seconds."""
        if not duration > 0.0:
            raise InvalidInput(f"duration must be positive, got {duration!r}")
        return cls([T_start, T_end], [0.0, duration], time_scaling)

    def pose(self, t: float) -> np.ndarray:
        """The pose at time ``t`` (held at the end poses outside the waypoint times)."""
        if t <= self.times[0]:
            return self.poses[0].copy()
        if t >= self.times[-1]:
            return self.poses[-1].copy()
        k = int(np.searchsorted(self.times, t, side="right")) - 1
        tau = (t - self.times[k]) / (self.times[k + 1] - self.times[k])
        return interpolate_pose(
            self.poses[k], self.poses[k + 1], time_scaling(tau, self.time_scaling)
        )


class CircularPath(PosePath):
    """The end-effector moving once around a circle, orientation held.

    The circle passes through ``T_start``'s position, around ``center``, in the plane normal
    to ``normal`` (world coordinates); the angle follows ``2π s(t / duration)`` with the
    time scaling ``s`` (quintic: starts and ends at rest with no acceleration jump, the
    reference a servo can follow).
    """

    def __init__(
        self,
        T_start: np.ndarray,
        center: np.ndarray,
        normal: np.ndarray,
        duration: float,
        time_scaling: str = "quintic",
    ):
        self.T_start = as_pose(T_start, "T_start")
        self.center = as_vector(center, 3, "center")
        normal = as_vector(normal, 3, "normal")
        if np.abs(self.center).max() > MAX_COORDINATE or not np.abs(normal).max() > 0.0:
            raise InvalidInput(
                f"center must be within ±{MAX_COORDINATE:g} m and normal non-zero, got "
                f"{self.center.tolist()} and {normal.tolist()}"
            )
        normal = normal / np.abs(normal).max()  # no overflow in the norm
        self.axis = normal / np.linalg.norm(normal)
        offset = self.T_start[:3, 3] - self.center
        self.offset = offset - (offset @ self.axis) * self.axis  # in the circle's plane
        if np.linalg.norm(self.offset) < 1e-9:
            raise InvalidInput("the start position lies on the circle's axis (radius 0)")
        duration = positive(duration, "duration", unit="s")
        if not isinstance(time_scaling, str) or time_scaling not in TIME_SCALINGS:
            raise InvalidInput(f"time_scaling must be one of {TIME_SCALINGS}, got {time_scaling!r}")
        self.start_time, self.end_time = 0.0, duration
        self.time_scaling = time_scaling

    @property
    def radius(self) -> float:
        """The circle's radius (m)."""
        return float(np.linalg.norm(self.offset))

    def pose(self, t: float) -> np.ndarray:
        """``T_start`` with its position turned by ``2π s(t / duration)`` about the axis."""
        tau = min(max(t / self.end_time, 0.0), 1.0)
        angle = 2.0 * np.pi * time_scaling(tau, self.time_scaling)
        T = self.T_start.copy()
        T[:3, 3] += so3_exp(angle * self.axis) @ self.offset - self.offset
        return T


@dataclasses.dataclass(frozen=True)
class Interval:
    """A stretch of the trajectory, samples ``start`` to ``end`` inclusive, with a label."""

    start: int
    end: int
    start_time: float
    end_time: float
    label: str
    value: float  # σ_min reached (singular crossing) or closest distance to the limit

    def __str__(self) -> str:
        return f"{self.label} t ∈ [{self.start_time:.3f}, {self.end_time:.3f}] s ({self.value:.3g})"


@dataclasses.dataclass
class JointTrajectory:
    """IK along a path: joint values per sample and what was checked on them.

    Attributes:
        times: (N,) sample times in seconds.
        q: (N, nq) configurations (``robot.nq`` entries each).
        targets: (N, 4, 4) desired poses.
        success: (N,) whether each sample's IK met its tolerances.
        iterations: (N,) solver iterations per sample (the first one starts from ``q0``).
        position_error, rotation_error: (N,) pose errors of FK(q) against the targets
            (metres, radians), recomputed here rather than taken from the solver.
        sigma_min: (N,) smallest singular value of the 6 × n world Jacobian.
        joint_steps: (N − 1,) ``‖q_{k+1} − q_k‖_∞`` per step.
        jump_tol: The continuity threshold the trajectory was checked with.
        singular_crossings: Intervals with ``σ_min < singular_tol``.
        limit_contacts: Intervals where a joint is within ``limit_margin`` of a limit,
            labelled ``"<joint> lower"`` or ``"<joint> upper"``.
    """

    times: np.ndarray
    q: np.ndarray
    targets: np.ndarray
    success: np.ndarray
    iterations: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    sigma_min: np.ndarray
    joint_steps: np.ndarray
    jump_tol: float
    singular_crossings: list[Interval]
    limit_contacts: list[Interval]

    @property
    def velocities(self) -> np.ndarray:
        """(N, n) joint velocities by finite differences (``np.gradient`` in time)."""
        if len(self.times) < 2:
            return np.zeros_like(self.q)
        return np.gradient(self.q, self.times, axis=0)

    @property
    def max_joint_step(self) -> float:
        """Largest joint change between consecutive samples (rad or m)."""
        return float(self.joint_steps.max()) if len(self.joint_steps) else 0.0

    @property
    def discontinuities(self) -> np.ndarray:
        """Indices ``k`` of the steps ``k → k + 1`` larger than ``jump_tol``."""
        return np.flatnonzero(self.joint_steps > self.jump_tol)

    @property
    def continuous(self) -> bool:
        """True when no step is larger than ``jump_tol``."""
        return self.max_joint_step <= self.jump_tol

    @property
    def success_rate(self) -> float:
        """Fraction of the samples solved."""
        return float(np.mean(self.success))

    @property
    def mean_iterations(self) -> float:
        """Mean iterations per sample after the first (the first solve starts cold)."""
        warm = self.iterations[1:] if len(self.iterations) > 1 else self.iterations
        return float(np.mean(warm))

    def summary(self) -> str:
        """A few lines: samples, success, iterations, errors, continuity and events."""
        lines = [
            f"{len(self.times)} samples over {self.times[-1] - self.times[0]:.3f} s: "
            f"{self.success_rate:.1%} solved, {self.mean_iterations:.2f} iterations per point "
            f"(max {int(self.iterations[1:].max()) if len(self.iterations) > 1 else 0})",
            f"max error {self.position_error.max():.2e} m, {self.rotation_error.max():.2e} rad; "
            f"largest joint step {self.max_joint_step:.4f} "
            f"({'continuous' if self.continuous else 'DISCONTINUOUS'}, tol {self.jump_tol:g})",
            f"σ_min(J) ≥ {self.sigma_min.min():.3g}; "
            f"{len(self.singular_crossings)} singular crossing(s), "
            f"{len(self.limit_contacts)} limit contact(s)",
        ]
        lines += [f"  {event}" for event in self.singular_crossings + self.limit_contacts]
        return "\n".join(lines)


def joint_steps(q: np.ndarray) -> np.ndarray:
    """``‖q_{k+1} − q_k‖_∞`` for each consecutive pair of rows of ``q`` (N × n)."""
    q = np.asarray(q, dtype=float)
    if len(q) < 2:
        return np.zeros(0)
    return np.max(np.abs(np.diff(q, axis=0)), axis=1)


def _tangent_steps(robot: Robot, q: np.ndarray) -> np.ndarray:
    """``‖q_{k+1} ⊖ q_k‖_∞`` per step, across ball and free joints.

    The difference ``⊖`` is the robot's (:meth:`redik.Robot.difference`): on the tangent
    space of ball and free joints.
    """
    return np.array([np.max(np.abs(robot.difference(a, b))) for a, b in itertools.pairwise(q)])


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Maximal runs of True in a boolean vector as inclusive ``(start, end)`` index pairs."""
    padded = np.concatenate(([False], mask, [False])).astype(np.int8)
    edges = np.flatnonzero(np.diff(padded))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def singular_crossings(times: np.ndarray, sigma_min: np.ndarray, tol: float) -> list[Interval]:
    """Intervals where ``σ_min < tol``, each with the smallest σ_min reached."""
    return [
        Interval(
            a, b, float(times[a]), float(times[b]), "singular", float(sigma_min[a : b + 1].min())
        )
        for a, b in _runs(sigma_min < tol)
    ]


def limit_contacts(times: np.ndarray, q: np.ndarray, robot: Robot, margin: float) -> list[Interval]:
    """Intervals where a joint is within ``margin`` of its lower or upper limit."""
    events = []
    values = q if robot.flat else np.array([robot.scalar_values(row) for row in q])
    for side, distance in (("lower", values - robot.lower), ("upper", robot.upper - values)):
        for j, joint in enumerate(robot.dof_names):
            for a, b in _runs(distance[:, j] <= margin):
                closest = float(distance[a : b + 1, j].min())
                events.append(
                    Interval(a, b, float(times[a]), float(times[b]), f"{joint} {side}", closest)
                )
    return sorted(events, key=lambda event: (event.start, event.label))


def follow_path(
    robot: Robot,
    path: PosePath,
    q0: np.ndarray,
    solver: Solver | None = None,
    *,
    rate: float = 100.0,
    jump_tol: float = 0.1,
    singular_tol: float = 1e-3,
    limit_margin: float = 1e-3,
    frame: str | None = None,
) -> JointTrajectory:
    """Solve IK at every sample of ``path``, each solve warm-started at the previous solution.

    Args:
        robot: The robot (a whole-model robot too: the default solver then moves the chain
            to ``frame``, a QP stack whatever it moves).
        path: The path of ``frame`` (a :class:`CartesianPath`, :class:`CircularPath`, …).
        q0: Start configuration for the first sample (ideally already on the path).
        solver: ``solver(T_target, q_start) -> IKResult``. Default: damped least squares
            (:func:`redik.solvers.pose.solve_pose`) without restarts — a restart would jump to a
            random seed and break continuity. A QP stack works too, e.g.
            ``lambda T, q: (task.set_target(T), redik.solve_problem(problem, q))[1]``: the
            driver keeps no state between calls (acceleration limits are left out of it,
            :meth:`redik.Problem.static_step`), so such a run does not depend on what the
            problem did before (a :func:`~redik.apps.sim.simulate`, a loop of ``step``).
        rate: Sampling rate in Hz.
        jump_tol: Largest joint change per sample (rad or m) still counted as continuous.
        singular_tol: ``σ_min(J)`` below which a sample counts as singular.
        limit_margin: Distance to a joint limit (rad or m) counted as contact.
        frame: The frame whose pose follows the path (default the end-effector); used for
            the independent error check and the Jacobian.

    Returns:
        The :class:`JointTrajectory`. A failed sample is reported, not raised; the next sample
        starts from its (closest) result.
    """
    q = robot.check_q(q0, name="q0")
    resolved = robot.frame(frame)
    if solver is None:

        def solver(T_target: np.ndarray, q_start: np.ndarray) -> IKResult:
            return solve_pose(robot, T_target, q0=q_start, restarts=0, frame=resolved)

    times, targets = path.sample(rate)
    count = len(times)
    qs = np.empty((count, robot.nq))
    success = np.zeros(count, dtype=bool)
    iterations = np.zeros(count, dtype=int)
    position_error, rotation_error, sigma_min = np.empty(count), np.empty(count), np.empty(count)
    T = np.eye(4)
    J = np.empty((6, robot.dof))
    for k, target in enumerate(targets):
        result = solver(target, q)
        q = result.q
        qs[k] = q
        success[k] = result.success
        iterations[k] = result.iterations
        robot.state.kinematics(q, resolved, T, J)
        position_error[k], rotation_error[k] = pose_errors(T, target)
        sigma_min[k] = np.linalg.svd(J, compute_uv=False)[-1]
    return JointTrajectory(
        times=times,
        q=qs,
        targets=targets,
        success=success,
        iterations=iterations,
        position_error=position_error,
        rotation_error=rotation_error,
        sigma_min=sigma_min,
        joint_steps=joint_steps(qs) if robot.flat else _tangent_steps(robot, qs),
        jump_tol=jump_tol,
        singular_crossings=singular_crossings(times, sigma_min, singular_tol),
        limit_contacts=limit_contacts(times, qs, robot, limit_margin),
    )
