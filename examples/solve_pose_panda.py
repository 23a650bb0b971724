"""Solve a pose of the Panda with every method and print what each result holds.

Run: python examples/solve_pose_panda.py
"""

import numpy as np

import redik
from redik.solvers.pose import solve_pose

robot = redik.load("panda")
q_goal = robot.random_q(np.random.default_rng(0))
T_target = robot.fk(q_goal)  # reachable by construction

for method in ("dls", "newton", "hybrid", "transpose", "qp"):
    try:
        result = solve_pose(robot, T_target, q0=robot.midrange, method=method, seed=0)
    except redik.RedikError as error:  # e.g. the QP core is not installed
        print(f"{method:9s} unavailable: {error}")
        continue
    print(f"{method:9s} {result.summary()}, {result.restarts} restarts")

result = solve_pose(robot, T_target, seed=0)
position_error, rotation_error = redik.lie.pose_errors(robot.fk(result.q), T_target)
print("q =", np.round(result.q, 4))
print(f"checked by FK: {position_error:.1e} m, {rotation_error:.1e} rad, inside limits:",
      robot.within_limits(result.q))  # fmt: skip

far = redik.lie.make_pose(np.eye(3), np.array([2.0, 0.0, 0.5]))
print("out of reach:", solve_pose(robot, far, seed=0).message)
