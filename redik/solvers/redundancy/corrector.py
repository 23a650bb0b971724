r"""Correctors: Newton projection of configurations onto the pose of a self-motion manifold.

:class:`Corrector` projects one configuration at a time with MuJoCo's kinematics: Gauss–Newton
on the body error twist (Modern Robotics §6.2.2, *IKinBody*),

.. math::

    ξ_b = \log(T(q)^{-1} T_d)^∨, \qquad q ← q + J_b^+ ξ_b,

until ``‖p_d − p‖`` and ``angle(Rᵀ R_d)`` are a hundredth of the sample tolerances. The
minimum-norm step is orthogonal to ``ker J_b``, so a corrected prediction does not slide
along the manifold.

:class:`BatchCorrector` runs the same iteration on a whole batch (a covering's frontier)
with the vectorised kinematics of :mod:`redik.solvers.batch`: the world-frame error
``e = (p_d − p, log(R_d Rᵀ)^∨)`` and the ``"world"`` Jacobian (the body pair rotated to world
axes: same kernel, same minimum-norm steps to first order). Frozen joints — a point placed on
a joint limit — get a zero Jacobian column, so the minimum-norm step leaves them still.

Frames and twists follow :mod:`redik.core.conventions`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from redik.kinematics.batched import chain_poses, world_jacobian
from redik.kinematics.chain import Chain
from redik.kinematics.dls import damped_step
from redik.lie import body_error_twist, pose_errors, rotation_log, world_jacobian_to, wrap_angle
from redik.solvers.redundancy.nullspace import nullspace_basis

if TYPE_CHECKING:
    from redik.kinematics.robot import Frame, Robot

SAMPLE_POSITION_TOLERANCE = 1e-9
"""Largest ``‖p_d − p‖`` (m) of a sample after correction."""

SAMPLE_ROTATION_TOLERANCE = 1e-8
"""Largest ``angle(Rᵀ R_d)`` (rad) of a sample after correction (and the default of
:func:`redik.solvers.redundancy.gradient_projection_ik`): an accuracy asked of a solver, not
the validation tolerance of an input rotation
(:data:`~redik.core.rotation_policy.ROTATION_TOLERANCE`)."""


_CONVERGED = 0.01  # iterate until the errors are this fraction of the tolerances
_DAMPING = 1e-12  # keeps the batched 6 × 6 solves regular at singular points


class Corrector:
    """Projects configurations onto a pose: Gauss–Newton with ``J_b⁺`` on ``log(T⁻¹ T_d)``.

    Works on preallocated buffers (one :meth:`Robot.kinematics` per iteration). Also gives
    the tangent space ``ker J_b`` at a point, the joint-space metric and the limit checks the
    tracer needs.
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
        self._T = np.eye(4)
        self.J = np.empty((6, robot.dof))
        self.J_body = np.empty((6, robot.dof))
        self.iterations = 0

    def body_error(self, q: np.ndarray) -> tuple[np.ndarray, float, float]:
        """Body error twist ``ξ_b = log(T(q)⁻¹ T_d)``, position error and rotation angle at
        ``q`` (Modern Robotics' IKinBody step); leaves the world and body Jacobians at ``q``
        in :attr:`J` and :attr:`J_body`."""
        self.robot.state.kinematics(q, self.frame, self._T, self.J)
        R = self._T[:3, :3]
        world_jacobian_to("body", self.J, R, self._T[:3, 3], out=self.J_body)
        xi = body_error_twist(self._T, self.T_target)
        position_error = math.dist(self._T[:3, 3], self.T_target[:3, 3])
        return xi, position_error, float(np.linalg.norm(xi[3:]))

    def pose_errors(self, q: np.ndarray) -> tuple[float, float]:
        """``(‖p_d − p‖, angle(Rᵀ R_d))`` at ``q`` (:func:`redik.lie.pose_errors`)."""
        self.robot.state.kinematics(q, self.frame, self._T)
        return pose_errors(self._T, self.T_target)

    def correct(
        self,
        q: np.ndarray,
        free: np.ndarray | None = None,
        max_iterations: int = 12,
        max_step: float = math.inf,
    ) -> tuple[np.ndarray, bool]:
        """Gauss–Newton from ``q`` onto the pose, moving only the ``free`` joints.

        Iterates ``q ← q + J_b⁺ ξ_b`` (the step clipped to ``max_step``) until the errors are
        a hundredth of the tolerances; returns ``(q, converged)`` where converged means within
        the tolerances.
        """
        q = np.array(q, dtype=float)
        for _ in range(max_iterations):
            xi, position_error, rotation_error = self.body_error(q)
            if (
                position_error <= 0.01 * self.position_tolerance
                and rotation_error <= 0.01 * self.rotation_tolerance
            ):
                return q, True  # the buffers hold the kinematics at the returned q
            self.iterations += 1
            J = self.J_body if free is None else self.J_body[:, free]
            step = _min_norm_solve(J, xi)
            norm = float(np.linalg.norm(step))
            if not math.isfinite(norm):
                return q, False
            if norm > max_step:
                step *= max_step / norm
            if free is None:
                q += step
            else:
                q[free] += step
        _, position_error, rotation_error = self.body_error(q)
        converged = (
            position_error <= self.position_tolerance and rotation_error <= self.rotation_tolerance
        )
        return q, converged

    def tangent_basis(self, q: np.ndarray | None, dimension: int) -> np.ndarray:
        """Orthonormal basis (n × dimension) of ``ker J_b(q)``: the manifold's tangent space.

        ``q = None`` reuses the Jacobian of the last point evaluated (the one :meth:`correct`
        just returned).
        """
        if q is not None:
            self.body_error(q)
        return nullspace_basis(self.J_body, dimension)

    def within_limits(self, q: np.ndarray) -> bool:
        return bool(np.all(q >= self.lower) and np.all(q <= self.upper))

    def limit_violation(self, q: np.ndarray) -> float:
        """How far ``q`` is outside its limits, hinge angles taken modulo 2π: the largest
        distance of one joint to its range. Every configuration closer than this (on the
        torus of hinge angles) is outside the limits too."""
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
        """Every row of ``q`` (… × n) with its hinges shifted by multiples of 2π towards their
        ranges, and whether it then lies within them.

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


def _min_norm_solve(J: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """``J⁺ ξ``: ``Jᵀ(JJᵀ)⁻¹ξ`` for a wide ``J`` of full row rank, else least squares."""
    if J.shape[1] >= J.shape[0]:
        try:
            return J.T @ np.linalg.solve(J @ J.T, xi)
        except np.linalg.LinAlgError:
            pass
    return np.linalg.lstsq(J, xi, rcond=1e-10)[0]


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
        """Newton from every row of ``q`` (B × n) onto the pose, ``frozen`` joints (B × n
        mask) held still; returns ``(q, converged)``, converged meaning within the
        tolerances."""
        q = np.array(q, dtype=float).reshape(-1, self.dof)
        if self.chain is None:
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
            e, J, position, rotation = self._errors(q[:, active])
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

    def _errors(self, q: np.ndarray) -> tuple[np.ndarray, ...]:
        """World error ``e`` (6 × B), world Jacobian (6 × n × B) and the scalar errors."""
        R, p, axes, origins = chain_poses(self.chain, q)
        e = np.empty((6, q.shape[1]))
        np.subtract(self._pd, p, out=e[:3])
        Rd = np.broadcast_to(self._Rd, R.shape)
        rotation = rotation_log(Rd, R, out=e[3:])
        position = np.sqrt(np.einsum("ib,ib->b", e[:3], e[:3]))
        return e, world_jacobian(self.chain, p, axes, origins), position, rotation

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
        """:meth:`Corrector.limit_point` for every pair of rows: the manifold's point on the
        limit between ``q_inside`` (within the limits) and a nearby ``q_outside``.

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
