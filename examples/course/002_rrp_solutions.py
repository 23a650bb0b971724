"""Notes 002 (Robotics 1, Inverse kinematics), "Inverse kinematics of polar (RRP) arm" and
"Numerical tests on RRP robot": the two analytic solutions with q3 ≥ 0 of p_d = (1, 1, 1),
d1 = 0.5.

Printed: q* = (0.7854, 0.3398, 1.5) and q** = (q1* − π, π − q2*, q3*) = (−2.3562, 2.8018, 1.5).
Both by ``rrp_polar`` and by ``redik.solve_all(..., method="analytic")`` on the bundled
``rrp_polar`` scene, whose θ2 range [−π, π] holds q** (the boom passes over the top).

Run: python examples/course/002_rrp_solutions.py
"""

import numpy as np
from _table import table

import redik
from redik.solvers.analytic import rrp_polar

NOTES = [("q*", ("0.7854", "0.3398", "1.5")), ("q**", ("-2.3562", "2.8018", "1.5"))]

solutions = rrp_polar([1.0, 1.0, 1.0], 0.5)
table(
    "002 RRP — analytic solutions of p_d = (1, 1, 1), d1 = 0.5: rrp_polar",
    ["q1", "q2", "q3"],
    [(name, printed, solutions.by_label(label))
     for (name, printed), label in zip(NOTES, ("front", "back"), strict=True)],
)  # fmt: skip
robot = redik.load("rrp_polar")
T = np.eye(4)
T[:3, 3] = 1.0
in_scene = sorted(redik.solve_all(robot, T, method="analytic"), key=lambda result: -result.q[0])
table(
    "the same on the bundled scene: solve_all(robot, T, method='analytic')",
    ["q1", "q2", "q3"],
    [(name, printed, result.q) for (name, printed), result in zip(NOTES, in_scene, strict=True)],
)
