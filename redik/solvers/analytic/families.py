"""Closed-form solvers for robot models: which solver fits a scene, with what parameters.

Every bundled scene (``scenes/*.xml``, made by :mod:`redik.models.scene_library`) stores its
kinematic parameters as MJCF custom numerics, ``model.numeric("a2").data``.
:func:`params_from_model` reads them for an arm family and :func:`solver_for` returns an
:class:`AnalyticSolver` for a :class:`redik.Robot`: it takes world-frame targets (as
``robot.fk`` returns them), applies the robot's joint limits, and gives joint vectors in the
robot's joint order.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from redik.core.exceptions import InvalidInput, ModelError
from redik.core.validate import real_array
from redik.models.dh import DHRow, forward
from redik.solvers.analytic import _checks
from redik.solvers.analytic import _decomposed_kernels as kernels
from redik.solvers.analytic._arm import ARM_LABELS, SHOULDER_WRIST_LABELS
from redik.solvers.analytic._branches import puma_slots_of, stanford_slots_of, ur_slots_of
from redik.solvers.analytic._solution import DEFAULT_TOL, IKSolutions, unreachable
from redik.solvers.analytic.decomposed import (
    DecomposedSolver,
    classify,
    decomposed_solver,
    screws_of,
    solver_from_robot,
)
from redik.solvers.analytic.general import GeneralSolver, general_solver
from redik.solvers.analytic.general import solver_from_robot as general_from_robot
from redik.solvers.analytic.hexapod import hexapod_leg
from redik.solvers.analytic.planar import planar_2r_solutions, planar_3r
from redik.solvers.analytic.polar import rrp_polar
from redik.solvers.analytic.puma import dh_rows as puma_rows
from redik.solvers.analytic.puma import puma_parameters, puma_solutions
from redik.solvers.analytic.stanford import dh_rows as stanford_rows
from redik.solvers.analytic.stanford import stanford
from redik.solvers.analytic.ur import dh_rows as ur_rows
from redik.solvers.analytic.ur import ur_parameters, ur_solutions

if TYPE_CHECKING:
    import mujoco

    from redik.kinematics.robot import Robot

Limits = tuple[np.ndarray, np.ndarray] | None
#: ``solve(T_base, params, limits, tol)``, ``T_base`` the target pose in the arm's base frame,
#: a validated rigid transform, and ``limits`` validated (the PUMA and UR solvers skip the
#: checks of their public functions, which would repeat the solver's at half the cost of a
#: solve).
Solve = Callable[[np.ndarray, Mapping[str, float], Limits, float], IKSolutions]

HALF_PI = np.pi / 2.0
#: How closely ``robot.fk`` must match the family's DH table for :func:`solver_for` (m).
MATCH_TOL = 1e-6


@dataclass(frozen=True)
class Family:
    """An arm family: its parameter names, its DH table and its solver."""

    name: str
    parameters: tuple[str, ...]
    rows: Callable[[Mapping[str, float]], tuple[DHRow, ...]]
    solve: Solve
    dof: int


def _planar(T: np.ndarray, tol: float, orientation: bool) -> str:
    """Why a pose cannot be reached by an arm moving in the base xy plane ('' if it can)."""
    if abs(T[2, 3]) > tol:
        return f"target is {T[2, 3]:.6g} m off the arm's plane (z = 0 in its base frame)"
    if orientation and np.linalg.norm(T[:3, 2] - (0.0, 0.0, 1.0)) > 1e-8:
        return "target orientation is not a rotation about the base z axis"
    return ""


def _solve_planar_2r(T: np.ndarray, p: Mapping[str, float], limits: Limits, tol: float):
    reason = _planar(T, tol, orientation=False)
    if reason:
        return unreachable(2, reason)
    return planar_2r_solutions(float(T[0, 3]), float(T[1, 3]), p["l1"], p["l2"], limits, tol)


def _solve_planar_3r(T: np.ndarray, p: Mapping[str, float], limits: Limits, tol: float):
    reason = _planar(T, tol, orientation=True)
    if reason:
        return unreachable(3, reason)
    phi = float(np.arctan2(T[1, 0], T[0, 0]))
    return planar_3r(T[0, 3], T[1, 3], phi, p["l1"], p["l2"], p["l3"], limits=limits, tol=tol)


FAMILIES: dict[str, Family] = {
    family.name: family
    for family in (
        Family(
            "planar_2r",
            ("l1", "l2"),
            lambda p: (DHRow(p["l1"], 0.0, 0.0), DHRow(p["l2"], 0.0, 0.0)),
            _solve_planar_2r,
            2,
        ),
        Family(
            "planar_3r",
            ("l1", "l2", "l3"),
            lambda p: tuple(DHRow(p[k], 0.0, 0.0) for k in ("l1", "l2", "l3")),
            _solve_planar_3r,
            3,
        ),
        Family(
            "rrp_polar",
            ("d1",),
            lambda p: (
                DHRow(0.0, p["d1"], HALF_PI),
                DHRow(0.0, 0.0, HALF_PI, HALF_PI),
                DHRow(0.0, 0.0, 0.0, 0.0, "prismatic"),
            ),
            lambda T, p, limits, tol: rrp_polar(T[:3, 3], p["d1"], limits=limits, tol=tol),
            3,
        ),
        Family(
            "hexapod_leg",
            ("coxa", "femur", "tibia", "z_offset"),
            lambda p: (
                DHRow(p["coxa"], p["z_offset"], HALF_PI),
                DHRow(p["femur"], 0.0, 0.0),
                DHRow(p["tibia"], 0.0, 0.0),
            ),
            lambda T, p, limits, tol: hexapod_leg(
                T[:3, 3], p["coxa"], p["femur"], p["tibia"], p["z_offset"], limits=limits, tol=tol
            ),
            3,
        ),
        Family(
            "puma",
            ("a2", "a3", "d3", "d4"),
            lambda p: puma_rows(p["a2"], p["a3"], p["d3"], p["d4"]),
            lambda T, p, limits, tol: puma_solutions(
                T, puma_parameters(p["a2"], p["a3"], p["d3"], p["d4"], 0.0), limits, tol
            ),
            6,
        ),
        Family(
            "stanford",
            ("d2", "d6"),
            lambda p: stanford_rows(p["d2"], p["d6"]),
            lambda T, p, limits, tol: stanford(T, p["d2"], p["d6"], limits=limits, tol=tol),
            6,
        ),
        Family(
            "ur",
            ("d1", "a2", "a3", "d4", "d5", "d6"),
            lambda p: ur_rows(p["d1"], p["a2"], p["a3"], p["d4"], p["d5"], p["d6"]),
            lambda T, p, limits, tol: ur_solutions(
                T,
                ur_parameters(*(p[k] for k in ("d1", "a2", "a3", "d4", "d5", "d6"))),
                limits,
                tol,
            ),
            6,
        ),
    )
}
"""Every arm family with a closed-form solver, by name."""

#: Scene (model) names that name a family differently.
ALIASES = {"puma560": "puma", "ur5e": "ur", "stanford_arm": "stanford"}


def family_of(name: str) -> Family:
    """The :class:`Family` called ``name`` or a scene name aliasing it (``"puma560"``)."""
    key = ALIASES.get(name, name) if isinstance(name, str) else None
    if key not in FAMILIES:
        raise InvalidInput(
            f"no closed-form solver for {name!r}; families: {sorted(FAMILIES)} "
            f"(scene names {sorted(ALIASES)} also work), or 'decomposed' / 'general_6r' "
            "for a 6R arm given by its screw axes"
        )
    return FAMILIES[key]


def params_from_model(model: mujoco.MjModel, family: str) -> dict[str, float]:
    """The family's parameters read from the model's custom numerics (metres).

    Raises:
        ModelError: A parameter is missing or is not a single number.
    """
    spec = family_of(family)
    present = [model.numeric(i).name for i in range(model.nnumeric)]
    missing = [name for name in spec.parameters if name not in present]
    if missing:
        raise ModelError(
            f"the model has no custom numeric(s) {missing} needed by the {spec.name} solver "
            f"(it has {present})"
        )
    params = {}
    for name in spec.parameters:
        data = np.asarray(model.numeric(name).data, dtype=float)
        if data.size != 1:
            raise ModelError(f"custom numeric {name!r} must hold one number, got {data.tolist()}")
        params[name] = float(data[0])
    return params


@dataclass(frozen=True)
class AnalyticSolver:
    """A closed-form solver bound to a robot (make one with :func:`solver_for`).

    Attributes:
        family: The arm family (a key of :data:`FAMILIES`).
        params: Its parameters, as read from the model.
        base: ``T_wb``, the pose of the arm's DH base frame in the world.
        lower, upper: The robot's joint limits, applied by default.
        compiled: For the PUMA, UR and Stanford families, the subproblem decomposition of the same
            robot (:mod:`.decomposed`): a call solves with it and names each solution by the
            family's slot (:mod:`._branches`), in a few µs instead of the family's Python
            kernel; a target with a singular solution, or with none, goes to the family's
            kernel (its singularity texts, families and reasons). The two give the same
            labelled set (tested on random poses).
    """

    family: str
    params: Mapping[str, float]
    base: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    compiled: DecomposedSolver | None = None

    def __call__(
        self,
        target: Any,
        *,
        limits: Limits | str = "robot",
        tol: float = DEFAULT_TOL,
        strict: bool = False,
    ) -> IKSolutions:
        """Every solution for a world-frame target.

        Args:
            target: 4×4 pose (as ``robot.fk`` returns) or, for the position-only families
                (``planar_2r``, ``rrp_polar``, ``hexapod_leg``), a 3-vector.
            limits: ``"robot"`` (the robot's limits), ``None`` (none) or ``(lower, upper)``.
            tol: As in the family's solver.
            strict: Refuse a near-rotation instead of projecting it
                (:mod:`~redik.core.rotation_policy`).
        """
        # A 4 × 4 array (the usual call) goes straight to the pose check.
        square = target.__class__ is np.ndarray and target.shape == (4, 4)
        array = target if square else real_array(target, "target")
        if array.shape == (3,) and self.family in ("planar_2r", "rrp_polar", "hexapod_leg"):
            T = np.eye(4)
            T[:3, 3] = _checks.finite_array(array, "target", (3,))
        else:
            T = _checks.pose(target, "target", strict=strict)
            if self.compiled is not None:
                solutions = self._compiled_solutions(T, limits, tol)
                if solutions is not None:
                    return solutions
        if isinstance(limits, str):
            if limits != "robot":
                raise InvalidInput(
                    f"limits must be 'robot', None or (lower, upper), got {limits!r}"
                )
            chosen = (self.lower, self.upper)
        else:
            chosen = _checks.limits(limits, len(self.lower))
        family = FAMILIES[self.family]
        return family.solve(self._base_inverse @ T, self.params, chosen, tol)

    def _compiled_solutions(self, T: np.ndarray, limits: Any, tol: Any) -> IKSolutions | None:
        """The labelled solutions by :attr:`compiled` (None: leave the target to the
        family's kernel)."""
        solver = self.compiled
        assert solver is not None
        T = np.ascontiguousarray(T)
        q, slots, flags = kernels.solve_labelled(T, solver._plan_for(limits, tol))
        if not len(slots) or kernels.SINGULAR in flags[0].tolist():
            return None
        local = self._base_inverse @ T
        p = self.params
        labels = ARM_LABELS
        if self.family == "puma":
            branch = puma_slots_of(q, local, p["a2"], p["a3"], p["d3"], p["d4"], 0.0)
        elif self.family == "ur":
            branch = ur_slots_of(q, local, p["a2"], p["a3"], p["d4"], p["d6"])
        else:
            branch, labels = stanford_slots_of(q, local, p["d2"], p["d6"]), SHOULDER_WRIST_LABELS
        order = np.argsort(branch)
        named = branch[order].tolist()
        if named and named[0] < 0:  # Stanford rows with d3 < 0, which its solver excludes
            start = named.count(-1)
            order, named = order[start:], named[start:]
            if not named:
                return None
        if len(set(named)) != len(named):  # two solutions on one branch: not regular after all
            return None
        return IKSolutions.from_arrays(q[order], [labels[slot] for slot in named])

    @cached_property
    def _base_inverse(self) -> np.ndarray:
        """``T_bw``, computed once: a solve per call would cost as much as the closed form."""
        return np.linalg.inv(self.base)


def solver_for(
    robot: Robot, family: str | None = None
) -> AnalyticSolver | DecomposedSolver | GeneralSolver:
    """The closed-form (all-solutions) solver of a robot.

    Args:
        robot: A :class:`redik.Robot`, e.g. ``redik.load("puma560")`` or one built with
            :meth:`redik.Robot.from_screws`.
        family: The arm family; default: inferred from the model name (``robot.name``), and
            for any other 6R arm the subproblem decomposition of its screw axes
            (:mod:`redik.solvers.analytic.decomposed`) when its geometry has one, else the
            general 6R elimination (:mod:`redik.solvers.analytic.general`).
            ``"decomposed"`` or ``"general_6r"`` forces one of those; the solver's
            ``family`` (and ``kind``) say which was chosen.

    A family's solver is checked against its DH table (``robot.fk`` at two configurations,
    up to a constant base transform), the decomposition and the elimination against the
    product of exponentials of the screw axes, so that a solver never silently answers for a
    different arm.

    Raises:
        InvalidInput: No family of that name.
        ModelError: A parameter is missing, the model does not match the table, or no
            family fits (for a 6R arm: its geometry fits no decomposition class and the
            general elimination is degenerate for it).
    """
    if family is not None and not isinstance(family, str):
        family_of(family)  # raises, naming the families
    if family == "general_6r":
        return general_from_robot(robot)
    if family == "decomposed" or (
        family is None and ALIASES.get(robot.name, robot.name) not in FAMILIES
    ):
        if family is None and robot.dof != 6:
            raise InvalidInput(
                f"no closed-form solver for {robot.name!r} ({robot.dof} joints): the families "
                f"are {sorted(FAMILIES)} (scene names {sorted(ALIASES)} also work), and "
                "the subproblem decomposition and general 6R elimination take 6R arms"
            )
        if family is None and robot.revolute.all():
            S, M = screws_of(robot)
            if classify(S, M) is None:
                return general_solver(S, M, robot.lower, robot.upper)
            return decomposed_solver(S, M, robot.lower, robot.upper)
        return solver_from_robot(robot)
    spec = family_of(family if family is not None else robot.name)
    if robot.dof != spec.dof:
        raise ModelError(
            f"{robot.name!r} has {robot.dof} joints, the {spec.name} solver expects {spec.dof}"
        )
    params = params_from_model(robot.model, spec.name)
    rows = spec.rows(params)
    home = np.asarray(robot.home, dtype=float)
    base = robot.fk(home) @ np.linalg.inv(forward(rows, home))
    probe = np.clip(home + np.linspace(0.3, -0.2, robot.dof), robot.lower, robot.upper)
    mismatch = np.abs(robot.fk(probe) - base @ forward(rows, probe)).max()
    if mismatch > MATCH_TOL:
        raise ModelError(
            f"{robot.name!r} does not move like the {spec.name} DH table with parameters "
            f"{params}: poses differ by {mismatch:.3g} (tolerance {MATCH_TOL:g})"
        )
    compiled = None
    if spec.name in _COMPILED_CLASS:
        S, M = screws_of(robot)
        found = classify(S, M)
        if found is not None and found[:2] == (_COMPILED_CLASS[spec.name], False):
            compiled = decomposed_solver(S, M, robot.lower, robot.upper)
    return AnalyticSolver(spec.name, params, base, robot.lower.copy(), robot.upper.copy(), compiled)


#: The decomposition class that solves a family's arms (forwards), for AnalyticSolver.compiled.
_COMPILED_CLASS = {
    "puma": "spherical_two_intersecting",
    "ur": "three_parallel_two_intersecting",
    "stanford": "spherical_two_intersecting_prismatic",
}
