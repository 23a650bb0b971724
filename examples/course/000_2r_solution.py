"""Notes 000 (Ch7 Inverse Kinematics), "Case Study": the joint values of x_d = (0.2, 1.3).

The case study's 2R arm has unit links (its figure; only l1 = l2 = 1 puts (0.5650, 1.7062) at
x_d). The closed form of the notes' first slides (θ2 = atan2(±√(1 − u²), u), θ1 = atan2(y, x)
− atan2(l2 s2, l1 + l2 c2)) is ``redik.solvers.analytic.planar_2r``.

Slip of the notes: they print θ1 = 0.5650, θ2 = 0.7062. θ2 is 1.7062 (the leading 1 is
dropped): (0.5650, 0.7062) puts the tip at (1.14, 1.49), and both iterate tables of the case
study end at 1.7062. The printed number is shown beside the corrected one.

Run: python examples/course/000_2r_solution.py
"""

from _table import table

import redik
from redik.solvers.analytic import planar_2r

solutions = planar_2r(0.2, 1.3, 1.0, 1.0)  # x, y, l1, l2
q = solutions.by_label("elbow-down")  # θ2 > 0, the solution both iterate tables converge to
table(
    "000 Case Study — the joint values of x_d = (0.2, 1.3)",
    ["θ1", "θ2"],
    [("printed", ("0.5650", "0.7062"), q), ("corrected", ("0.5650", "1.7062"), q)],
)
tip = redik.load("planar_2r").fk([0.5650, 0.7062])[:2, 3]
print(
    f"slip of the notes: θ2 = 0.7062 is 1.7062; the printed pair puts the tip at "
    f"({tip[0]:.2f}, {tip[1]:.2f}), not at (0.2, 1.3)"
)
other = solutions.by_label("elbow-up")
print(f"the other closed-form solution (elbow-up): ({other[0]:.4f}, {other[1]:.4f})")
