"""UR5e: every closed-form solution against the numeric solver on the same random poses.

For poses reached by random joint values, the closed-form UR solver returns up to eight
joint vectors; each must reproduce the pose to 1e-10. The numeric solver (damped least
squares from the home posture, with restarts) must reach the pose to its tolerances, and the
configuration it lands on must be one of the closed-form branches (angles modulo 2π).
The ratio of their times is reported (informational: it depends on the machine's Python).
"""

import time

import numpy as np

import redik
from redik.apps.specs import sample_poses
from redik.lie import pose_errors, wrap_angle
from redik.solvers.analytic import solver_for
from redik.solvers.pose import solve_pose

CRITERIA = {
    "analytic_success_rate": ">= 1.0",
    "max_analytic_position_error": "<= 1e-10",
    "max_analytic_rotation_error": "<= 1e-10",
    "numeric_success_rate": ">= 1.0",
    "numeric_branch_match_rate": ">= 1.0",
}


def run(ctx):
    robot = redik.load("ur5e")
    closed_form = solver_for(robot)
    poses = sample_poses(robot, ctx.rng, ctx.size(full=200, fast=15), min_sigma=0.05)
    analytic_ok, numeric_ok, matched, counts, iterations = [], [], [], [], []
    worst_p, worst_r, numeric_p, numeric_r = 0.0, 0.0, 0.0, 0.0
    analytic_time = numeric_time = 0.0
    for T in ctx.progress(poses, total=len(poses), desc="ur5e poses"):
        start = time.perf_counter()
        solutions = closed_form(T, limits=None)
        analytic_time += time.perf_counter() - start
        errors = np.array([pose_errors(robot.fk(np.asarray(q)), T) for q in solutions])
        counts.append(len(solutions))
        analytic_ok.append(len(solutions) > 0)
        if len(solutions):
            worst_p = max(worst_p, float(errors[:, 0].max()))
            worst_r = max(worst_r, float(errors[:, 1].max()))

        start = time.perf_counter()
        result = solve_pose(robot, T, seed=ctx.seed)
        numeric_time += time.perf_counter() - start
        numeric_ok.append(result.success)
        iterations.append(result.iterations)
        p_err, r_err = pose_errors(robot.fk(result.q), T)
        numeric_p, numeric_r = max(numeric_p, p_err), max(numeric_r, r_err)
        # The numeric answer is a branch of the closed form (within its own tolerance).
        gaps = [np.abs(wrap_angle(result.q - np.asarray(q))).max() for q in solutions]
        matched.append(bool(gaps) and min(gaps) < 1e-4)
    return {
        "analytic_success_rate": float(np.mean(analytic_ok)),
        "mean_solutions_per_pose": float(np.mean(counts)),
        "max_analytic_position_error": worst_p,
        "max_analytic_rotation_error": worst_r,
        "numeric_success_rate": float(np.mean(numeric_ok)),
        "max_numeric_position_error": numeric_p,
        "max_numeric_rotation_error": numeric_r,
        "numeric_branch_match_rate": float(np.mean(matched)),
        "mean_numeric_iterations": float(np.mean(iterations)),
        "numeric_over_analytic_time": numeric_time / analytic_time,
    }
