"""Notes 000 (Ch7 Inverse Kinematics), "Preliminary: Newton–Raphson Method" and "Remarks on
Jacobian (Pseudo-)Inverse and Transpose Methods" (with 002, "Issues in implementation"): the
stopping rules, each alone, on the Case Study (unit-link 2R, x_d = (0.2, 1.3),
θ⁰ = (0.25, 0.75), λ = 0.75).

The notes' rules (no numbers printed):
- the relative change |f(x^{k+1}) − f(x^k)| / |f(x^k)| ≤ ε (the Newton preliminary);
- a threshold on the Cartesian error, possibly separate for position and orientation;
- the joint increment ‖θ^{k+1} − θ^k‖ < ε_q.
redik: ``tol=None`` asks for no error test, so ``rel_tol`` or ``q_tol`` alone is the criterion
and ends the run "converged"; ``tol=0`` would run the whole budget (an iterate table).

Slip of the notes: the preliminary writes the relative change for the function whose root is
sought (here e(θ) = x_d − f(θ)). On a converging run with step λ that ratio tends to λ (to 1
at λ = 1), never to 0, so the rule as written cannot stop a converging run; it can only stop a
stalled one. redik reads f as the task function x = f(θ) of the IK section, whose relative
change tends to 0. The table below shows both ratios.

Run: python examples/course/000_stopping_rules.py
"""

import numpy as np
from _table import attempt

import redik

arm = redik.load("planar_2r")


def tip(q):
    """x = f(θ): the (x, y) of the tip."""
    return arm.fk(q)[:2, 3]


def jacobian(q):
    return arm.jacobian(q, reference="world")[:2]


x_d, theta0 = np.array([0.2, 1.3]), [0.25, 0.75]
options = {"step": 0.75, "max_iterations": 30}

iterates = redik.solve_equations(tip, x_d, theta0, "newton", jacobian, tol=0, **options).history
x = np.array([tip(q) for q in iterates])
e = x_d - x
as_written = np.linalg.norm(np.diff(e, axis=0), axis=1) / np.linalg.norm(e[:-1], axis=1)
task_value = np.linalg.norm(np.diff(x, axis=0), axis=1) / np.linalg.norm(x[:-1], axis=1)
increment = np.linalg.norm(np.diff(iterates, axis=0), axis=1)
print("000 stopping rules on the Case Study (λ = 0.75)")
print("   k+1   ‖e(k+1) − e(k)‖/‖e(k)‖   ‖f(k+1) − f(k)‖/‖f(k)‖   ‖θ(k+1) − θ(k)‖")
for k in (0, 1, 2, 5, 10, 11, 12, 13, 20, 29):
    print(f"  {k + 1:4d}   {as_written[k]:22.3e}   {task_value[k]:22.3e}   {increment[k]:15.3e}")
first_change = 1 + int(np.argmax(task_value <= 1e-6))
first_increment = 1 + int(np.argmax(increment < 1e-6))
print(f"the rules fire after iteration {first_change} (relative change of f ≤ 1e-6) and "
      f"{first_increment} (increment < 1e-6); the ratio as written never falls below "
      f"{as_written.min():.2f}")  # fmt: skip

for name, rule in [("rel_tol = 1e-6", {"rel_tol": 1e-6}), ("q_tol = 1e-6", {"q_tol": 1e-6}),
                   ("tol = 1e-6", {"tol": 1e-6})]:  # fmt: skip
    rule = {"tol": None, **rule}
    attempt(f"{name} alone", lambda rule=rule: redik.solve_equations(
        tip, x_d, theta0, "newton", jacobian, **rule, **options
    ))  # fmt: skip
