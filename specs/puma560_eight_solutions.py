"""PUMA 560: all eight closed-form solutions of generic poses, checked by FK and by search.

Shoulder left/right × elbow up/down × wrist flip: a pose reached from random joint values in
general position has eight distinct solutions (joint limits ignored), each reproducing the
pose to 1e-10 by forward kinematics. Independently, multi-start numeric search
(``solve_all``) must find no solution outside that set, and recover most of it.
"""

import numpy as np

import redik
from redik.apps.specs import sample_poses
from redik.lie import pose_errors, wrap_angle
from redik.solvers.analytic import solver_for
from redik.solvers.pose import solve_all

CRITERIA = {
    "eight_solution_rate": ">= 1.0",
    "distinct_rate": ">= 1.0",
    "max_position_error": "<= 1e-10",
    "max_rotation_error": "<= 1e-10",
    "numeric_outside_set": "== 0",
    "numeric_recovery_rate": ">= 0.85",
}


def run(ctx):
    robot = redik.load("puma560")
    closed_form = solver_for(robot)
    poses = sample_poses(robot, ctx.rng, ctx.size(full=100, fast=12), min_sigma=0.05)
    eight, distinct, worst_p, worst_r = [], [], 0.0, 0.0
    outside, recovered, total = 0, 0, 0
    for k, T in enumerate(ctx.progress(poses, total=len(poses), desc="puma560 poses")):
        solutions = np.array([np.asarray(q) for q in closed_form(T, limits=None)])
        eight.append(len(solutions) == 8)
        gaps = np.abs(wrap_angle(solutions[:, None, :] - solutions[None, :, :])).max(axis=2)
        distinct.append(bool(np.all(gaps[~np.eye(len(solutions), dtype=bool)] > 1e-6)))
        for q in solutions:
            p_err, r_err = pose_errors(robot.fk(q), T)
            worst_p, worst_r = max(worst_p, p_err), max(worst_r, r_err)
        found = solve_all(
            robot, T, n_starts=ctx.size(full=60, fast=40), seed=ctx.seed + k,
            respect_limits=False,
        )  # fmt: skip
        hit = np.zeros(len(solutions), dtype=bool)
        for result in found:
            distance = np.abs(wrap_angle(solutions - result.q)).max(axis=1)
            if distance.min() < 1e-4:
                hit[int(distance.argmin())] = True
            else:
                outside += 1
        recovered += int(hit.sum())
        total += len(solutions)
    return {
        "eight_solution_rate": float(np.mean(eight)),
        "distinct_rate": float(np.mean(distinct)),
        "max_position_error": worst_p,
        "max_rotation_error": worst_r,
        "numeric_outside_set": float(outside),
        "numeric_recovery_rate": recovered / total,
    }
