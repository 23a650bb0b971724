"""Notes 002 (Robotics 1, Inverse kinematics), "Numerical test - 2": the RRP arm (d1 = 0.5) to
p_d = (1, 1, 1) from the singular start q⁰ = (−π/4, π/2, 1) (c2 = 0, so det J_r = 0).

The settings of test 1 (ε = 10⁻⁵, ε_q = 10⁻⁶, k_max = 15, |det J_r| ≤ 10⁻⁴). The notes print
outcomes, no numbers: Newton with the singularity check is blocked at the start; without it, it
diverges; the gradient starts toward the solution and stops where the error e lies in
Ker J_rᵀ.

Run: python examples/course/002_rrp_test2.py
"""

import math

import numpy as np
from _table import attempt

import redik

robot = redik.load("rrp_polar")
SETTINGS = {"tol": 1e-5, "q_tol": 1e-6, "max_iterations": 15}
q0 = [-math.pi / 4, math.pi / 2, 1.0]
p_d = np.array([1.0, 1.0, 1.0])


def position(q):
    return robot.fk(q)[:3, 3]


def jacobian(q):
    return robot.jacobian(q, reference="world")[:3]


def run(name, method, **options):
    return attempt(name, lambda: redik.solve_equations(
        position, p_d, q0, method, jacobian, **SETTINGS, **options
    ))  # fmt: skip


print(
    f"002 Numerical test 2 — q⁰ = (−π/4, π/2, 1), det J_r(q⁰) = {np.linalg.det(jacobian(q0)):.0e}"
)
run("Newton, |det J_r| ≤ 1e-4 checked (notes: blocked at start)", "newton", singular_tol=1e-4,
    singular_test="det")  # fmt: skip
run("Newton, no check (notes: it diverges)", "newton")
gradient = run("gradient α = 0.7 (notes: stops in singularity)", "transpose", step=0.7)
if gradient is not None:
    e = p_d - position(gradient.q)
    print(f"    stops at q = {np.round(gradient.q, 4)} with e = {np.round(e, 4)}, "
          f"‖J_rᵀ e‖ = {np.linalg.norm(jacobian(gradient.q).T @ e):.0e}: e ∈ Ker J_rᵀ")  # fmt: skip
