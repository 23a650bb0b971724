"""Notes 002 (Robotics 1, Inverse kinematics), "Multiplicity of solutions" (E-E positioning of a
planar 2R arm), "Inverse kinematics of planar 2R arm" and "Algebraic solution for q1".

Stated: 2 regular solutions in WS1 (q2' and q2'' of equal magnitude and opposite signs),
1 on ∂WS1, ∞ in WS2 for l1 = l2 (q1 undefined at the origin: det = l1² + l2² + 2 l1 l2 c2 = 0).
The bundled ``planar_2r`` (l1 = l2 = 1); the targets are chosen here. The notes' algebraic q1
(ATAN2 of s1, c1 from the linear system) is evaluated beside redik's solutions.

Run: python examples/course/002_multiplicity_2r.py
"""

import math

from redik.solvers.analytic import planar_2r

L1 = L2 = 1.0


def algebraic_q1(px, py, q2):
    """q1 = ATAN2{(py(l1 + l2c2) − px l2s2)/det, (px(l1 + l2c2) + py l2s2)/det}."""
    c2, s2 = math.cos(q2), math.sin(q2)
    det = L1**2 + L2**2 + 2 * L1 * L2 * c2
    return math.atan2((py * (L1 + L2 * c2) - px * L2 * s2) / det,
                      (px * (L1 + L2 * c2) + py * L2 * s2) / det)  # fmt: skip


print("002 planar 2R, l1 = l2 = 1: the notes' counts against redik's closed form")
for where, (px, py), stated in [("in WS1", (1.2, 0.7), "2 regular"), ("on ∂WS1", (2.0, 0.0), "1"),
                                ("in WS2", (0.0, 0.0), "∞ (q1 undefined)")]:  # fmt: skip
    solutions = planar_2r(px, py, L1, L2)
    listed = ", ".join(f"({q[0]:.4f}, {q[1]:.4f})" for q in solutions)
    free = " with q1 free (a family: ∞¹ solutions)" if solutions[0].family is not None else ""
    print(f"  p = ({px}, {py}) {where}: notes {stated}; redik {len(solutions)}{free}: {listed}")
    if len(solutions) == 2:
        q2a, q2b = solutions[0][1], solutions[1][1]
        q1s = ", ".join(f"{algebraic_q1(px, py, q[1]):.4f} (redik {q[0]:.4f})" for q in solutions)
        print(f"    q2' = {q2a:.4f}, q2'' = {q2b:.4f}; the notes' algebraic q1: {q1s}")
    if solutions[0].singular:
        print(f"    redik: {solutions[0].singular}")
