"""Closed-form inverse kinematics that returns every solution.

:func:`solver_for` gives the solver of a robot, chosen from its screw axes
(:mod:`.solver`): a 6-joint arm's IK-Geo class solved by subproblems
(:class:`SixJointSolver`: spherical wrist or shoulder after two intersecting axes, two
parallel axes or a general shoulder; three parallel axes with or without a wrist point; the
Stanford arm's sliding joint), any other 6R arm by the Raghavan–Roth elimination
(:class:`GeneralSolver`: every solution, up to 16), and the planar 2R/3R, RRP polar and
hexapod-leg arms. The functions of the small arms take their parameters directly:
:func:`planar_2r`, :func:`planar_3r` (and :func:`planar_3r_family`), :func:`rrp_polar`,
:func:`hexapod_leg`, :func:`spherical_wrist` (ZYZ, ZXZ, ZYX). :mod:`.srs` gives the exact
self-motion loops of a 7R arm with a spherical shoulder and wrist.

Every solver returns an :class:`IKSolutions`: the distinct joint vectors that reach the
target, each a :class:`JointSolution` (a numpy array with a ``label`` such as
``"left-up-noflip"``, named from its geometry: :mod:`.labels`), with ``reachable`` and, when
empty, a ``reason``; singular targets give a representative with ``singular`` text and, where
there is a continuum, a :class:`SolutionFamily`. ``limits=`` keeps the solutions that have a
2π-shifted representative within the limits. ``solver.raw(T)`` returns the solutions as a
plain array in one compiled call, ``solver.batch(T_stack)`` solves many targets on every core
(:class:`BatchSolutions`). Misuse (NaN, wrong shapes, a matrix that is not a rigid transform,
a negative length) raises :mod:`redik.core.exceptions` errors.

The modules: :mod:`.geometry` (the chain and its class), :mod:`.subproblems` (SP1–SP6, on
:mod:`.vectors`; quartics by :mod:`.polynomial`), :mod:`.kernels` (one compiled closed form
per class), :mod:`.chain` (compiled forward kinematics and polish), :mod:`.finish` (verify,
polish, limits, duplicates), :mod:`.labels`, :mod:`.six_joint` (the solver),
:mod:`.elimination` and :mod:`.general` (the general 6R arm), :mod:`.results`.
"""

from redik.solvers.analytic.general import GeneralSolver, general_solver
from redik.solvers.analytic.hexapod import hexapod_leg
from redik.solvers.analytic.planar import (
    Planar3RFamily,
    planar_2r,
    planar_2r_batch,
    planar_3r,
    planar_3r_family,
)
from redik.solvers.analytic.polar import rrp_polar
from redik.solvers.analytic.results import (
    BatchSolutions,
    IKSolutions,
    JointSolution,
    SolutionFamily,
    wrap_angle,
)
from redik.solvers.analytic.six_joint import SixJointSolver
from redik.solvers.analytic.solver import SmallArmSolver, solver_for
from redik.solvers.analytic.wrist import spherical_wrist

__all__ = [
    "BatchSolutions",
    "GeneralSolver",
    "IKSolutions",
    "JointSolution",
    "Planar3RFamily",
    "SixJointSolver",
    "SmallArmSolver",
    "SolutionFamily",
    "general_solver",
    "hexapod_leg",
    "planar_2r",
    "planar_2r_batch",
    "planar_3r",
    "planar_3r_family",
    "rrp_polar",
    "solver_for",
    "spherical_wrist",
    "wrap_angle",
]
