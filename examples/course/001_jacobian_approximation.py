"""Notes 001 (Inverse Kinematics), "Jacobian" (simple example) and "Jacobian: Approximation".

F(x) = (x1² + x2² − 1, 5x1² + 2x2² + 4) at x = (1, 2): the proper Jacobian
[[2x1, 2x2], [10x1, 4x2]] = [[2, 4], [10, 8]], and the forward difference with δ = 0.1,
[[2.1, 4.1], [10.5, 8.2]] (a forward difference of a·x² is a·(2x + δ)). A central difference
is exact on a quadratic, so it gives the proper Jacobian.

Run: python examples/course/001_jacobian_approximation.py
"""

import numpy as np
from _table import table

from redik.solvers.iterative import finite_difference_jacobian


def F(x):
    """The notes' F: R² → R²."""
    return np.array([x[0] ** 2 + x[1] ** 2 - 1.0, 5.0 * x[0] ** 2 + 2.0 * x[1] ** 2 + 4.0])


x = np.array([1.0, 2.0])
central = finite_difference_jacobian(F, x, step=0.1, scheme="central")
forward = finite_difference_jacobian(F, x, step=0.1, scheme="forward")
table(
    "001 Jacobian — J(1, 2) (redik: central difference, exact on a quadratic)",
    ["∂/∂x1", "∂/∂x2"],
    [("F1", ("2", "4"), central[0]), ("F2", ("10", "8"), central[1])],
)
table(
    "001 Jacobian: Approximation — forward difference, δ = 0.1",
    ["∂/∂x1", "∂/∂x2"],
    [("F1", ("2.1", "4.1"), forward[0]), ("F2", ("10.5", "8.2"), forward[1])],
)
