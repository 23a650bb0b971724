"""Self-motion completeness: are independent IK solutions on the explored manifold?

For each pose (the FK of a random configuration inside the limits) of each robot,
:func:`redik.solvers.redundancy.explore_self_motion` samples the self-motion manifold; then
:func:`redik.solve_pose` solves the same pose from ``--starts`` random starts (limits
respected, a random stream independent of the exploration's) and every solution is checked
to lie within one sample spacing of the explored samples. Reports the covered fraction
(target ≥ 99 %), samples per second and time per pose, with medians over poses.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from redik.apps import measured
from redik.kinematics.robot import load
from redik.solvers.pose import solve_pose
from redik.solvers.redundancy import explore_self_motion

ROBOTS = ("panda", "iiwa14", "dexter8r")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add this benchmark's options to its ``redik bench`` subparser."""
    parser.add_argument("--robots", nargs="+", default=list(ROBOTS), help="bundled scenes")
    parser.add_argument("--poses", type=int, default=3, help="poses per robot")
    parser.add_argument("--starts", type=int, default=200, help="random IK starts per pose")
    parser.add_argument("--explore-starts", type=int, default=64, help="seeds of the explorer")
    parser.add_argument("--spacing", type=float, default=None, help="sample spacing (rad)")
    parser.add_argument("--seed", type=int, default=0)


def completeness(
    robot, T_target: np.ndarray, spacing: float | None, explore_starts: int, starts: int, seed: int
) -> dict:
    """Explore one pose, then check ``starts`` independent IK solutions against it."""
    started = time.perf_counter()
    motion = explore_self_motion(
        robot, T_target, spacing=spacing, seed=seed, n_starts=explore_starts
    )
    explore_time = time.perf_counter() - started
    rng = np.random.default_rng([seed, 1])  # independent of the exploration's starts
    solutions = []
    for q0 in robot.random_q(rng, size=starts):
        result = solve_pose(robot, T_target, q0, respect_limits=True, seed=int(rng.integers(2**63)))
        if result.success:
            solutions.append(result.q)
    distances = motion.distance_to(np.array(solutions)) if solutions else np.empty(0)
    covered = int(np.sum(distances <= motion.spacing))
    return {
        "samples": len(motion),
        "components": motion.n_components,
        "spacing": motion.spacing,
        "solutions": len(solutions),
        "covered": covered,
        "fraction": covered / len(solutions) if solutions else float("nan"),
        "worst": float(np.max(distances, initial=0.0)),
        "time": explore_time,
        "rate": len(motion) / explore_time,
    }


def run(args: argparse.Namespace) -> int:
    """One row per pose and a total per robot; exit code 1 when one covers below 99 %."""
    rng = np.random.default_rng(args.seed)
    # Times are wall clock: on a shared machine they include waiting for a core.
    loadavg = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"load average {loadavg} on {os.cpu_count()} cores")
    print(
        f"{'robot':<10}{'pose':>5}{'dim':>4}{'samples':>9}{'comp':>6}{'solved':>8}"
        f"{'covered':>9}{'worst/sp':>10}{'time s':>9}{'samples/s':>11}"
    )
    status = 0
    for name in args.robots:
        robot = load(name)
        rows = []
        for k in range(args.poses):
            T = robot.fk(robot.random_q(rng))
            row = completeness(
                robot, T, args.spacing, args.explore_starts, args.starts, args.seed + k
            )
            rows.append(row)
            print(
                f"{name:<10}{k:>5}{max(robot.dof - 6, 0):>4}"
                f"{row['samples']:>9}{row['components']:>6}"
                f"{row['solutions']:>8}{100 * row['fraction']:>8.1f}%"
                f"{row['worst'] / row['spacing']:>10.2f}{row['time']:>9.2f}{row['rate']:>11.0f}"
            )
        solved = sum(r["solutions"] for r in rows)
        covered = sum(r["covered"] for r in rows)
        fraction = covered / solved if solved else float("nan")
        print(
            f"{name:<10} total {covered}/{solved} covered ({100 * fraction:.1f} %), median "
            f"{np.median([r['time'] for r in rows]):.2f} s/pose, "
            f"{np.median([r['rate'] for r in rows]):.0f} samples/s"
        )
        measured.record(
            "self-motion completeness",
            robot=name,
            poses=len(rows),
            solutions=solved,
            covered=covered,
            covered_pct=100 * fraction,
            median_time_s=np.median([r["time"] for r in rows]),
            samples_per_s=np.median([r["rate"] for r in rows]),
        )
        if not fraction >= 0.99:
            status = 1
    return status
