"""Notes 004 (Modern Robotics Ch. 6 course notes), "Python Solution for Course Quiz", question 1:
Newton–Raphson on f(θ) = (θ1² − 9, θ2² − 4) from θ⁰ = (1, 1), two iterations.

The notes print no output; their code prints ``np.around(theta, 2)`` = [3.4, 2.05]
(θ¹ = (5, 2.5), θ² = (3.4, 2.05)). Their loop θ ← θ − J⁻¹f(θ) is ``solve_equations`` on
f(θ) = x_d with x_d = 0; ``tol=0`` runs exactly the two iterations.

Run: python examples/course/004_quiz_question1.py
"""

import numpy as np
from _table import table

import redik


def function_1(theta):
    return np.array([theta[0] ** 2 - 9, theta[1] ** 2 - 4])


def jacobian_1(theta):
    return np.array([[2 * theta[0], 0], [0, 2 * theta[1]]])


run = redik.solve_equations(
    function_1, [0, 0], [1, 1], "newton", jacobian_1, tol=0, max_iterations=2
)
table(
    "004 quiz, question 1 — θ after each Newton iteration",
    ["θ1", "θ2"],
    [("θ¹", ("5", "2.5"), run.history[1]), ("θ² (printed)", ("3.4", "2.05"), run.history[2])],
)
