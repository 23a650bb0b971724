"""A UR5e whose shoulder starts near its −2π bound reaches a pose that the short way needs
past that bound.

Boxed, an attempt stops against the bound; with ``ConfigurationLimit(periodic=True)`` a joint
whose range spans a full turn is not boxed and each iterate is turned back into range by
2π — the same pose — so the solve goes on (``solve_pose(method="qp")`` does this by
default). One attempt each, without restarts, to show the stop.
Run: python examples/qp_periodic_joints_ur5e.py
"""

import numpy as np

import redik
from redik.limits import ConfigurationLimit
from redik.qp import Problem
from redik.tasks import FrameTask

robot = redik.load("ur5e")
q_goal = np.array([-0.3, -1.2, 1.4, -1.8, -1.5, 0.4])
start = q_goal.copy()
start[0] = robot.lower[0] + 0.05  # −2π + 0.05: the goal's −0.3 ≡ −2π − 0.3 is just below
task = FrameTask("ee", target=robot.fk(q_goal))

for name, limit in (
    ("boxed", ConfigurationLimit()),
    ("periodic", ConfigurationLimit(periodic=True)),
):
    result = redik.solve_problem(
        Problem(robot, [task], [limit]), start, redik.SolveOptions(restarts=0)
    )
    print(f"{name:<9} {result.summary()}; shoulder {result.q[0]:+.4f} rad, within limits: "
          f"{robot.within_limits(result.q)}")  # fmt: skip
