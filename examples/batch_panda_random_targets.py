"""Solve thousands of Panda poses at once on every core, and check a few answers with MuJoCo.

Run: python examples/batch_panda_random_targets.py
"""

import time

import numpy as np

import redik
from redik.solvers.batch import Chain, forward_kinematics, solve_batch

robot = redik.load("panda")
chain = Chain.from_robot(robot)  # the kinematic chain as arrays, compiled once
q_goal = robot.random_q(np.random.default_rng(0), size=5000)
T_targets = forward_kinematics(chain, q_goal)  # reachable by construction
T_targets[0, 0, 0] = np.nan  # a malformed target is reported, not raised

solve_batch(chain, T_targets[1:9], seed=0)  # first call loads (or compiles) the kernel
start = time.perf_counter()
result = solve_batch(chain, T_targets, seed=0)  # engine="local": compiled kernel, every core
elapsed = time.perf_counter() - start
print(result.summary())
print(f"{result.success.sum() / elapsed:,.0f} strict solves/s in {elapsed:.2f} s")
print("target 0:", result.status_names[0], "q finite:", np.isfinite(result.q[0]).all())

for i in np.flatnonzero(result.success)[:3]:
    position_error, rotation_error = redik.lie.pose_errors(robot.fk(result.q[i]), T_targets[i])
    print(
        f"target {i}: {result.iterations[i]} it, checked by MuJoCo FK: "
        f"{position_error:.1e} m, {rotation_error:.1e} rad"
    )
