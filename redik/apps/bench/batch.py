"""Batch IK throughput: strict solves per second of solve_batch beside a solve_pose loop.

For each robot and batch size, reachable targets (poses of random configurations) are
solved by :func:`redik.solvers.batch.solve_batch` on one thread (the kernel unthreaded, in this
process), on every core by threads (``engine="local"``, the default) and on every core by a
process pool (``engine="process"``; the pool is started before timing), and a subsample by
the single-target :func:`redik.solvers.pose.solve_pose` in a Python loop. A *strict* solve meets
``pos_tol`` = 1e-6 m and ``rot_tol`` = 1e-5 rad within the joint limits. Rates are medians
over ``--repeats`` runs of wall-clock time; the CPU-time rate (this process's CPU time, so
shown for the in-process runs) is less disturbed by other load on a shared machine, and the
load average is printed at start and end. The target: at least 100,000 strict 7-DoF solves
per second on every core at ≥ 99.99 % strict success.

Two ratios follow each robot, each from runs alternated in one loop (medians): the
per-thread throughput of ``solve_batch`` (the kernel on one thread, in this process) over
that of the ``solve_pose`` loop on the same ``--single`` targets, by CPU time (goal ≥ 4),
and the wall-clock rate of two threads over one on the largest batch (goal ≥ 1.8).
"""

from __future__ import annotations

import argparse
import functools
import statistics
import time
from collections.abc import Callable
from typing import TypeVar

import numba
import numpy as np

from redik.apps import measured
from redik.apps.bench import load_average
from redik.kinematics.robot import Robot, load
from redik.solvers.batch import Chain, forward_kinematics, solve_batch
from redik.solvers.batch.engines import default_workers
from redik.solvers.pose import solve_pose

_T = TypeVar("_T")

TARGET_RATE = 100_000
TARGET_SUCCESS = 0.9999
TARGET_PER_THREAD = 4.0
"""Goal of ``solve_batch`` on one thread over the ``solve_pose`` loop, per target."""
TARGET_TWO_THREADS = 1.8
"""Goal of ``solve_batch`` on two threads over one."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add this benchmark's options to its ``redik bench`` subparser."""
    parser.add_argument("--robots", nargs="+", default=["panda", "iiwa14", "ur5e"])
    parser.add_argument("--sizes", nargs="+", type=int, default=[1_000, 10_000, 100_000])
    parser.add_argument("--repeats", type=int, default=3, help="runs per case; median reported")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: all)")
    parser.add_argument("--single", type=int, default=2000, help="targets for the solve_pose loop")
    parser.add_argument("--seed", type=int, default=0)


def _timed(fn: Callable[[], _T]) -> tuple[float, float, _T]:
    """``(wall seconds, CPU seconds, fn())``."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return time.perf_counter() - wall, time.process_time() - cpu, out


def _median_rate(solve: Callable[[], np.ndarray], repeats: int) -> tuple[float, float, float]:
    """``(median wall rate, median CPU rate, success fraction)`` of ``repeats`` runs.

    ``solve()`` returns the strict success mask of its targets; a rate counts the solved ones.
    The median, because one run is easily slowed by a garbage collection or another process.
    """
    walls, cpus, success = [], [], 0.0
    for _ in range(repeats):
        wall, cpu, mask = _timed(solve)
        solved = int(mask.sum())
        walls.append(solved / wall)
        cpus.append(solved / cpu if cpu > 0 else float("nan"))
        success = solved / mask.size if mask.size else 0.0
    return statistics.median(walls), statistics.median(cpus), success


def _batch_success(chain: Chain, T: np.ndarray, seed: int, engine: str, workers: int) -> np.ndarray:
    """The success mask of ``solve_batch`` over ``T`` on ``engine`` with ``workers``."""
    return solve_batch(chain, T, seed=seed, engine=engine, workers=workers).success


def _loop_success(robot: Robot, T: np.ndarray, seed: int) -> np.ndarray:
    """The success mask of a ``solve_pose`` loop over ``T`` (target ``i`` with ``seed + i``)."""
    return np.array([solve_pose(robot, Ti, seed=seed + i).success for i, Ti in enumerate(T)])


def _alternated(
    runs: dict[object, Callable[[], object]], repeats: int, part: int
) -> dict[object, float]:
    """Median of ``_timed(fn)[part]`` (0: wall, 1: CPU seconds) of each run, alternated."""
    times: dict[object, list[float]] = {label: [] for label in runs}
    for _ in range(repeats):
        for label, fn in runs.items():
            wall, cpu, _ = _timed(fn)
            times[label].append(cpu if part else wall)
    return {label: statistics.median(samples) for label, samples in times.items()}


def _print_ratios(
    name: str, robot: Robot, chain: Chain, T_all: np.ndarray, args: argparse.Namespace
) -> None:
    """The per-thread ratio to the ``solve_pose`` loop and the two-thread ratio.

    Per thread is CPU time (both run on this process's one thread, so another process's load
    does not enter it); two threads against one is wall time.
    """
    T_single, T_large = T_all[: args.single], T_all[: max(args.sizes)]

    def batch(T: np.ndarray, threads: int) -> Callable[[], object]:
        return lambda: solve_batch(chain, T, seed=args.seed, engine="local", workers=threads)

    loop = functools.partial(_loop_success, robot, T_single, args.seed)
    single = _alternated({"batch": batch(T_single, 1), "loop": loop}, args.repeats, 1)
    per_thread = single["loop"] / single["batch"]
    print(
        f"{name}: per thread (CPU), solve_batch {1e6 * single['batch'] / len(T_single):.1f} us"
        f" / solve_pose loop {1e6 * single['loop'] / len(T_single):.1f} us per target: "
        f"{per_thread:.2f}x (goal ≥ {TARGET_PER_THREAD:g}x; {len(T_single)} targets)"
    )
    two_threads = None
    # numba's stubs omit config.NUMBA_NUM_THREADS (the thread pool's size).
    if numba.config.NUMBA_NUM_THREADS >= 2:  # type: ignore[attr-defined]
        threads = _alternated({1: batch(T_large, 1), 2: batch(T_large, 2)}, args.repeats, 0)
        two_threads = threads[1] / threads[2]
        print(
            f"{name}: solve_batch on 2 threads / 1 thread (wall): {two_threads:.2f}x "
            f"(goal ≥ {TARGET_TWO_THREADS:g}x; {len(T_large)} targets)"
        )
    measured.record("batch ratios", robot=name, per_thread=per_thread, two_threads=two_threads)


def run(args: argparse.Namespace) -> int:
    """Rates per robot, size and engine, then the verdict on the 7-DoF target."""
    workers = args.workers or default_workers()
    print(f"strict solves/s (pos 1e-6 m, rot 1e-5 rad, limits); {workers} workers")
    print(load_average("load average at start"))
    print(f"{'robot':<8}{'batch':>8}{'engine':>20}{'wall /s':>11}{'cpu /s':>11}{'success':>10}")
    best: dict[str, tuple[float, float]] = {}
    for name in args.robots:
        robot = load(name)
        chain = Chain.from_robot(robot)
        q = robot.random_q(args.seed, size=max(args.sizes))
        T_all = forward_kinematics(chain, q)
        # Start the pool and load the compiled kernel before timing: paid once per session.
        for engine, count in (("process", workers), ("process", 1), ("local", workers)):
            solve_batch(chain, T_all[: 2 * workers], engine=engine, workers=count, chunk_size=1)
        runs = (
            ("process", 1, "1 thread"),
            ("local", workers, f"{workers} threads"),
            ("process", workers, f"{workers} processes"),
        )
        for size in args.sizes:
            T = T_all[:size]
            for engine, count, label in runs:
                rate, cpu_rate, success = _median_rate(
                    functools.partial(_batch_success, chain, T, args.seed, engine, count),
                    args.repeats,
                )
                in_process = engine == "local" or count == 1
                cpu_text = f"{cpu_rate:>11,.0f}" if in_process else f"{'':>11}"
                print(
                    f"{name:<8}{size:>8}{label:>20}{rate:>11,.0f}{cpu_text}{100 * success:>9.2f}%"
                )
                measured.record(
                    "batch throughput",
                    robot=name,
                    batch=size,
                    engine=label.split()[-1],
                    workers=count,
                    wall_per_s=rate,
                    cpu_per_s=cpu_rate if in_process else None,
                    success_pct=100 * success,
                )
                if count == workers and success >= TARGET_SUCCESS:
                    best[name] = max(best.get(name, (0.0, 0.0)), (rate, success))
        T_single = T_all[: args.single]
        solve_pose(robot, T_single[0], seed=args.seed)  # load the compiled kernel before timing
        rate, cpu_rate, success = _median_rate(
            functools.partial(_loop_success, robot, T_single, args.seed), args.repeats
        )
        print(
            f"{name:<8}{args.single:>8}{'solve_pose loop':>20}{rate:>11,.0f}{cpu_rate:>11,.0f}"
            f"{100 * success:>9.2f}%"
        )
        measured.record(
            "batch throughput",
            robot=name,
            batch=args.single,
            engine="solve_pose loop",
            workers=1,
            wall_per_s=rate,
            cpu_per_s=cpu_rate,
            success_pct=100 * success,
        )
        _print_ratios(name, robot, chain, T_all, args)
    for name, (rate, success) in best.items():
        robot = load(name)
        if robot.dof == 7:
            verdict = "meets" if rate >= TARGET_RATE else "misses"
            print(
                f"{name} (7-DoF): best all-core rate {rate:,.0f}/s at {100 * success:.2f} % "
                f"— {verdict} the {TARGET_RATE:,}/s target at ≥ {100 * TARGET_SUCCESS:.2f} %"
            )
    print(load_average("load average at end"))
    return 0
