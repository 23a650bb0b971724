"""Notes 002 (Robotics 1, Inverse kinematics), "Dexter robot (8R arm)": m = 6 (E-E position and
orientation), n = 8 revolute joints, so ∞² inverse solutions (redundancy degree n − m = 2),
explored by a self-motion.

The bundled ``dexter8r`` (an 8R arm in Dexter's layout; the notes give no dimensions) at its
home pose: redik's self-motion of that pose is a two-dimensional family.

Run: python examples/course/002_dexter_8r.py
"""

import numpy as np

import redik

robot = redik.load("dexter8r")
T = robot.fk(robot.home)
J = robot.jacobian(robot.home)
motion = redik.explore_self_motion(robot, T, seed=0, n_starts=8, max_samples=2000)
print("002 Dexter 8R            notes   redik")
print(f"  m (task)               6       {J.shape[0]}")
print(f"  n (joints)             8       {J.shape[1]}")
print(f"  rank J at home         6       {np.linalg.matrix_rank(J)}")
print(f"  redundancy n − m       2       {motion.dimension}  (self-motion dimension)")
print(f"  self-motion samples explored: {len(motion)}")
