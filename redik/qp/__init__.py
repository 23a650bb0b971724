"""The optimisation core: the differential IK problem, its QP, hierarchy and back-ends.

The problem (tasks and limits → one QP per step) in :mod:`redik.qp.problem`, its formulation
in :mod:`redik.qp.assembly`, strict priorities in :mod:`redik.qp.hierarchy`, the
curvature term of level 1 in :mod:`redik.qp.curvature`, back-ends in
:mod:`redik.qp.backends`.
"""

from redik.qp.backends import Backend, FallbackChain, available_backends, make_backend
from redik.qp.hierarchy import solve_lexicographic
from redik.qp.problem import Measurement, Problem
from redik.qp.problem_data import QP

__all__ = [
    "QP",
    "Backend",
    "FallbackChain",
    "Measurement",
    "Problem",
    "available_backends",
    "make_backend",
    "solve_lexicographic",
]
