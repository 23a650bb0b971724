"""Notes 002 (Robotics 1, Inverse kinematics), "Numerical test - 1": the RRP (polar) arm,
d1 = 0.5, to p_d = (1, 1, 1) from q⁰ = (0, 0, 1).

The notes' settings ("Numerical tests on RRP robot"): ε = 10⁻⁵ (max Cartesian error),
ε_q = 10⁻⁶ (min joint increment), k_max = 15, |det J_r| ≤ 10⁻⁴ (closeness to singularity).
Printed: the gradient with α = 1 does not converge; with α = 0.7 it converges in 11 iterations
(final error 0.57·10⁻⁵); Newton in 5; both to q* = (0.7854, 0.3398, 1.5). The task is the
position of the bundled ``rrp_polar`` scene's end-effector.

Run: python examples/course/002_rrp_test1.py
"""

from _table import attempt, table

import redik

robot = redik.load("rrp_polar")
SETTINGS = {"tol": 1e-5, "q_tol": 1e-6, "max_iterations": 15}


def position(q):
    """f_r(q) = (q3 c2 c1, q3 c2 s1, d1 + q3 s2)."""
    return robot.fk(q)[:3, 3]


def jacobian(q):
    """J_r(q) = ∂f_r/∂q: the ṗ rows of the world Jacobian."""
    return robot.jacobian(q, reference="world")[:3]


def run(name, method, **options):
    return attempt(name, lambda: redik.solve_equations(
        position, [1.0, 1.0, 1.0], [0.0, 0.0, 1.0], method, jacobian, **SETTINGS, **options
    ))  # fmt: skip


print("002 Numerical test 1 — q⁰ = (0, 0, 1)")
run("gradient α = 1 (notes: not converging)", "transpose", step=1.0)
gradient_07 = run("gradient α = 0.7", "transpose", step=0.7)
newton = run("Newton", "newton", singular_tol=1e-4, singular_test="det")
if gradient_07 is not None and newton is not None:
    table(
        "iterations and the solution reached",
        ["iterations", "q1", "q2", "q3"],
        [("grad 0.7", ("11", "0.7854", "0.3398", "1.5"), (gradient_07.iterations, *gradient_07.q)),
         ("Newton", ("5", "0.7854", "0.3398", "1.5"), (newton.iterations, *newton.q))],
    )  # fmt: skip
    table(
        "final Cartesian error of the gradient run, × 10⁻⁵",
        ["‖e‖"],
        [("grad 0.7", ("0.57",), (gradient_07.error * 1e5,))],
    )
