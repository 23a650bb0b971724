"""Notes 004 (Modern Robotics Ch. 6 course notes), "Python Solution for Course Quiz", question 2:
IKinBody on the planar 3R arm.

The body screws B_i are written in Modern Robotics' (ω, v) order, as the quiz writes them;
``redik.Robot.from_screws`` takes them so (redik's own twists are (v, ω)). M, the target T_sd
typed with 3 decimals, θ⁰ = (π/4, π/4, π/4), ε_ω = 0.001, ε_v = 0.0001. The notes print no
output; their code prints θ to 2 decimals: [0.93, 0.59, 0.68]. T_sd is not exactly a rotation
(3 decimals): redik projects it onto SO(3) and says so with a ``NearRotationWarning``. The
textbook run: ``method="newton", stop="twist", restarts=0, respect_limits=False``.

Run: python examples/course/004_quiz_question2.py
"""

import math
import warnings

import numpy as np
from _table import table

import redik

B_LIST = np.array([[0, 0, 1, 0, 3, 0], [0, 0, 1, 0, 2, 0], [0, 0, 1, 0, 1, 0]]).T
M = np.array([[1, 0, 0, 3], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
T_SD = np.array([[-0.585, -0.811, 0, 0.076], [0.811, -0.585, 0, 2.608], [0, 0, 1, 0],
                 [0, 0, 0, 1]])  # fmt: skip

robot = redik.Robot.from_screws(B_LIST, M, frame="body")
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always", redik.NearRotationWarning)
    run = redik.solve_pose(
        robot, T_SD, [math.pi / 4] * 3, method="newton", stop="twist", rot_tol=0.001,
        pos_tol=0.0001, max_iterations=20, restarts=0, respect_limits=False,
    )  # fmt: skip
for warning in caught:
    print(f"warning: {warning.message}")
print(run.summary())
table(
    "004 quiz, question 2 — IKinBody, θ to 2 decimals",
    ["θ1", "θ2", "θ3"],
    [("θ", ("0.93", "0.59", "0.68"), run.q)],
)
