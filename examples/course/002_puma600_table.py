"""Notes 002 (Robotics 1, Inverse kinematics), "6R example: Unimation PUMA 600": Table I (link
parameters), the closed-form direct kinematics (n, o, a, p) and the 8 inverse solutions.

Table I in inches: α = (−90°, 0, 90°, −90°, 90°, 0), a2 = 17.000, a3 = 0.75, d3 = 4.937,
d4 = 17.000, d6 = 0, and the ranges ±160°, +45°…−225°, 225°…−45°, ±170°, ±135°, ±170°.
``redik.Robot.from_dh`` builds it; its FK is compared with the printed n, o, a, p, and its
closed form (``solver_for``, without the ranges) gives the "8 different inverse solutions";
at the pose chosen here one of them has θ4 beyond Table I's ±170°. The bundled ``puma560``
scene is this table in metres.

Slip of the notes: below the table they print "a1 = 17.000"; it is a2 (the table's a column
holds a2 and a3 only, and the printed p uses a2). With a1 = 17 the printed p does not hold,
which the output shows.

Run: python examples/course/002_puma600_table.py
"""

import math

import numpy as np

import redik
from redik.solvers.analytic import solver_for

A2, A3, D3, D4 = 17.000, 0.75, 4.937, 17.000
TABLE = [(0, 0, -math.pi / 2), (A2, 0, 0), (A3, D3, math.pi / 2), (0, D4, -math.pi / 2),
         (0, 0, math.pi / 2), (0, 0, 0)]  # (a, d, α) per joint, standard DH  # fmt: skip
RANGES = np.radians([(-160, 160), (-225, 45), (-45, 225), (-170, 170), (-135, 135), (-170, 170)])


def notes_fk(q):
    """The printed n, o, a, p of the PUMA 600 (C23 = cos(θ2 + θ3), …)."""
    C1, S1, C2, S2, C4, S4, C5, S5, C6, S6 = (
        f(q[i]) for i in (0, 1, 3, 4, 5) for f in (math.cos, math.sin)
    )
    C23, S23 = math.cos(q[1] + q[2]), math.sin(q[1] + q[2])
    n = [
        C1 * (C23 * (C4 * C5 * C6 - S4 * S6) - S23 * S5 * C6) - S1 * (S4 * C5 * C6 + C4 * S6),
        S1 * (C23 * (C4 * C5 * C6 - S4 * S6) - S23 * S5 * C6) + C1 * (S4 * C5 * C6 + C4 * S6),
        -S23 * (C4 * C5 * C6 - S4 * S6) - C23 * S5 * C6,
    ]
    o = [
        C1 * (-C23 * (C4 * C5 * S6 + S4 * C6) + S23 * S5 * S6) - S1 * (-S4 * C5 * S6 + C4 * C6),
        S1 * (-C23 * (C4 * C5 * S6 + S4 * C6) + S23 * S5 * S6) + C1 * (-S4 * C5 * S6 + C4 * C6),
        S23 * (C4 * C5 * S6 + S4 * C6) + C23 * S5 * S6,
    ]
    a = [
        C1 * (C23 * C4 * S5 + S23 * C5) - S1 * S4 * S5,
        S1 * (C23 * C4 * S5 + S23 * C5) + C1 * S4 * S5,
        -S23 * C4 * S5 + C23 * C5,
    ]
    p = [
        C1 * (D4 * S23 + A3 * C23 + A2 * C2) - S1 * D3,
        S1 * (D4 * S23 + A3 * C23 + A2 * C2) + C1 * D3,
        -(-D4 * C23 + A3 * S23 + A2 * S2),
    ]
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = np.column_stack([n, o, a]), p
    return T  # fmt: skip


robot = redik.Robot.from_dh(TABLE, limits=RANGES)
rng = np.random.default_rng(1)
samples = [robot.random_q(rng) for _ in range(20)]
worst = max(float(np.abs(robot.fk(q) - notes_fk(q)).max()) for q in samples)
print(f"002 PUMA 600: |FK of Table I − the printed n, o, a, p| ≤ {worst:.1e} on 20 random q")
as_printed = redik.Robot.from_dh([(A2, 0, -math.pi / 2), (0, 0, 0), *TABLE[2:]])  # "a1 = 17"
miss = max(float(np.abs(as_printed.fk(q)[:3, 3] - notes_fk(q)[:3, 3]).max()) for q in samples)
print(f"slip of the notes: with the printed a1 = 17.000 (a2 = 0), p misses by up to {miss:.1f} in")
scene = redik.load("puma560")
same = np.allclose([scene.lower, scene.upper], RANGES.T)
print(f"the bundled puma560's ranges are Table I's: {same}")

q = np.radians([30.0, -60.0, 120.0, 40.0, 50.0, 60.0])
solutions = solver_for(robot)(notes_fk(q), limits=None)
print(
    f"inverse solutions of the pose at q = (30°, −60°, 120°, 40°, 50°, 60°): {len(solutions)} "
    "(the notes: 8)"
)
for solution in solutions:
    error = np.abs(notes_fk(solution) - notes_fk(q)).max()
    inside = "" if robot.within_limits(solution) else "  outside Table I's ranges"
    print(f"  {solution.label:17s} {np.round(np.degrees(solution), 2)} error {error:.0e}{inside}")
