"""Notes 000 (Ch7 Inverse Kinematics), "Example 2: Stanford-Type Arms (RRP)": the two
solutions for the wrist centre.

p_W = ((θ3 + a2) c2 c1, (θ3 + a2) c2 s1, (θ3 + a2) s2 + d1), so θ3 = √(p_Wx² + p_Wy² +
(p_Wz − d1)²) − a2, θ2 = atan2(p_Wz − d1, ±√(p_Wx² + p_Wy²)), θ1 = atan2(p_Wy/c2, p_Wx/c2):
two solutions. The notes give no numbers: d1 = 0.5, a2 = 0.25 and p_W = (1, 1, 1) are chosen
here. ``rrp_polar(p, d1, a2=…)`` takes the boom's fixed length a2, so its θ3 is the notes'.

Run: python examples/course/000_stanford_type_rrp.py
"""

import math

import numpy as np
from _table import table

from redik.solvers.analytic import rrp_polar

D1, A2 = 0.5, 0.25
p_w = np.array([1.0, 1.0, 1.0])

notes = []
for sign in (1.0, -1.0):
    theta3 = math.sqrt(p_w[0] ** 2 + p_w[1] ** 2 + (p_w[2] - D1) ** 2) - A2
    theta2 = math.atan2(p_w[2] - D1, sign * math.hypot(p_w[0], p_w[1]))
    theta1 = math.atan2(p_w[1] / math.cos(theta2), p_w[0] / math.cos(theta2))
    notes.append((theta1, theta2, theta3))

solutions = rrp_polar(p_w, D1, a2=A2)
print(f"rrp_polar: {len(solutions)} solutions (the notes: 2), labels {solutions.labels}")
table(
    "000 Example 2, Stanford-type RRP — the notes' formulas (8 decimals) against redik",
    ["θ1", "θ2", "θ3"],
    [
        (label, tuple(f"{value:.8f}" for value in row), solutions.by_label(label))
        for label, row in zip(("front", "back"), notes, strict=True)
    ],
)
