r"""Correctors: Newton projection of configurations onto the pose of a self-motion manifold.

:class:`Corrector` projects one configuration at a time: the Newton loop of redik
(:func:`redik.solvers.iterative.newton_raphson`) on the body error twist of the pose
(:class:`~redik.solvers.iterative.PoseResidual`, Modern Robotics §6.2.2, *IKinBody*),

.. math::

    ξ_b = \log(T(q)^{-1} T_d)^∨, \qquad q ← q + J_b^+ ξ_b,

until ``‖p_d − p‖`` and ``angle(Rᵀ R_d)`` are a hundredth of the sample tolerances. The
minimum-norm step is orthogonal to ``ker J_b``, so a corrected prediction does not slide
along the manifold.

:class:`BatchCorrector` takes the same steps on a whole batch (a covering's frontier) with the
vectorised kinematics of :mod:`redik.kinematics.batched`: the world-frame error
``e = (p_d − p, log(R_d Rᵀ)^∨)`` and the ``"world"`` Jacobian (the body pair rotated to world
axes: the same minimum-norm steps to first order), by the batched damped least-squares step
with a vanishing damping (:func:`redik.solvers.dls.damped_step`). Frozen joints — a point
placed on a joint limit — get a zero Jacobian column, so the minimum-norm step leaves them
still.

Frames and twists follow :mod:`redik.core.conventions`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.kinematics.batched import chain_poses, world_jacobian
from redik.kinematics.chain import Chain
from redik.lie import pose_errors, rotation_log, wrap_angle
from redik.solvers.dls import damped_step
from redik.solvers.iterative import PosePoint, PoseResidual, StoppingRules, newton_raphson
from redik.solvers.redundancy.nullspace import nullspace_basis

if TYPE_CHECKING:
    from redik.kinematics.robot import Frame, Robot

SAMPLE_POSITION_TOLERANCE = 1e-9
"""Largest ``‖p_d − p‖`` (m) of a sample after correction."""

SAMPLE_ROTATION_TOLERANCE = 1e-8
"""Largest ``angle(Rᵀ R_d)`` (rad) of a sample after correction: an accuracy asked of a
solver, not the validation tolerance of an input rotation
(:data:`~redik.core.rotation_policy.ROTATION_TOLERANCE`)."""


_CONVERGED = 0.01  # iterate until the errors are this fraction of the tolerances
_DAMPING = 1e-12  # keeps the batched 6 × 6 solves regular at singular points


class Corrector:
    """Projects configurations onto a pose by Newton's method on the body error twist.

    Also gives the tangent space ``ker J_b`` at a point, the joint-space metric and the limit
    checks the tracer needs.

    Args:
        robot: The robot (a chain).
        T_target: The pose of the manifold.
        frame: The resolved frame placed at ``T_target``.
        position_tolerance: The largest ``‖p_d − p‖`` of a corrected point.
        rotation_tolerance: The largest rotation angle of a corrected point.
    """

    def __init__(
        self,
        robot: Robot,
        T_target: np.ndarray,
        frame: Frame,
        position_tolerance: float = SAMPLE_POSITION_TOLERANCE,
        rotation_tolerance: float = SAMPLE_ROTATION_TOLERANCE,
    ):
        self.robot = robot
        self.frame = frame
        self.T_target = T_target
        self.position_tolerance = position_tolerance
        self.rotation_tolerance = rotation_tolerance
        self.periodic = robot.periodic
        self.lower = np.asarray(robot.lower)
        self.upper = np.asarray(robot.upper)
        self.residual = PoseResidual(robot, frame, T_target, form="body")
        self._rules: dict[int, StoppingRules] = {}  # by iteration budget
        # The residual and point correct() returned last.
        self._last: tuple[PoseResidual, PosePoint] | None = None

    def pose_errors(self, q: np.ndarray) -> tuple[float, float]:
        """``(‖p_d − p‖, angle(Rᵀ R_d))`` at ``q`` (:func:`redik.lie.pose_errors`)."""
        T = np.eye(4)
        self.robot.state.kinematics(q, self.frame, T)
        return pose_errors(T, self.T_target)

    def correct(
        self, q: np.ndarray, free: np.ndarray | None = None, max_iterations: int = 12
    ) -> tuple[np.ndarray, bool]:
        """Newton from ``q`` onto the pose, moving only the ``free`` joints.

        Iterates ``q ← q + J_b⁺ ξ_b`` until the errors are a hundredth of the tolerances.

        Args:
            q: The start.
            free: A mask of the joints that move (default all).
            max_iterations: The iteration budget.

        Returns:
            ``(q, converged)``, converged meaning within the tolerances.
        """
        q = np.array(q, dtype=float)
        residual = self.residual
        if free is not None:
            residual = PoseResidual(
                self.robot, self.frame, self.T_target, form="body", free=free, q_full=q
            )
        start = q if free is None else q[free]
        run = newton_raphson(residual, start, self._rules_for(max_iterations))
        self._last = (residual, run.point)
        position, rotation = residual.errors(run.point)
        converged = position <= self.position_tolerance and rotation <= self.rotation_tolerance
        return residual.full(run.q).copy(), converged

    def tangent_basis(self, q: np.ndarray | None, dimension: int) -> np.ndarray:
        """Orthonormal basis (n × dimension) of ``ker J_b(q)``: the manifold's tangent space.

        ``q = None`` reuses the Jacobian of the last point :meth:`correct` returned.
        """
        if q is None:
            if self._last is None:
                raise InvalidInput("tangent_basis(None) reuses the last point: call correct first")
            residual, point = self._last
        else:
            residual = self.residual
            evaluated = residual.evaluate(np.array(q, dtype=float))
            if evaluated is None:
                raise InvalidInput(f"the pose error is not finite at q = {q!r}")
            point = evaluated
        return nullspace_basis(residual.jacobian(point), dimension)

    def _rules_for(self, max_iterations: int) -> StoppingRules:
        rules = self._rules.get(max_iterations)
        if rules is None:
            tol = (_CONVERGED * self.position_tolerance, _CONVERGED * self.rotation_tolerance)
            rules = self._rules[max_iterations] = StoppingRules(
                tol=tol, max_iterations=max_iterations
            )
        return rules

    def within_limits(self, q: np.ndarray) -> bool:
        """``lower ≤ q ≤ upper``."""
        return bool(np.all(q >= self.lower) and np.all(q <= self.upper))

    def limit_violation(self, q: np.ndarray) -> float:
        """How far ``q`` is outside its limits, hinge angles taken modulo 2π.

        The largest distance of one joint to its range: every configuration closer than this
        (on the torus of hinge angles) is outside the limits too.
        """
        return float(self.limit_violations(q))

    def limit_violations(self, q: np.ndarray) -> np.ndarray:
        """:meth:`limit_violation` of every row of ``q`` (… × n)."""
        below = self.lower - q
        above = q - self.upper
        distance = np.maximum(np.maximum(below, above), 0.0)
        hinges = self.robot.revolute & np.isfinite(self.lower) & np.isfinite(self.upper)
        width = self.upper[hinges] - self.lower[hinges]
        offset = np.mod(q[..., hinges] - self.lower[hinges], 2 * np.pi)  # past the lower limit
        outside = np.where(offset > width, np.minimum(offset - width, 2 * np.pi - offset), 0.0)
        distance[..., hinges] = np.where(self.periodic[hinges], 0.0, outside)  # never outside
        return np.max(distance, axis=-1, initial=0.0)

    def into_limits(self, q: np.ndarray) -> np.ndarray | None:
        """``q`` with hinges shifted by multiples of 2π into their ranges, or None if impossible."""
        shifted, inside = self.shift_into_limits(q)
        return shifted if inside else None

    def shift_into_limits(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every row of ``q`` (… × n), hinges shifted by turns towards their ranges, and if inside.

        The shifts are multiples of 2π; the mask says whether each row then lies within the
        limits.

        A hinge that cannot be brought into its range takes the angle nearest to it, on
        whichever side (what :meth:`limit_violation` measures): the start of a limit point.
        A periodic hinge (range of 2π or more, :attr:`redik.Robot.periodic`) has several
        in-range representatives; it takes the one in (−π, π] when its range holds it, else
        the in-range one beyond the nearer limit. The manifold is sampled at that one
        representative only.
        """
        revolute = self.robot.revolute
        with np.errstate(invalid="ignore"):  # ±inf limits
            up = np.ceil((self.lower - q) / (2 * np.pi))
            down = -np.ceil((q - self.upper) / (2 * np.pi))
        turns = np.where(
            revolute & (q < self.lower), up, np.where(revolute & (q > self.upper), down, 0.0)
        )
        shifted = q + 2 * np.pi * np.nan_to_num(turns)
        shifted[..., self.periodic] = wrap_angle(shifted[..., self.periodic])
        above, below = shifted - self.upper, self.lower - shifted
        other_side = revolute & (
            ((above > 0.0) & (self.lower - (shifted - 2 * np.pi) < above))
            | ((below > 0.0) & (shifted + 2 * np.pi - self.upper < below))
        )
        shifted = np.where(other_side, shifted - 2 * np.pi * np.sign(above), shifted)
        inside = np.all((shifted >= self.lower) & (shifted <= self.upper), axis=-1)
        return shifted, inside

    def limit_point(self, q_inside: np.ndarray, q_outside: np.ndarray) -> np.ndarray | None:
        """The point of the manifold on the joint limit between two nearby points.

        The joints ``q_outside`` violates are frozen at their limits, starting from the
        straight-line crossing of the boundary, and the pose is corrected with the others.
        Returns None when that fails or lands outside another limit.
        """
        violated = (q_outside < self.lower) | (q_outside > self.upper)
        delta = q_outside - q_inside
        bound = np.where(q_outside < self.lower, self.lower, self.upper)
        with np.errstate(divide="ignore", invalid="ignore"):
            fractions = (bound[violated] - q_inside[violated]) / delta[violated]
        fraction = float(np.clip(np.min(fractions, initial=1.0), 0.0, 1.0))
        start = np.clip(q_inside + fraction * delta, self.lower, self.upper)
        start[violated] = bound[violated]
        q, converged = self.correct(start, free=~violated)
        if converged and self.within_limits(q):
            return q
        return None


class BatchCorrector:
    """:class:`Corrector`'s Newton projection for many configurations at once.

    Uses :mod:`redik.solvers.batch`'s kinematics when the frame is the robot's end-effector (the
    chain it compiles); any other frame falls back to :class:`Corrector`, row by row.
    """

    def __init__(self, corrector: Corrector):
        self.corrector = corrector
        robot = corrector.robot
        self.dof = robot.dof
        self.chain = Chain.from_robot(robot) if corrector.frame == robot.ee else None
        self._Rd = corrector.T_target[:3, :3, None]
        self._pd = corrector.T_target[:3, 3, None]

    def correct(
        self, q: np.ndarray, frozen: np.ndarray | None = None, max_iterations: int = 12
    ) -> tuple[np.ndarray, np.ndarray]:
        """Newton from every row of ``q`` (B × n) onto the pose, ``frozen`` joints held still.

        ``frozen`` is a B × n mask. Returns ``(q, converged)``, converged meaning within the
        tolerances.
        """
        q = np.array(q, dtype=float).reshape(-1, self.dof)
        chain = self.chain
        if chain is None:
            rows = [
                self.corrector.correct(x, None if frozen is None else ~frozen[k], max_iterations)
                for k, x in enumerate(q)
            ]
            return (
                np.array([x for x, _ in rows]).reshape(q.shape),
                np.array([ok for _, ok in rows], dtype=bool),
            )
        c = self.corrector
        q = np.ascontiguousarray(q.T)  # n × B: batch last, as redik.solvers.batch computes
        converged = np.zeros(q.shape[1], dtype=bool)
        active = np.arange(q.shape[1])
        for iteration in range(max_iterations + 1):
            e, J, position, rotation = self._errors(chain, q[:, active])
            last = iteration == max_iterations
            scale = 1.0 if last else _CONVERGED
            done = (position <= scale * c.position_tolerance) & (
                rotation <= scale * c.rotation_tolerance
            )
            converged[active[done]] = True
            if last:
                break
            active, e, J = active[~done], e[:, ~done], J[:, :, ~done]
            if not active.size:
                break
            if frozen is not None:
                J *= ~frozen[active].T[None]
            step = damped_step(J, e, np.full(J.shape[2], _DAMPING))  # minimum-norm Newton
            finite = np.all(np.isfinite(step), axis=0)
            q[:, active[finite]] += step[:, finite]
            active = active[finite]
        return q.T.copy(), converged

    def _errors(self, chain: Chain, q: np.ndarray) -> tuple[np.ndarray, ...]:
        """World error ``e`` (6 × B), world Jacobian (6 × n × B) and the scalar errors."""
        R, p, axes, origins = chain_poses(chain, q)
        e = np.empty((6, q.shape[1]))
        np.subtract(self._pd, p, out=e[:3])
        Rd = np.broadcast_to(self._Rd, R.shape)
        rotation = rotation_log(Rd, R, out=e[3:])
        position = np.sqrt(np.einsum("ib,ib->b", e[:3], e[:3]))
        return e, world_jacobian(chain, p, axes, origins), position, rotation

    def tangent_bases(self, q: np.ndarray, dimension: int) -> np.ndarray:
        """Orthonormal bases (B × n × dimension) of ``ker J`` at every row of ``q``."""
        q = np.asarray(q, dtype=float).reshape(-1, self.dof)
        if self.chain is None:
            return np.array([self.corrector.tangent_basis(x, dimension) for x in q]).reshape(
                len(q), self.dof, dimension
            )
        _, p, axes, origins = chain_poses(self.chain, np.ascontiguousarray(q.T))
        J = world_jacobian(self.chain, p, axes, origins)
        return nullspace_basis(J.transpose(2, 0, 1), dimension)

    def limit_points(
        self, q_inside: np.ndarray, q_outside: np.ndarray, max_rounds: int = 3
    ) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`Corrector.limit_point` for every pair of rows.

        The manifold's point on the limit between ``q_inside`` (within the limits) and a
        nearby ``q_outside``.

        A joint the corrected point pushes past another limit is frozen there too and the
        point corrected again (up to ``max_rounds`` times), which finds the corners where
        two limits cut a surface. Returns ``(q, placed)``: the points (B × n) and whether
        each converged onto the pose within the limits.
        """
        c = self.corrector
        violated = (q_outside < c.lower) | (q_outside > c.upper)
        delta = q_outside - q_inside
        bound = np.where(q_outside < c.lower, c.lower, c.upper)
        with np.errstate(divide="ignore", invalid="ignore"):
            fractions = np.where(violated, (bound - q_inside) / delta, np.inf)
        fraction = np.clip(np.min(fractions, axis=1, initial=1.0), 0.0, 1.0)
        start = np.clip(q_inside + fraction[:, None] * delta, c.lower, c.upper)
        start[violated] = bound[violated]
        q, converged = self.correct(start, frozen=violated)
        for _ in range(max_rounds - 1):
            past = converged[:, None] & ~violated & ((q < c.lower) | (q > c.upper))
            again = np.flatnonzero(past.any(axis=1))
            if not again.size:
                break
            violated[again] |= past[again]
            start = np.clip(q[again], c.lower, c.upper)
            q[again], converged[again] = self.correct(start, frozen=violated[again])
        inside = np.all((q >= c.lower) & (q <= c.upper), axis=1)
        return q, converged & inside
