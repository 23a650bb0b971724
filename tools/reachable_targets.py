"""Reachable targets that solve_batch and solve_pose leave unsolved, on many random poses.

Each target is the pose of a configuration drawn uniformly within the joint limits
(``robot.random_q(np.random.default_rng(SEED), size=COUNT)``), so every one has a solution
inside the limits. Each is solved by :func:`redik.solve_batch` (one call, ``seed``) and by
:func:`redik.solve_pose` (one call per target, ``seed``); every target either leaves
unsolved is printed with its index (its row in the draw), status and errors. The goal: none.

Usage::

    python tools/reachable_targets.py [--count 100000] [--seed 0] [--robots panda iiwa14 ur5e]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import redik
from redik.solvers.batch import Chain, forward_kinematics


def main() -> int:
    """Solve every robot's targets both ways and print the unsolved; exit code 1 if any."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=100_000)
    parser.add_argument("--seed", type=int, default=0, help="seed of the draw and of the solves")
    parser.add_argument("--robots", nargs="+", default=["panda", "iiwa14", "ur5e"])
    args = parser.parse_args()
    unsolved = 0
    for name in args.robots:
        robot = redik.load(name)
        qs = robot.random_q(np.random.default_rng(args.seed), size=args.count)
        T = forward_kinematics(Chain.from_robot(robot), qs)
        unsolved += _batch(name, robot, T, args.seed) + _single(name, robot, T, args.seed)
    print(f"unsolved in all: {unsolved} (goal 0)")
    return int(unsolved > 0)


def _batch(name: str, robot: redik.Robot, T: np.ndarray, seed: int) -> int:
    start = time.perf_counter()
    result = redik.solve_batch(robot, T, seed=seed)
    seconds = time.perf_counter() - start
    failed = np.flatnonzero(~result.success)
    for i in failed:
        print(
            f"  {name} solve_batch target {i}: {result.status_names[i]}, "
            f"{result.position_error[i]:.2g} m, {result.rotation_error[i]:.2g} rad"
        )
    print(f"{name}: solve_batch, {len(T)} targets in {seconds:.1f} s: {len(failed)} unsolved")
    return len(failed)


def _single(name: str, robot: redik.Robot, T: np.ndarray, seed: int) -> int:
    start = time.perf_counter()
    failed = 0
    for i, T_target in enumerate(T):
        result = redik.solve_pose(robot, T_target, seed=seed)
        if not result.success:
            failed += 1
            print(f"  {name} solve_pose target {i}: {result.status}: {result.message}")
    seconds = time.perf_counter() - start
    print(f"{name}: solve_pose, {len(T)} targets in {seconds:.1f} s: {failed} unsolved")
    return failed


if __name__ == "__main__":
    raise SystemExit(main())
