"""Panda reach with joint-limit avoidance: a QP stack of a pose task over a limit potential.

Targets are poses around the ready posture (±20 cm, ±0.5 rad). Each is solved twice from
``home`` by the task-stack driver (``redik.solve_problem``): with the pose task alone, and
with a joint-limit-avoidance task at the lower priority level, which may only use the arm's
self-motion (the pose task's null space) and so can never cost accuracy. Success: ≥ 97 %
of the targets reached within 1e-6 m and 1e-5 rad (the errors below are over those), every q
inside the joint limits, and the limit potential φ(q) = Σ((q − q_mid)/(q_max − q_min))² no
higher with the avoidance task than without on ≥ 95 % of them.
"""

import numpy as np

import redik
from redik.lie import make_pose, pose_errors, so3_exp
from redik.qp import Problem
from redik.solvers.task_stack import solve_problem
from redik.tasks import FrameTask, JointLimitAvoidanceTask

CRITERIA = {
    "success_rate": ">= 0.97",
    "max_position_error": "<= 1e-6",
    "max_rotation_error": "<= 1e-5",
    "outside_limits": "== 0",
    "avoidance_no_worse_rate": ">= 0.95",
}


def run(ctx):
    robot = redik.load("panda")
    T_home = robot.fk(robot.home)
    targets = [
        make_pose(
            T_home[:3, :3] @ so3_exp(ctx.rng.uniform(-0.5, 0.5, 3)),
            T_home[:3, 3] + ctx.rng.uniform(-0.2, 0.2, 3),
        )
        for _ in range(ctx.size(full=200, fast=20))
    ]
    potential = JointLimitAvoidanceTask().bind(robot)
    solved, iterations, outside, no_worse = [], [], 0, []
    worst_p = worst_r = 0.0
    phi_plain, phi_avoid = [], []
    for T in ctx.progress(targets, total=len(targets), desc="panda reach"):
        pose = FrameTask("ee", target=T)
        with_avoidance = Problem(robot, [pose, JointLimitAvoidanceTask(priority=1)])
        result = solve_problem(with_avoidance, robot.home)
        plain = solve_problem(Problem(robot, [FrameTask("ee", target=T)]), robot.home)
        p_err, r_err = pose_errors(robot.fk(result.q), T)  # checked by FK, not the flag
        solved.append(p_err <= 1e-6 and r_err <= 1e-5 and robot.within_limits(result.q))
        if solved[-1]:
            worst_p, worst_r = max(worst_p, p_err), max(worst_r, r_err)
        outside += not robot.within_limits(result.q)
        iterations.append(result.iterations)
        phi_avoid.append(potential.value(result.q))
        phi_plain.append(potential.value(plain.q))
        no_worse.append(phi_avoid[-1] <= phi_plain[-1] + 1e-9)
    return {
        "success_rate": float(np.mean(solved)),
        "max_position_error": worst_p,
        "max_rotation_error": worst_r,
        "mean_iterations": float(np.mean(iterations)),
        "outside_limits": float(outside),
        "avoidance_no_worse_rate": float(np.mean(no_worse)),
        "mean_limit_potential": float(np.mean(phi_avoid)),
        "mean_limit_potential_without": float(np.mean(phi_plain)),
    }
