"""Notes 003 (Modern Robotics Ch. 6, "Important concepts, symbols, and equations (cont.)"):
"Graphically find a 'good' solution to Ax = b, e.g., x = A†b" for
1) A = [1 2], b = 3 (wide: infinitely many solutions, A† gives the one of least norm) and
2) A = [1 2]ᵀ, b = [0 3]ᵀ (tall: none, A† gives the least-squares one).

The notes print no answer; by hand 1) x = Aᵀ(AAᵀ)⁻¹b = (0.6, 1.2), 2) x = (AᵀA)⁻¹Aᵀb =
6/5 = 1.2. One Newton step Δθ = J†(θ⁰)(x_d − f(θ⁰)) from θ⁰ = 0 on f(θ) = Aθ is exactly A†b,
the notes' linear correction (1).

Run: python examples/course/003_pseudoinverse_exercises.py
"""

import numpy as np
from _table import table

import redik

EXERCISES = [
    ("1) A = [1 2], b = 3", np.array([[1.0, 2.0]]), [3.0], ("0.6", "1.2")),
    ("2) A = [1 2]ᵀ, b = [0 3]ᵀ", np.array([[1.0], [2.0]]), [0.0, 3.0], ("1.2",)),
]

for name, A, b, by_hand in EXERCISES:
    step = redik.solve_equations(
        lambda x, A=A: A @ x, b, np.zeros(A.shape[1]), "newton", lambda x, A=A: A,
        tol=0, max_iterations=1,
    )  # fmt: skip
    table(
        f"003 {name}: x = A†b (by hand) against one Newton step from 0",
        [f"x{i + 1}" for i in range(A.shape[1])],
        [("A†b", by_hand, step.q)],
    )
