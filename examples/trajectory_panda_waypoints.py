"""IK along a Cartesian path: the Panda's flange through timed waypoints, warm-started.

Position moves on straight lines and orientation by SLERP between the waypoints (quintic
timing: at rest at each one). Each sample is solved from the previous solution, so damped
least squares needs one or two iterations per point; the joint trajectory is checked for
jumps, singular crossings and joint-limit contacts.

Run: python examples/trajectory_panda_waypoints.py   (writes trajectory.png to $REDIK_OUT or .)
"""

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import redik
from redik.apps.trajectory import CartesianPath, follow_path
from redik.lie import make_pose, so3_exp

robot = redik.load("panda")
T0 = robot.fk(robot.home)
waypoints = [
    T0,
    T0 @ make_pose(so3_exp(np.array([0.0, 0.4, 0.0])), [0.10, -0.15, 0.05]),
    T0 @ make_pose(so3_exp(np.array([0.3, 0.0, 0.5])), [-0.05, 0.15, 0.12]),
    T0,
]
path = CartesianPath(waypoints, times=[0.0, 1.5, 3.0, 4.0], time_scaling="quintic")
trajectory = follow_path(robot, path, robot.home, rate=100.0)
print(trajectory.summary())
print(
    "points solved in k iterations:",
    dict(enumerate(np.bincount(trajectory.iterations[1:]).tolist())),
)

out = Path(os.environ.get("REDIK_OUT", "."))
fig, (ax_q, ax_it) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
ax_q.plot(trajectory.times, trajectory.q)
ax_q.set_ylabel("joint value [rad]")
ax_q.legend(robot.joint_names, ncol=4, fontsize=7)
ax_it.step(trajectory.times, trajectory.iterations, where="mid")
ax_it.set_ylabel("IK iterations")
ax_it.set_xlabel("time [s]")
fig.tight_layout()
fig.savefig(out / "trajectory.png", dpi=100)
print(f"wrote {out / 'trajectory.png'}")
