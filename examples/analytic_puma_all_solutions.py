"""All eight closed-form solutions of a PUMA 560 pose, checked against MuJoCo.

Loads the bundled ``puma560`` scene, builds a target by forward kinematics, solves it in
closed form (the class found from the robot's screw axes: a spherical wrist after two
intersecting axes) and prints every solution with its label (left/right, elbow up/down,
wrist flip, from each solution's geometry) and pose error. Then shows a wrist singularity, an
unreachable target and a batch.
"""

from __future__ import annotations

import numpy as np

import redik
from redik.solvers.analytic import solver_for

robot = redik.load("puma560")
solve = solver_for(robot)  # the class of its screw axes
print(f"{robot.name}: {solve.kind}, labels {solve.labels[0]} … {solve.labels[-1]}")

q_true = np.array([0.4, -0.9, 2.0, 0.3, 0.8, -0.5])
T = robot.fk(q_true)
result = solve(T, limits=None)  # every solution, joint limits ignored
print(f"\n{len(result)} solutions (target from q = {q_true}):")
for q in result:
    error = np.abs(robot.fk(q) - T).max()
    print(f"  {q.label:<18} {np.array2string(q.q, precision=3, sign=' ')}  |ΔT| = {error:.1e}")
within = solve(T)  # the scene's joint limits
print(f"within the joint limits: {list(within.labels)}")
print(f"closest to home: {within.nearest(robot.home).label}")

singular = solve(robot.fk(np.array([0.4, -0.9, 2.0, 0.3, 0.0, -0.5])), limits=None)
wrist = next(q for q in singular if q.singular)
print(f"\nθ5 = 0: {len(singular)} solutions; {wrist.label}: {wrist.singular}")
print(f"  another member of its family: {np.round(wrist.family.at(1.0), 3)}")

far = np.eye(4)
far[:3, 3] = (1.5, 0.0, 0.2)
print(f"\nunreachable: {solve(far).reason}")

rng = np.random.default_rng(0)
targets = np.stack([robot.fk(q) for q in robot.random_q(rng, size=1000)])
batch = solve.batch(targets, limits=None)  # threaded over the targets
print(f"\nbatch of {len(batch)}: q {batch.q.shape}, {batch.valid.sum(axis=1).mean():.2f} per pose")
