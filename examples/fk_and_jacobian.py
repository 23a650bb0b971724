"""Forward kinematics and Jacobians of a bundled arm, in the three references.

Run: python examples/fk_and_jacobian.py
"""

import numpy as np

import redik
from redik import lie

robot = redik.load("panda")
print(robot, "joints:", robot.joint_names)

q = robot.home
T = robot.fk(q)
print("ee position at home [m]:", np.round(T[:3, 3], 4))

J_space = robot.jacobian(q, reference="space")
J_body = robot.jacobian(q, reference="body")
J_world = robot.jacobian(q, reference="world")
# The space and body Jacobians are related by the adjoint of the pose (redik.core.conventions).
print("‖J_s − Ad_T J_b‖ =", np.linalg.norm(J_space - lie.adjoint(T) @ J_body))
# The world Jacobian's linear rows are the velocity of the ee origin: check by differences.
dq = 1e-6 * np.eye(robot.dof)[0]
velocity = (robot.fk(q + dq)[:3, 3] - robot.fk(q - dq)[:3, 3]) / 2e-6
print(
    "joint 1 moves the ee at",
    np.round(velocity, 6),
    "== J_world[:3, 0]",
    np.round(J_world[:3, 0], 6),
)
print("σ_min(J) at home:", np.linalg.svd(J_body, compute_uv=False)[-1].round(4))
