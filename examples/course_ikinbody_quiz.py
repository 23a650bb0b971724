"""The course workflow: Modern Robotics Chapter 6, worked with redik as the book writes it.

1. Newton–Raphson on f(x, y) = (x² − 9, y² − 4) from (1, 1): the iterate table (tol=0).
2. Example 6.1: IKinBody on the planar 2R arm, the book's table of θ^i, ‖ω_b‖, ‖v_b‖.
3. The Chapter 6 quiz: IKinBody on the planar 3R arm to a target typed with 3 decimals
   (projected onto SO(3), with a warning), with the book's stopping rule ‖ω_b‖ ≤ ε_ω,
   ‖v_b‖ ≤ ε_v (stop="twist").

Run: python examples/course_ikinbody_quiz.py
"""

import math
import warnings

import numpy as np

import redik
from redik.lie import inverse, se3_log

# 1. Two Newton iterations on a user's function, every iteration kept (tol=0).
root = redik.solve_equations(lambda x: np.array([x[0] ** 2 - 9, x[1] ** 2 - 4]), [0, 0], [1, 1],
                             method="newton", tol=0, max_iterations=2)  # fmt: skip
print("Newton on (x² − 9, y² − 4) from (1, 1):")
for i, x in enumerate(root.history):
    print(f"  x^{i} = ({x[0]:.4g}, {x[1]:.4g})")

# 2. Example 6.1: θ_d = (30°, 90°), θ0 = (0°, 30°), ε_ω = 0.001, ε_v = 1e-4.
arm = redik.Robot.from_file(redik.models.scene_path("planar_2r"))
T_d = arm.fk(np.radians([30, 90]))
table = redik.solve_pose(arm, T_d, np.radians([0, 30]), method="newton", stop="twist",
                         pos_tol=1e-4, rot_tol=1e-3, restarts=0)  # fmt: skip
print("\nExample 6.1 (IKinBody, 2R):")
print("  i   (θ1, θ2) deg        (x, y)          ‖ω_b‖   ‖v_b‖")
for i, q in enumerate(table.history):
    T = arm.fk(q)
    V_b = se3_log(inverse(T) @ T_d)  # (v, ω): redik's twist order
    theta = np.degrees(q)
    print(f"  {i}   ({theta[0]:6.2f}, {theta[1]:6.2f})   ({T[0, 3]:.3f}, {T[1, 3]:.3f})"
          f"   {np.linalg.norm(V_b[3:]):.3f}   {np.linalg.norm(V_b[:3]):.3f}")  # fmt: skip

# 3. The quiz: T_sd typed from the book, θ0 = (π/4, π/4, π/4).
T_sd = np.array([[-0.585, -0.811, 0, 0.076], [0.811, -0.585, 0, 2.608], [0, 0, 1, 0],
                 [0, 0, 0, 1]])  # fmt: skip
robot = redik.Robot.from_file(redik.models.scene_path("planar_3r"))
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always", redik.NearRotationWarning)
    quiz = redik.solve_pose(robot, T_sd, [math.pi / 4] * 3, method="newton", stop="twist",
                            pos_tol=1e-4, rot_tol=1e-3, restarts=0)  # fmt: skip
for warning in caught:
    print(f"\nwarning: {warning.message}")
print(f"IKinBody quiz: {quiz.summary()}")
print(f"  θ = ({', '.join(f'{value:.3f}' for value in quiz.q)})  (the book: 0.925, 0.586, 0.684)")
