"""Planar 2R: Newton–Raphson against gradient descent, with the classic convergence plot.

The task function is the 2R arm's tip position, x = f(q), read from the MuJoCo scene
(``robot.fk``) with its Jacobian (the xy rows of the world Jacobian). For reachable targets
away from the workspace boundary, started within 0.4 rad of a solution, Newton (full step,
J⁻¹) converges quadratically — the error roughly squares each iteration — while the
Jacobian transpose with Armijo steps decreases the error monotonically but only linearly,
needing many more iterations. (From arbitrary starts the undamped Newton step can overshoot
and wander: that is what ``solve_pose``'s damped least squares is for.)
``convergence.png`` shows both for one target.
"""

import itertools

import numpy as np

import redik
from redik.apps.plot import convergence
from redik.solvers.iterative import solve_equations

CRITERIA = {
    "newton_success_rate": ">= 1.0",
    "gradient_success_rate": ">= 1.0",
    "newton_order": ">= 1.8",
    "gradient_monotone_rate": ">= 1.0",
    "newton_mean_iterations": "<= 10",
}


def convergence_order(errors):
    """Median of log(e_{k+1}) / log(e_k) over the last steps with e_k < 0.1 (2: quadratic)."""
    errors = np.asarray(errors)
    pairs = [(a, b) for a, b in itertools.pairwise(errors) if 1e-13 < b and a < 0.1]
    return float(np.median([np.log(b) / np.log(a) for a, b in pairs])) if pairs else float("nan")


def run(ctx):
    robot = redik.load("planar_2r")

    def f(q):
        return robot.fk(q)[:2, 3]

    def jac(q):
        return robot.jacobian(q, reference="world")[:2]

    tol = 1e-10
    results = {"newton": [], "gradient": []}
    count = ctx.size(full=50, fast=10)
    for _ in ctx.progress(range(count), total=count, desc="2R targets"):
        # elbow away from 0 and ±π keeps the target off the workspace boundaries r = 0, 2
        q_true = np.array([ctx.rng.uniform(-np.pi, np.pi), ctx.rng.uniform(0.4, 2.6)])
        q_true[1] *= ctx.rng.choice([-1.0, 1.0])
        x_d = f(q_true)
        q0 = q_true + ctx.rng.uniform(-0.4, 0.4, 2)  # a start in the solution's basin
        results["newton"].append(solve_equations(f, x_d, q0, jac=jac, tol=tol, max_iterations=100))
        results["gradient"].append(
            solve_equations(
                f, x_d, q0, "transpose", jac, step="armijo", tol=tol, max_iterations=5000
            )
        )
    first = [results["newton"][0], results["gradient"][0]]
    convergence(
        first, ["Newton–Raphson (J⁻¹)", "gradient (Jᵀ, Armijo)"], ctx.path("convergence.png")
    )
    orders = [convergence_order(r.error_history) for r in results["newton"] if r.success]
    monotone = [np.all(np.diff(r.error_history) <= 1e-15) for r in results["gradient"]]
    return {
        "newton_success_rate": float(np.mean([r.success for r in results["newton"]])),
        "gradient_success_rate": float(np.mean([r.success for r in results["gradient"]])),
        "newton_mean_iterations": float(np.mean([r.iterations for r in results["newton"]])),
        "gradient_mean_iterations": float(np.mean([r.iterations for r in results["gradient"]])),
        "newton_order": float(np.nanmedian(orders)),
        "gradient_monotone_rate": float(np.mean(monotone)),
    }
