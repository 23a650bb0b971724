"""Notes 002 (Robotics 1, Inverse kinematics), "Wrist position and E-E pose inverse solutions for
an articulated 6R robot" (Unimation PUMA 560): 4 inverse solutions for the wrist-centre position
out of singularities (left/right, up/down), 8 for the complete pose (each with its two wrists).

The bundled ``puma560`` scene is the PUMA of Paul, Shimano & Mayer (1981); the target is the pose
at a regular configuration chosen here. The closed form gives the 4 and the 8; ``solve_all``
from many random starts, without the joint limits, must find the same 8 (angles modulo 2π).

Run: python examples/course/002_puma560_solutions.py
"""

import numpy as np

import redik
from redik.lie import wrap_angle

robot = redik.load("puma560")
T = robot.fk(np.radians([30.0, -60.0, 120.0, 40.0, 50.0, 60.0]))

closed = redik.solve_all(robot, T, method="analytic", respect_limits=False)
wrist_centre = {tuple(np.round(wrap_angle(result.q[:3]), 6)) for result in closed}
searched = redik.solve_all(robot, T, n_starts=200, seed=0, respect_limits=False)
print("002 PUMA 560                       notes   redik")
print(f"  wrist-centre solutions (closed)      4   {len(wrist_centre)}")
print(f"  pose solutions (closed form)         8   {len(closed)}")
print(f"  pose solutions (solve_all, 200 starts) 8   {len(searched)}")
for result in searched:
    print(f"    {np.round(np.degrees(result.q), 2)}")
