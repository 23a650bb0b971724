"""Closed-form inverse kinematics that returns every solution.

One module per arm family, each with the equations and the textbook reference in its
docstring: :mod:`.planar` (2R, 3R and the 3R self-motion family), :mod:`.polar` (RRP),
:mod:`.hexapod` (3-servo leg), :mod:`.wrist` (spherical wrist, ZYZ/ZYX), :mod:`.puma`
(PUMA-type 6R), :mod:`.stanford` (Stanford arm), :mod:`.ur` (Universal Robots 6R).

Every solver returns an :class:`IKSolutions`: the distinct joint vectors that reach the
target, each a :class:`JointSolution` (a numpy array with a ``label`` such as
``"left-up-noflip"``), with ``reachable`` and, when empty, a ``reason``; singular targets give
a representative with ``singular`` text and, where there is a continuum, a
:class:`SolutionFamily`. ``limits=(lower, upper)`` keeps the solutions that have a 2π-shifted
representative within the limits. Misuse (NaN, wrong shapes, a matrix that is not a rigid
transform, a negative length) raises :mod:`redik.core.exceptions` errors.

``planar_2r_batch``, ``puma_batch`` and ``ur_batch`` solve arrays of targets at once into a
:class:`BatchSolutions` (``q`` of shape (B, S, n), a ``valid`` mask, fixed slot ``labels``).
Each kernel is written once (:mod:`._numeric`): on Python floats for one target, so a single
pose allocates no arrays, and on (B,) arrays for a batch. ``redik bench analytic`` times both
against iterative DLS.
:func:`solver_for` binds a solver to a bundled scene's :class:`redik.Robot`, and to any other
6R arm whose screw axes fit a subproblem decomposition (:mod:`.decomposed`: spherical wrist or
shoulder, three parallel axes; IK-Geo's classes), compiled with numba
(:meth:`DecomposedSolver.raw` returns a plain array in a few microseconds; it also takes the
Stanford arm's prismatic joint, and the PUMA, UR and Stanford families solve with it and keep
their labels), and to any other 6R arm by the
Raghavan–Roth elimination solved as an eigenproblem (:mod:`.general`: every solution, up to
16, of an arm with no closed form; :class:`GeneralSolver`). :mod:`.srs` gives
the exact self-motion loops of a 7R arm with a spherical shoulder and wrist by the arm angle.
"""

from redik.solvers.analytic._solution import (
    BatchSolutions,
    IKSolutions,
    JointSolution,
    SolutionFamily,
    wrap_angle,
)
from redik.solvers.analytic.decomposed import DecomposedSolver, decomposed_solver
from redik.solvers.analytic.families import AnalyticSolver, params_from_model, solver_for
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
from redik.solvers.analytic.puma import puma, puma_batch
from redik.solvers.analytic.stanford import stanford
from redik.solvers.analytic.ur import UR5E, ur, ur_batch
from redik.solvers.analytic.wrist import spherical_wrist

__all__ = [
    "UR5E",
    "AnalyticSolver",
    "BatchSolutions",
    "DecomposedSolver",
    "GeneralSolver",
    "IKSolutions",
    "JointSolution",
    "Planar3RFamily",
    "SolutionFamily",
    "decomposed_solver",
    "general_solver",
    "hexapod_leg",
    "params_from_model",
    "planar_2r",
    "planar_2r_batch",
    "planar_3r",
    "planar_3r_family",
    "puma",
    "puma_batch",
    "rrp_polar",
    "solver_for",
    "spherical_wrist",
    "stanford",
    "ur",
    "ur_batch",
    "wrap_angle",
]
