"""Notes 000 (Ch7 Inverse Kinematics), "Optimization-based Inverse Kinematics": the joint-limit
cost φ(θ) = Σ_i ((θ_i − θ_i,mid) / (θ_i,max − θ_i,min))².

The notes print no numbers: the PUMA's ranges (the bundled ``puma560``, 002's Table I) and the
configuration θ are chosen here. The notes' sum is evaluated as written, beside
``redik.criteria.joint_limit_potential`` (the same cost, from each joint's deviation from the
middle of its range and the range's inverse).

Run: python examples/course/000_joint_limit_cost.py
"""

import numpy as np

import redik
from redik.criteria import joint_limit_potential, joint_limit_scaling

robot = redik.load("puma560")
theta = np.radians([30.0, -60.0, 120.0, 40.0, 50.0, 60.0])
middle = (robot.lower + robot.upper) / 2
notes = float(np.sum(((theta - middle) / (robot.upper - robot.lower)) ** 2))
scale, centre = joint_limit_scaling(robot.lower, robot.upper)
ours = float(joint_limit_potential(theta - centre, scale))
print("000 joint-limit cost φ(θ), PUMA 560 ranges, θ = (30°, −60°, 120°, 40°, 50°, 60°)")
print(f"  the notes' sum {notes:.15f}")
print(f"  redik          {ours:.15f}   difference {ours - notes:+.1e}")
