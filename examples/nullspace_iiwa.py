"""Null-space motion of a KUKA iiwa: move the joints while the hand stays put.

Integrates q̇ = J⁺ẋ + (I − J⁺J) q̇₀ with ẋ = 0 (hold the pose) and q̇₀ the gradient of
a secondary criterion, here the distance from the joint limits (Liégeois), and shows the
criterion improving while the end-effector pose drifts only at second order.

Run: python examples/nullspace_iiwa.py
"""

import numpy as np

import redik
from redik.criteria import joint_limit_distance, joint_limit_distance_gradient, joint_limit_margin
from redik.solvers.redundancy import nullspace_velocity

robot = redik.load("iiwa14")
q = np.array([0.4, 1.2, -1.5, -1.6, 2.2, 1.0, 0.3])
T_hold = robot.fk(q)
print("start: joint-limit margin", round(joint_limit_margin(q, robot.lower, robot.upper), 3), "rad")

dt, gain = 0.01, 200.0
for step in range(301):
    J = robot.jacobian(q, reference="body")
    # Hold the pose: a corrective body twist toward T_hold, and climb w(q) in the null space.
    twist = redik.lie.body_error_twist(robot.fk(q), T_hold) / dt
    dq0 = gain * joint_limit_distance_gradient(q, robot.lower, robot.upper)
    q = q + dt * nullspace_velocity(J, twist, dq0)
    if step % 100 == 0:
        position, rotation = redik.lie.pose_errors(robot.fk(q), T_hold)
        print(
            f"step {step:3d}: w(q) = {joint_limit_distance(q, robot.lower, robot.upper):+.4f}, "
            f"margin {joint_limit_margin(q, robot.lower, robot.upper):.3f} rad, "
            f"hand error {position:.1e} m / {rotation:.1e} rad"
        )
