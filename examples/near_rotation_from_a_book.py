"""A target typed from a book: Modern Robotics' IKinBody quiz on the 3R planar arm.

The book prints ``T_sd`` with three decimals, so its rotation block is only close to a
rotation (max|RᵀR − I| = 5.4e-5). redik projects it onto the closest rotation with a
``NearRotationWarning`` and solves; ``strict=True`` refuses it instead (see the tolerance
policy in :mod:`~redik.core.rotation_policy`). The arm: three unit links, joints about z (Lynch &
Park, Fig. 6.6; screws S_i = (0, 0, 1, 0, −(i−1), 0), home M with the tool at x = 3).

Run: python examples/near_rotation_from_a_book.py
"""

import warnings

import numpy as np

import redik

S = np.array([[0, 0, 1, 0, 0, 0], [0, 0, 1, 0, -1, 0], [0, 0, 1, 0, -2, 0]], float).T
M = np.array([[1, 0, 0, 3], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], float)
robot = redik.Robot.from_screws(S, M, "space", limits=[(-np.pi, np.pi)] * 3, name="mr_3r")

T_sd = np.array(  # as printed in the quiz
    [[-0.585, -0.811, 0, 0.076], [0.811, -0.585, 0, 2.608], [0, 0, 1, 0], [0, 0, 0, 1]]
)
defect = redik.core.rotation_policy.rotation_defect(T_sd[:3, :3])[0]
print(f"max|RᵀR − I| of the printed target: {defect:.1e}")

with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    result = redik.solve_pose(robot, T_sd, q0=np.full(3, np.pi / 4), method="newton")
for warning in caught:
    print(f"{warning.category.__name__}: {warning.message}")
print(result.summary())
print("θ =", np.round(result.q, 4))
heading = np.arctan2(T_sd[1, 0], T_sd[0, 0])
print(f"θ1 + θ2 + θ3 = {result.q.sum():.6f}, the target's heading {heading:.6f}")
print(f"FK position error against the printed target: {result.position_error:.1e} m")

try:
    redik.solve_pose(robot, T_sd, method="newton", strict=True)
except redik.InvalidPose as error:
    print("strict=True refuses it:", error)
