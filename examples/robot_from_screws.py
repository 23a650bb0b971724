"""Build a robot from screw axes (product of exponentials) — Modern Robotics Example 4.5.

The UR5 of the book, given by its space screw axes ``S_i = (ω_i, v_i)`` and home pose ``M``,
becomes a MuJoCo model whose ``ee`` site reproduces ``e^[S1]q1 ⋯ e^[S6]q6 M``.

Run: python examples/robot_from_screws.py
"""

import numpy as np

import redik
from redik import lie

W1, W2, L1, L2, H1, H2 = 0.109, 0.082, 0.425, 0.392, 0.089, 0.095  # metres
S = np.array(
    [
        [0, 0, 1, 0, 0, 0],
        [0, 1, 0, -H1, 0, 0],
        [0, 1, 0, -H1, 0, L1],
        [0, 1, 0, -H1, 0, L1 + L2],
        [0, 0, -1, -W1, L1 + L2, 0],
        [0, 1, 0, H2 - H1, 0, L1 + L2],
    ],
    dtype=float,
).T  # 6 × n, columns (ω, v) in Modern Robotics order
M = np.array([[-1, 0, 0, L1 + L2], [0, 0, 1, W1 + W2], [0, 1, 0, H1 - H2], [0, 0, 0, 1]], float)

robot = redik.Robot.from_screws(S, M, "space", limits=[(-np.pi, np.pi)] * 6, name="mr_ur5")
print(robot, "joints:", robot.joint_names)

q = np.array([0, -np.pi / 2, 0, 0, np.pi / 2, 0])
print("T(q) for the book's q = (0, −π/2, 0, 0, π/2, 0):")
print(np.round(robot.fk(q), 4))
book = np.array([[0, -1, 0, 0.095], [1, 0, 0, 0.109], [0, 0, 1, 0.988], [0, 0, 0, 1]])
print(f"max difference from the book's answer: {np.abs(robot.fk(q) - book).max():.1e}")

# Body screws B_i = [Ad_{M⁻¹}] S_i describe the same arm (T = M e^[B1]q1 ⋯ e^[Bn]qn).
# redik.lie.adjoint acts on (v, ω) twists, so swap the halves of the (ω, v) screws around it.
swap = np.r_[3:6, 0:3]
B = (lie.adjoint(lie.inverse(M)) @ S[swap])[swap]
same_arm = redik.Robot.from_screws(B, M, "body", limits=[(-np.pi, np.pi)] * 6)
q = np.random.default_rng(1).uniform(-np.pi, np.pi, 6)
print(f"space vs body screws at a random q: {np.abs(robot.fk(q) - same_arm.fk(q)).max():.1e}")
J = robot.jacobian(q, reference="space")
print("space Jacobian rank at that q:", np.linalg.matrix_rank(J))
