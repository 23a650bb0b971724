"""Every closed-form solution of a 6R arm given only by its screw axes (subproblem decomposition).

An elbow arm (waist about z, shoulder and elbow about y) with a ZYX wrist — axes z, y, x
through one point, the yaw-pitch-roll wrist of Modern Robotics §6.1.1 — is built with
``Robot.from_screws``; ``redik.solvers.analytic.solver_for`` recognises its geometry from the screws
(spherical wrist, axes 1 and 2 meeting) and returns all eight solutions, each checked here by FK.

Run: python examples/analytic_screws_elbow_zyx.py
"""

import numpy as np

import redik
from redik.solvers import analytic

L0, L1, L2, L3 = 0.35, 0.45, 0.40, 0.10  # base height, upper arm, forearm, tool (m)
points = np.array(
    [[0, 0, 0], [0, 0, L0], [L1, 0, L0], [L1 + L2, 0, L0], [L1 + L2, 0, L0], [L1 + L2, 0, L0]]
)
axes = np.array([[0, 0, 1], [0, 1, 0], [0, 1, 0], [0, 0, 1], [0, 1, 0], [1, 0, 0]], float)
S = np.vstack([axes.T, np.cross(-axes, points).T])  # S_i = (ω_i, −ω_i × q_i), 6 × 6
M = np.eye(4)
M[:3, 3] = (L1 + L2 + L3, 0.0, L0)

robot = redik.Robot.from_screws(S, M, limits=[(-np.pi, np.pi)] * 6, name="elbow_zyx")
solver = analytic.solver_for(robot)
print(f"{robot.name}: {solver.kind} (reversed: {solver.reversed})")

q_true = np.array([0.4, -0.6, 1.1, 0.3, -0.7, 1.2])
T = robot.fk(q_true)
solutions = solver(T)
print(f"{len(solutions)} solutions of the pose reached by q = {q_true}:")
for q in solutions:
    error = np.abs(robot.fk(q) - T).max()
    print(f"  {q.label:>8}  q = {np.round(q.q, 4)}  FK error {error:.1e}")
assert any(np.allclose(q.q, q_true) for q in solutions)

# The compiled path: the same solutions as a plain (k, 6) array, no labels.
print("raw array:", solver.raw(T).shape)
