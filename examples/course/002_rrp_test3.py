"""Notes 002 (Robotics 1, Inverse kinematics), "Numerical test - 3": the RRP arm (d1 = 0.5) to
p_d = (1, 1, 1) from the "double singular" start q⁰ = (0, π/2, 0) (c2 = 0 and q3 = 0).

Printed: the gradient with α = 0.7 starts toward the solution, exits the double singularity and
"slowly converges in 19 iterations" to q* = (0.7854, 0.3398, 1.5); Newton is either blocked at
the start or, without the check, explodes (NaN).

Slip of the notes: the tests' k_max is 15, so a run held to it stops at iteration 15 with the
error above ε; the 19 iterations need a budget of at least 19. Both runs are shown.

Run: python examples/course/002_rrp_test3.py
"""

import math

from _table import attempt, table

import redik

robot = redik.load("rrp_polar")
q0 = [0.0, math.pi / 2, 0.0]


def position(q):
    return robot.fk(q)[:3, 3]


def jacobian(q):
    return robot.jacobian(q, reference="world")[:3]


def run(name, method, max_iterations=15, **options):
    return attempt(name, lambda: redik.solve_equations(
        position, [1.0, 1.0, 1.0], q0, method, jacobian, tol=1e-5, q_tol=1e-6,
        max_iterations=max_iterations, **options,
    ))  # fmt: skip


print("002 Numerical test 3 — q⁰ = (0, π/2, 0)")
run("gradient α = 0.7, k_max = 15 (the notes' setting)", "transpose", step=0.7)
gradient = run("gradient α = 0.7, k_max = 19", "transpose", step=0.7, max_iterations=19)
if gradient is not None:
    table(
        "the gradient run with a budget of 19",
        ["iterations", "q1", "q2", "q3"],
        [("grad 0.7", ("19", "0.7854", "0.3398", "1.5"), (gradient.iterations, *gradient.q))],
    )
run("Newton, |det J_r| ≤ 1e-4 checked (notes: blocked at start)", "newton", singular_tol=1e-4,
    singular_test="det")  # fmt: skip
run("Newton, no check (notes: explodes)", "newton")
