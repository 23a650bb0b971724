"""The optimisation core: QP data, assembly from tasks and limits, hierarchy, back-ends.

Formulation in :mod:`redik.qp.assembly`, strict priorities in :mod:`redik.qp.hierarchy`,
back-ends in :mod:`redik.qp.backends`.
"""

from redik.qp.backends import Backend, FallbackChain, available_backends, make_backend
from redik.qp.hierarchy import solve_lexicographic
from redik.qp.problem_data import QP

__all__ = [
    "QP",
    "Backend",
    "FallbackChain",
    "available_backends",
    "make_backend",
    "solve_lexicographic",
]
