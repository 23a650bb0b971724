"""Dexter-style 8R arm: a tour of the two-dimensional self-motion of one pose.

The arm holds its ``home`` end-effector pose while its eight joints move over a surface of
configurations (8 joints − 6 pose constraints = 2). ``explore_self_motion`` covers that
surface (seeded from ``home`` and random IK starts); the tour then walks across it between
two far-apart samples. Checks: every sample keeps the pose (≤ 1e-9 m, 1e-8 rad), the
samples span a 2-D set (local rank of neighbour differences), tour steps stay within the
sample spacing, and the best sample by manipulability is at least as good as ``home``.
"""

import numpy as np

import redik
from redik.solvers.redundancy import explore_self_motion, manipulability

CRITERIA = {
    "max_position_error": "<= 1e-9",
    "max_rotation_error": "<= 1e-8",
    "local_dimension": "== 2",
    "tour_max_step_over_spacing": "<= 1.01",
    "best_manipulability_gain": ">= 1.0",
}

SPACING = 0.3


def local_dimension(samples, spacing):
    """Median rank of the differences from a sample to its neighbours (within 1.5 spacing)."""
    ranks = []
    for q in samples[:: max(1, len(samples) // 40)]:
        near = samples[np.linalg.norm(samples - q, axis=1) < 1.5 * spacing] - q
        if len(near) >= 4:
            s = np.linalg.svd(near, compute_uv=False)
            ranks.append(int(np.sum(s > 0.2 * s[0])))
    return float(np.median(ranks))


def run(ctx):
    robot = redik.load("dexter8r")
    T = robot.fk(robot.home)
    motion = explore_self_motion(
        robot, T, spacing=SPACING, seed=ctx.seed, n_starts=ctx.size(full=32, fast=8),
        initial=robot.home[None], max_samples=ctx.size(full=3000, fast=300),
    )  # fmt: skip
    tour = motion.samples[motion.walk(0)]
    steps = np.linalg.norm(np.diff(tour, axis=0), axis=1)
    home_manipulability = manipulability(robot.jacobian(robot.home, reference="world"))
    best = motion.best("manipulability")
    motion.save(ctx.path("selfmotion.npz"))
    np.save(ctx.path("tour.npy"), tour)
    return {
        "n_samples": float(len(motion)),
        "n_components": float(motion.n_components),
        "max_position_error": float(motion.position_error.max()),
        "max_rotation_error": float(motion.rotation_error.max()),
        "local_dimension": local_dimension(motion.samples, SPACING),
        "tour_samples": float(len(tour)),
        "tour_max_step_over_spacing": float(steps.max() / SPACING),
        "tour_joint_travel": float(np.abs(tour[-1] - tour[0]).max()),
        "best_manipulability_gain": manipulability(robot.jacobian(best, reference="world"))
        / home_manipulability,
    }
