"""Notes 002 (Robotics 1, Inverse kinematics), "A case study", "Error function", "Error reduction
by Gradient method" and "Properties of Gradient method": the unit-link 2R arm to r_d = (1, 1).

Stated: J_r = [[−(s1 + s12), −s12], [c1 + c12, c12]] with det J_r = s2 (the 1/s2 of Newton's
step); the inverse solutions q' = (0, π/2) and q'' = (π/2, −π/2); the maximum of ‖e‖² at
(−3π/4, 0) and the saddle at (π/4, 0), where e ∈ Ker J_rᵀ and the gradient is stuck. A gain
matrix K > 0 in q̇ = J_rᵀ K e "can be used also to escape from being stuck in a stationary
point, by rotating the error e out of the kernel of J_rᵀ": the notes give no K; the rotation
by 45° (xᵀKx = cos 45° ‖x‖² > 0, not symmetric) and the step α = 0.5 are chosen here.

Run: python examples/course/002_case_study_2r.py
"""

import math

import numpy as np
from _table import attempt, table

import redik
from redik.solvers.analytic import planar_2r

arm = redik.load("planar_2r")
r_d = np.array([1.0, 1.0])


def tip(q):
    """f_r(q) = (c1 + c12, s1 + s12)."""
    return arm.fk(q)[:2, 3]


def jacobian(q):
    return arm.jacobian(q, reference="world")[:2]


q = np.array([0.7, -1.9])  # any configuration: the notes' J_r and det J_r = s2
s1, c1, s12, c12 = math.sin(q[0]), math.cos(q[0]), math.sin(q.sum()), math.cos(q.sum())
notes_J = np.array([[-(s1 + s12), -s12], [c1 + c12, c12]])
print(f"002 case study: |J_r(q) − the notes' J_r| = {np.abs(jacobian(q) - notes_J).max():.1e}, "
      f"det J_r − s2 = {np.linalg.det(jacobian(q)) - math.sin(q[1]):+.1e} at q = {q}")  # fmt: skip
solutions = planar_2r(1.0, 1.0, 1.0, 1.0)
table(
    "the two inverse solutions of r_d = (1, 1): q' = (0, π/2), q'' = (π/2, −π/2)",
    ["q1", "q2"],
    [("q'", ("0.0000", "1.5708"), solutions.by_label("elbow-down")),
     ("q''", ("1.5708", "-1.5708"), solutions.by_label("elbow-up"))],
)  # fmt: skip
for name, point in [("maximum", [-3 * math.pi / 4, 0.0]), ("saddle", [math.pi / 4, 0.0])]:
    e = r_d - tip(point)
    print(f"  {name:8s} q = {np.round(point, 4)}: ‖e‖² = {e @ e:.4f}, "
          f"‖J_rᵀ e‖ = {np.linalg.norm(jacobian(point).T @ e):.1e} (e ∈ Ker J_rᵀ)")  # fmt: skip

saddle = [math.pi / 4, 0.0]
options = {"step": 0.5, "tol": 1e-6, "max_iterations": 100}
attempt("gradient from the saddle, K = I", lambda: redik.solve_equations(
    tip, r_d, saddle, "transpose", jacobian, **options
))  # fmt: skip
K = np.array([[1.0, -1.0], [1.0, 1.0]]) / math.sqrt(2.0)  # rotation by 45°
escaped = attempt("gradient from the saddle, K = Rot(45°)", lambda: redik.solve_equations(
    tip, r_d, saddle, "transpose", jacobian, gain=K, **options
))  # fmt: skip
if escaped is not None:
    print(f"    it ends at q = {np.round(escaped.q, 4)} (q'' = (π/2, −π/2))")
