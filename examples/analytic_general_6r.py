"""Every inverse-kinematics solution of a general 6R arm, which has no closed form.

A DH table with every a_i, d_i and α_i non-zero has no two axes meeting or parallel, so no
subproblem decomposition applies; ``redik.solvers.analytic.solver_for`` falls back to the
Raghavan–Roth elimination solved as a 24 × 24 eigenproblem (Manocha & Canny 1994), which
finds all the real roots of the degree-16 polynomial — up to 16 solutions — each checked here
by MuJoCo's FK. A multistart numeric solve finds the same set, much more slowly.

Run: python examples/analytic_general_6r.py
"""

import time

import numpy as np

import redik
from redik.models.dh import DHRow
from redik.solvers import analytic
from redik.solvers.pose import solve_all

rows = [  # a (m), d (m), α (rad)
    DHRow(0.30, 0.40, 1.10),
    DHRow(0.45, 0.15, -0.70),
    DHRow(0.25, 0.20, 0.90),
    DHRow(0.20, 0.35, -1.20),
    DHRow(0.15, 0.10, 0.60),
    DHRow(0.10, 0.12, 0.80),
]
robot = redik.Robot.from_dh(rows, limits=[(-np.pi, np.pi)] * 6, name="general_6r")
solver = analytic.solver_for(robot)
print(f"{robot.name}: class {solver.kind}, method {solver.method}")

q_true = np.array([1.3, 2.2, 1.1, -0.8, 0.5, 0.4])
T = robot.fk(q_true)
start = time.perf_counter()
solutions = solver(T)
elapsed = time.perf_counter() - start
print(f"{len(solutions)} solutions in {elapsed * 1e3:.1f} ms:")
for q in solutions:
    error = np.abs(robot.fk(q) - T).max()
    print(f"  {q.label:>6}  q = {np.round(q.q, 4)}  FK error {error:.1e}")
assert any(np.abs(redik.lie.wrap_angle(q.q - q_true)).max() < 1e-9 for q in solutions)

start = time.perf_counter()
numeric = solve_all(robot, T, n_starts=300, seed=0, pos_tol=1e-9)
elapsed = time.perf_counter() - start
print(f"multistart dls (300 starts): {len(numeric)} distinct solutions in {elapsed:.2f} s")
