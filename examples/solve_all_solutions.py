"""All the distinct inverse-kinematics solutions of a UR5e pose, found from random starts.

A 6R arm with this geometry has up to eight solutions (shoulder, elbow, wrist); with joint
ranges of ±2π every angle is compared modulo 2π.

Run: python examples/solve_all_solutions.py
"""

import numpy as np

import redik
from redik.solvers.pose import solve_all

robot = redik.load("ur5e")
T_target = robot.fk(np.array([0.3, -1.2, 1.4, -1.6, -1.5, 0.4]))
solutions = solve_all(robot, T_target, n_starts=200, seed=0)
print(f"{len(solutions)} distinct solutions:")
for solution in solutions:
    position_error, rotation_error = redik.lie.pose_errors(robot.fk(solution.q), T_target)
    angles = np.round(redik.lie.wrap_angle(solution.q), 3)
    print(f"  q = {angles}  ({position_error:.0e} m, {rotation_error:.0e} rad)")
