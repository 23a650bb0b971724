r"""The closed-form solver of a robot, chosen from its screw axes.

:func:`solver_for` reads the robot's screws at q = 0 (:func:`.geometry.screws_of`) and picks:

- a 6-joint arm: its IK-Geo class (:func:`.geometry.classify`) solved by subproblems
  (:class:`~.six_joint.SixJointSolver`), else every solution by the elimination
  (:class:`~.general.GeneralSolver`);
- a 2- or 3-joint arm: the small arm its axes make (:data:`SMALL_ARMS`), with the lengths read
  off the axes and checked against the robot's forward kinematics:

  ``planar_2r`` / ``planar_3r``
      two or three parallel hinges: link lengths are the distances between consecutive axes
      and from the last axis to the end-effector (:func:`.planar.planar_2r`, ``planar_3r``);
  ``rrp_polar``
      a yaw hinge, an elevation hinge meeting it at right angles, a slide through their
      meeting point: the shoulder height d1 and the boom length a2 (:func:`.polar.rrp_polar`);
  ``hexapod_leg``
      a yaw hinge, then two parallel pitch hinges across it: coxa, femur, tibia and the
      femur axis' height (:func:`.hexapod.hexapod_leg`).

The model's name and its custom numerics play no part: a scene solves under any file name.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from redik.core.exceptions import InvalidInput, ModelError
from redik.core.validate import real_array
from redik.models.dh import DHRow, forward
from redik.solvers.analytic import _checks
from redik.solvers.analytic.general import GeneralSolver, general_solver
from redik.solvers.analytic.geometry import Chain, classify, screws_of
from redik.solvers.analytic.hexapod import hexapod_leg
from redik.solvers.analytic.planar import planar_2r_batch, planar_2r_solutions, planar_3r
from redik.solvers.analytic.polar import rrp_polar
from redik.solvers.analytic.results import DEFAULT_TOL, BatchSolutions, IKSolutions, unreachable
from redik.solvers.analytic.six_joint import SixJointSolver

if TYPE_CHECKING:
    from redik.kinematics.robot import Robot

HALF_PI = np.pi / 2.0

#: How closely ``robot.fk`` must match a small arm's DH table for :func:`solver_for` (m).
MATCH_TOL = 1e-6

#: Below this an axis pair counts as parallel, perpendicular or meeting (m, rad).
AXIS_TOL = 1e-9

Limits = tuple[np.ndarray, np.ndarray] | None

#: The values of :func:`solver_for`'s ``method`` for a 6-joint arm.
METHODS = ("closed_form", "elimination")


@dataclass(frozen=True)
class SmallArm:
    """A 2- or 3-joint arm with a closed form.

    Attributes:
        kind: Its name (module docstring).
        rows: ``rows(p)``: its standard DH table for the parameters ``p``.
        fit: ``fit(chain)``: the parameters read off the axes, or None if the axes do not
            fit.
        solve: ``solve(T_base, p, limits, tol)``: every solution of a base-frame target.
        position_only: Whether a target may be a point.
    """

    kind: str
    rows: Callable[[dict[str, float]], tuple[DHRow, ...]]
    fit: Callable[[Chain], dict[str, float] | None]
    solve: Callable[[np.ndarray, dict[str, float], Limits, float], IKSolutions]
    position_only: bool


def _unit_parallel(u: np.ndarray, v: np.ndarray) -> bool:
    return bool(np.linalg.norm(np.cross(u, v)) <= AXIS_TOL and u @ v > 0.0)


def _across(chain: Chain, i: int, point: np.ndarray) -> float:
    """The distance of ``point`` from axis ``i``."""
    offset = point - chain.a[i]
    return float(np.linalg.norm(offset - chain.h[i] * (offset @ chain.h[i])))


def _fit_planar(chain: Chain) -> dict[str, float] | None:
    """Parallel hinges (same sense): each link's length across the axes."""
    n = len(chain.h)
    if chain.prismatic.any() or not all(_unit_parallel(chain.h[0], h) for h in chain.h[1:]):
        return None
    ends = [*chain.a[1:], chain.M[:3, 3]]
    return {f"l{i + 1}": _across(chain, i, ends[i]) for i in range(n)}


def _fit_polar(chain: Chain) -> dict[str, float] | None:
    """Yaw and elevation hinges meeting at right angles, a slide through the meeting point."""
    if list(chain.prismatic) != [False, False, True]:
        return None
    h1, h2, slide = chain.h
    shoulder = chain.meeting_point(0, 1)
    if shoulder is None or abs(h1 @ h2) > AXIS_TOL or abs(slide @ h2) > AXIS_TOL:
        return None
    return {
        "d1": float((shoulder - chain.a[0]) @ h1),
        "a2": float((chain.M[:3, 3] - shoulder) @ slide),
    }


def _fit_leg(chain: Chain) -> dict[str, float] | None:
    """A yaw hinge, then two parallel pitch hinges across it."""
    if chain.prismatic.any() or abs(chain.h[0] @ chain.h[1]) > AXIS_TOL:
        return None
    if not _unit_parallel(chain.h[1], chain.h[2]):
        return None
    gap = chain.a[1] - chain.a[0]
    normal = np.cross(chain.h[0], chain.h[1])
    coxa = abs(gap @ normal)
    # The foot on axis 1 of the common normal with axis 2 (they are perpendicular).
    height = float(gap @ chain.h[0])
    return {
        "coxa": float(coxa),
        "femur": _across(chain, 1, chain.a[2]),
        "tibia": _across(chain, 2, chain.M[:3, 3]),
        "z_offset": height,
    }


def _planar_reason(T: np.ndarray, tol: float, orientation: bool) -> str:
    """Why a pose cannot be reached by an arm moving in the base xy plane ('' if it can)."""
    if abs(T[2, 3]) > tol:
        return f"target is {T[2, 3]:.6g} m off the arm's plane (z = 0 in its base frame)"
    if orientation and np.linalg.norm(T[:3, 2] - (0.0, 0.0, 1.0)) > 1e-8:
        return "target orientation is not a rotation about the base z axis"
    return ""


def _solve_planar_2r(T: np.ndarray, p: dict[str, float], limits: Limits, tol: float):
    reason = _planar_reason(T, tol, orientation=False)
    if reason:
        return unreachable(2, reason)
    return planar_2r_solutions(float(T[0, 3]), float(T[1, 3]), p["l1"], p["l2"], limits, tol)


def _solve_planar_3r(T: np.ndarray, p: dict[str, float], limits: Limits, tol: float):
    reason = _planar_reason(T, tol, orientation=True)
    if reason:
        return unreachable(3, reason)
    phi = float(np.arctan2(T[1, 0], T[0, 0]))
    return planar_3r(T[0, 3], T[1, 3], phi, p["l1"], p["l2"], p["l3"], limits=limits, tol=tol)


#: The 2- and 3-joint arms :func:`solver_for` recognises, by number of joints.
SMALL_ARMS: dict[int, tuple[SmallArm, ...]] = {
    2: (
        SmallArm(
            "planar_2r",
            lambda p: (DHRow(p["l1"], 0.0, 0.0), DHRow(p["l2"], 0.0, 0.0)),
            _fit_planar,
            _solve_planar_2r,
            True,
        ),
    ),
    3: (
        SmallArm(
            "planar_3r",
            lambda p: tuple(DHRow(p[k], 0.0, 0.0) for k in ("l1", "l2", "l3")),
            _fit_planar,
            _solve_planar_3r,
            False,
        ),
        SmallArm(
            "rrp_polar",
            lambda p: (
                DHRow(0.0, p["d1"], HALF_PI),
                DHRow(0.0, 0.0, HALF_PI, HALF_PI),
                DHRow(0.0, p["a2"], 0.0, 0.0, "prismatic"),
            ),
            _fit_polar,
            lambda T, p, limits, tol: rrp_polar(
                T[:3, 3], p["d1"], a2=p["a2"], limits=limits, tol=tol
            ),
            True,
        ),
        SmallArm(
            "hexapod_leg",
            lambda p: (
                DHRow(p["coxa"], p["z_offset"], HALF_PI),
                DHRow(p["femur"], 0.0, 0.0),
                DHRow(p["tibia"], 0.0, 0.0),
            ),
            _fit_leg,
            lambda T, p, limits, tol: hexapod_leg(
                T[:3, 3], p["coxa"], p["femur"], p["tibia"], p["z_offset"], limits=limits, tol=tol
            ),
            True,
        ),
    ),
}


@dataclass(frozen=True)
class SmallArmSolver:
    """The closed form of a 2- or 3-joint arm bound to a robot (:func:`solver_for`).

    Attributes:
        arm: The small arm (:data:`SMALL_ARMS`).
        params: Its parameters, read off the robot's axes.
        base: ``T_wb``, the pose of the arm's DH base frame in the world.
        lower, upper: The robot's joint limits, applied by default.
    """

    arm: SmallArm
    params: dict[str, float]
    base: np.ndarray
    lower: np.ndarray
    upper: np.ndarray

    @property
    def kind(self) -> str:
        """The arm's name (:data:`SMALL_ARMS`)."""
        return self.arm.kind

    @property
    def method(self) -> str:
        """``"closed_form"``."""
        return "closed_form"

    def __call__(
        self, target: Any, *, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> IKSolutions:
        """Every solution for a world-frame target.

        Args:
            target: 4×4 pose (as ``robot.fk`` returns) or, for an arm that places a point
                (``planar_2r``, ``rrp_polar``, ``hexapod_leg``), a 3-vector.
            limits: ``"robot"`` (the robot's limits), None (none) or ``(lower, upper)``.
            tol: As in the arm's solver.
            strict: Refuse a near-rotation instead of projecting it
                (:mod:`~redik.core.rotation_policy`).
        """
        square = target.__class__ is np.ndarray and target.shape == (4, 4)
        array = target if square else real_array(target, "target")
        if array.shape == (3,) and self.arm.position_only:
            T = np.eye(4)
            T[:3, 3] = _checks.finite_array(array, "target", (3,))
        else:
            T = _checks.pose(target, "target", strict=strict)
        bounds = _checks.resolve_limits(limits, (self.lower, self.upper), len(self.lower))
        bounded = np.isfinite(bounds[0]).any() or np.isfinite(bounds[1]).any()
        return self.arm.solve(self._base_inverse @ T, self.params, bounds if bounded else None, tol)

    def batch(
        self, T: Any, limits: Any = "robot", tol: float = DEFAULT_TOL, strict: bool = False
    ) -> BatchSolutions:
        """Every solution of a (B, 4, 4) stack of targets.

        The planar 2R arm is vectorised (:func:`.planar.planar_2r_batch`, on the targets'
        positions, one slot per elbow); the other arms solve target by target.

        Returns:
            ``q`` (B, S, n) by label, a (B, S) ``valid`` mask and a (B, S) ``singular`` mask.
        """
        T = self._base_inverse @ _checks.poses(T, "T", strict=strict)
        bounds = _checks.resolve_limits(limits, (self.lower, self.upper), len(self.lower))
        if self.arm.kind == "planar_2r":
            reason = np.abs(T[:, 2, 3]) > tol  # off the arm's plane
            result = planar_2r_batch(
                T[:, :2, 3], self.params["l1"], self.params["l2"], limits=bounds, tol=tol
            )
            result.valid[reason] = False
            result.q[reason] = np.nan
            return result
        return _batch_by_target(self, T, bounds, tol)

    @cached_property
    def _base_inverse(self) -> np.ndarray:
        return np.linalg.inv(self.base)


def _batch_by_target(
    solver: SmallArmSolver, T: np.ndarray, bounds: tuple[np.ndarray, np.ndarray], tol: float
) -> BatchSolutions:
    """:meth:`SmallArmSolver.batch` one base-frame target at a time, by label."""
    labels: list[str] = []
    rows: list[IKSolutions] = []
    for pose in T:
        result = solver.arm.solve(pose, solver.params, bounds, tol)
        rows.append(result)
        labels += [label for label in result.labels if label not in labels]
    n = len(solver.lower)
    q = np.full((len(T), len(labels), n), np.nan)
    valid = np.zeros((len(T), len(labels)), bool)
    singular = np.zeros((len(T), len(labels)), bool)
    for b, result in enumerate(rows):
        for solution in result:
            code = labels.index(solution.label)
            q[b, code], valid[b, code] = solution, True
            singular[b, code] = bool(solution.singular)
    return BatchSolutions(q, valid, singular, tuple(labels))


def _small_arm_solver(robot: Robot) -> SmallArmSolver:
    """The first small arm whose axes fit the robot's and whose DH table moves like it."""
    S, M = screws_of(robot)
    chain = Chain.from_screws(S, M)
    home = np.asarray(robot.home, dtype=float)
    probe = np.clip(home + np.linspace(0.3, -0.2, robot.dof), robot.lower, robot.upper)
    for arm in SMALL_ARMS.get(robot.dof, ()):
        params = arm.fit(chain)
        if params is None:
            continue
        rows = arm.rows(params)
        base = robot.fk(home) @ np.linalg.inv(forward(rows, home))
        if np.abs(robot.fk(probe) - base @ forward(rows, probe)).max() <= MATCH_TOL:
            return SmallArmSolver(arm, params, base, robot.lower.copy(), robot.upper.copy())
    kinds = [arm.kind for arm in SMALL_ARMS.get(robot.dof, ())]
    raise ModelError(
        f"no closed form fits {robot.name!r} ({robot.dof} joints): its axes are none of "
        f"{kinds} (closed forms take 2- and 3-joint arms of these kinds and 6-joint arms)"
    )


def solver_for(
    robot: Robot, method: Literal["closed_form", "elimination"] | None = None
) -> SixJointSolver | GeneralSolver | SmallArmSolver:
    """The all-solutions solver of a robot, chosen from its screw axes (module docstring).

    Args:
        robot: A :class:`redik.Robot`, e.g. ``redik.load("ur5e")`` or one built with
            :meth:`redik.Robot.from_dh` or :meth:`redik.Robot.from_screws`.
        method: For a 6-joint arm, ``"closed_form"`` (its class's subproblems; the arm must
            have a class) or ``"elimination"`` (every solution by the general elimination);
            default: the closed form when the arm has one. The solver's ``kind`` and
            ``method`` say which was chosen.

    Raises:
        InvalidInput: An unknown ``method``, or one given for an arm that is not 6-joint.
        ModelError: The robot does not move as the product of exponentials of its screws,
            has no closed form (a 2- or 3-joint arm of another kind, another number of
            joints, ``method="closed_form"`` for an arm without a class), or a joint is
            prismatic outside the Stanford class.
    """
    if not (method is None or (isinstance(method, str) and method in METHODS)):
        raise InvalidInput(f"method must be None, 'closed_form' or 'elimination', got {method!r}")
    if robot.dof != 6:
        if method is not None:
            raise InvalidInput(
                f"method={method!r} is for 6-joint arms; {robot.name!r} has {robot.dof}"
            )
        return _small_arm_solver(robot)
    S, M = screws_of(robot)
    found = classify(S, M) if method != "elimination" else None
    if found is not None:
        return SixJointSolver(found.kind, found.reversed, found.geometry, robot.lower.copy(),
                              robot.upper.copy())  # fmt: skip
    if method == "closed_form":
        raise ModelError(
            f"no closed-form class fits {robot.name!r}: it needs a spherical wrist or shoulder "
            "(three axes through one point) or three parallel axes (redik.solvers.analytic."
            "geometry); method='elimination' solves any 6R arm"
        )
    return general_solver(S, M, robot.lower, robot.upper)
