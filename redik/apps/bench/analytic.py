"""Closed-form IK (PUMA 560, UR5e, planar 2R): µs per pose, single and batched, vs iterative DLS.

Protocol: for each scene, ``--batch`` targets are the FK of configurations drawn uniformly
within the joint limits (world frame, as ``robot.fk`` returns them); the first ``--n`` of them
are solved one at a time. In the same run:

- *single*: the scene's :func:`redik.solvers.analytic.solver_for` solver, one pose per call (robot
  limits applied, every solution returned);
- *batched*: the vectorised solver (``puma_batch``, ``ur_batch``, ``planar_2r_batch``) on all
  ``--batch`` targets at once, including the world-to-base transform and the robot limits;
- *dls*: :func:`redik.solve_pose` with ``method="dls"`` on the first ``--n`` targets from the
  home keyframe (default restarts), which returns one solution.

Single and dls times are the median over every call of every repeat; batched is the median
over repeats of the batch time divided by ``--batch``. Speed-ups are ratios of those medians.

A second table compares, for the 6R scenes, the compiled subproblem-decomposition path
(:meth:`redik.solvers.analytic.DecomposedSolver.raw`: every solution as an array, FK-verified, no
limits) with the ``ik-geo`` package (Elias & Wen's Rust IK-Geo, ``ik_geo.Robot`` of the same
geometry class built from the same screw axes) when it is installed: the same ``--n`` poses,
the two calls interleaved pose by pose (alternating which goes first, as the first call on
a pose pays for loading it into cache), median µs per call, their ratio, the labelled call
(:meth:`~redik.solvers.analytic.DecomposedSolver.__call__`, an ``IKSolutions`` with labels
and families, timed on each pose before the pair) and its ratio to ik-geo, the mean number of
solutions each returns and the largest FK error (by ``robot.fk``) among ik-geo's answers that
are not flagged least-squares. The load average is printed with it.
A third table times the general 6R solver (:mod:`redik.solvers.analytic.general`, every
solution of an arm with no closed form) against a multistart ``dls`` ``solve_all`` and
ik-geo's ``gen_six_dof`` (IK-Geo's 2-D search) on the same poses, with the share of the
elimination's solutions each finds and the FK error of its answers.
``--clock cpu`` times with the process CPU clock instead of the wall clock: on a shared,
loaded machine it leaves out the time spent waiting for a core.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from redik.kinematics.robot import Robot, load
from redik.solvers.analytic import (
    AnalyticSolver,
    BatchSolutions,
    planar_2r_batch,
    puma_batch,
    solver_for,
    ur_batch,
)
from redik.solvers.pose import solve_pose

ROBOTS = ("puma560", "ur5e", "planar_2r")
CLOCKS: dict[str, Callable[[], float]] = {"wall": time.perf_counter, "cpu": time.process_time}

#: ``batch(T_base, params, limits)`` for a (B, 4, 4) stack of targets in the arm's base frame.
Batch = Callable[[np.ndarray, dict, tuple[np.ndarray, np.ndarray]], BatchSolutions]

BATCH: dict[str, Batch] = {
    "puma": lambda T, p, limits: puma_batch(T, p["a2"], p["a3"], p["d3"], p["d4"], limits=limits),
    "ur": lambda T, p, limits: ur_batch(
        T, p["d1"], p["a2"], p["a3"], p["d4"], p["d5"], p["d6"], limits=limits
    ),
    "planar_2r": lambda T, p, limits: planar_2r_batch(T[:, :2, 3], p["l1"], p["l2"], limits=limits),
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--n", type=int, default=300, help="targets solved one by one (default 300)"
    )
    parser.add_argument(
        "--batch", type=int, default=2000, help="targets in the batched call (default 2000)"
    )
    parser.add_argument("--repeats", type=int, default=5, help="repeats (default 5)")
    parser.add_argument("--robots", nargs="+", default=list(ROBOTS), help="scenes to use")
    parser.add_argument("--seed", type=int, default=0, help="seed of the targets")
    parser.add_argument(
        "--clock", choices=sorted(CLOCKS), default="wall", help="wall (default) or cpu time"
    )
    parser.add_argument(
        "--no-dls", action="store_true", help="skip the iterative reference (closed form only)"
    )
    parser.add_argument(
        "--no-ik-geo", action="store_true", help="skip the comparison with the ik-geo package"
    )
    parser.add_argument(
        "--no-general", action="store_true", help="skip the general 6R table (no closed form)"
    )


def run(args: argparse.Namespace) -> int:
    print(
        f"redik bench analytic: targets = FK of q uniform in the limits; {args.n} solved one "
        f"by one (single, dls = solve_pose from home), {max(args.batch, args.n)} batched; "
        f"median µs per pose ({args.clock} clock) over {args.repeats} repeats; load average "
        + ", ".join(f"{x:.2f}" for x in os.getloadavg())
    )
    header = (
        f"{'robot':<10}{'single':>9}{'batched':>9}{'dls':>10}{'dls ok':>8}"
        f"{'dls/single':>12}{'dls/batched':>13}{'solutions':>11}"
    )
    print(header)
    for name in args.robots:
        row = measure(
            load(name),
            args.n,
            args.batch,
            args.repeats,
            args.seed,
            dls=not args.no_dls,
            clock=CLOCKS[args.clock],
        )
        dls = row["dls_us"]
        reference = (
            f"{dls:>10.1f}{row['dls_success']:>8.0%}"
            f"{dls / row['single_us']:>11.0f}×{dls / row['batch_us']:>12.0f}×"
            if not args.no_dls
            else f"{'-':>10}{'-':>8}{'-':>12}{'-':>13}"
        )
        print(
            f"{name:<10}{row['single_us']:>9.1f}{row['batch_us']:>9.2f}{reference}"
            f"{row['solutions']:>11.2f}"
        )
    if not args.no_ik_geo:
        compare_ik_geo(args)
    if not args.no_general:
        compare_general(args)
    return 0


#: The general 6R arm of the third table (every a, d, α non-zero: no decomposition fits);
#: the arm of ``examples/analytic_general_6r.py``.
GENERAL_ROWS = (
    (0.30, 0.40, 1.10),
    (0.45, 0.15, -0.70),
    (0.25, 0.20, 0.90),
    (0.20, 0.35, -1.20),
    (0.15, 0.10, 0.60),
    (0.10, 0.12, 0.80),
)


def compare_general(args: argparse.Namespace, n_poses: int = 20, n_starts: int = 100) -> None:
    """The third table: the general 6R solver (:mod:`redik.solvers.analytic.general`) on
    ``n_poses`` FK targets of a fixed general arm (:data:`GENERAL_ROWS`), beside a multistart
    ``dls`` :func:`~redik.solvers.pose.solve_all` (``n_starts`` random starts) and, when
    installed, ik-geo's general 6-DOF solver (``ik_geo.Robot.gen_six_dof``, IK-Geo's 2-D
    search) on the same poses, calls interleaved per pose: median ms per call, answers per
    pose, the share of the elimination's solutions each finds (within 1e-5 rad for dls, 1e-2
    rad for ik-geo, whose answers are approximate) and the largest FK error (``robot.fk``)
    among its answers."""
    from redik.models.dh import DHRow
    from redik.solvers.pose import solve_all

    robot = Robot.from_dh(
        [DHRow(*row) for row in GENERAL_ROWS], limits=[(-np.pi, np.pi)] * 6, name="general_6r"
    )
    solver = solver_for(robot)
    methods: dict[str, tuple[Callable[[np.ndarray], np.ndarray], float]] = {
        "elimination (every root)": (lambda T: solver(T).as_array(), 1e-9),
        f"dls solve_all ({n_starts} starts)": (
            lambda T: np.array(
                [r.q for r in solve_all(robot, T, n_starts=n_starts, seed=0, pos_tol=1e-9)]
            ).reshape(-1, 6),
            1e-5,
        ),
    }
    if not args.no_ik_geo:
        try:
            import ik_geo

            methods["ik-geo gen_six_dof (2-D search)"] = (_ik_geo_general(robot, ik_geo), 1e-2)
        except ImportError:
            pass
    clock = CLOCKS[args.clock]
    rng = np.random.default_rng(args.seed)
    targets = [robot.fk(q) for q in robot.random_q(rng, size=n_poses)]
    for call, _ in methods.values():
        call(targets[0])  # compiles / warms up
    times: dict[str, list[float]] = {name: [] for name in methods}
    answers: dict[str, list[np.ndarray]] = {name: [] for name in methods}
    for T in targets:
        for name, (call, _) in methods.items():
            start = clock()
            found = call(T)
            times[name].append(clock() - start)
            answers[name].append(found)
    load_average = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(
        f"\ngeneral 6R (DH rows a, d, α all non-zero; {solver.method}), {n_poses} poses, "
        f"interleaved, median ms per call ({args.clock} clock); load average {load_average}"
    )
    print(f"{'method':<34}{'ms':>9}{'answers':>9}{'of every root':>15}{'max FK err':>12}")
    exact = answers["elimination (every root)"]
    total = sum(len(e) for e in exact)
    for name, (_, match) in methods.items():
        matched, worst = 0, 0.0
        for T, reference, found in zip(targets, exact, answers[name], strict=True):
            for q in found:
                worst = max(worst, float(np.abs(robot.fk(q) - T).max()))
            if len(found):
                gap = np.abs(np.angle(np.exp(1j * (reference[:, None] - found[None])))).max(2)
                matched += int((gap.min(axis=1) < match).sum())
        print(
            f"{name:<34}{1e3 * statistics.median(times[name]):>9.2f}"
            f"{np.mean([len(f) for f in answers[name]]):>9.2f}"
            f"{matched / total:>15.0%}{worst:>12.1e}"
        )


def _ik_geo_general(robot: Robot, ik_geo: Any) -> Callable[[np.ndarray], np.ndarray]:
    """ik-geo's ``gen_six_dof`` for the arm's screw chain: ``T -> (k, 6)`` answers (its
    least-squares ones included: it flags nearly all of them so)."""
    from redik.solvers.analytic.decomposed import Chain, screws_of

    chain = Chain.from_screws(*screws_of(robot))
    offsets = np.vstack([chain.a[0], np.diff(chain.a, axis=0), chain.M[:3, 3] - chain.a[5]])
    reference = ik_geo.Robot.gen_six_dof(chain.h.tolist(), offsets.tolist())
    R_home = chain.M[:3, :3]

    def call(T: np.ndarray) -> np.ndarray:
        found = reference.get_ik((T[:3, :3] @ R_home.T).T.tolist(), T[:3, 3].tolist())
        return np.array([q for q, _ in found], dtype=float).reshape(-1, 6)

    return call


#: Decomposition classes that ik-geo builds from axes and offsets, by redik's class name.
IK_GEO_CLASSES = {
    "spherical_two_intersecting": "spherical_two_intersecting",
    "spherical_two_parallel": "spherical_two_parallel",
    "spherical": "spherical",
    "three_parallel_two_intersecting": "three_parallel_two_intersecting",
}


def compare_ik_geo(args: argparse.Namespace) -> None:
    """The second table of the module docstring (skipped, with a note, without ik-geo)."""
    try:
        import ik_geo
    except ImportError:
        print("\nik-geo is not installed (pip install ik-geo): comparison skipped")
        return
    load_average = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(
        f"\nsubproblem decomposition (raw array) vs ik-geo, {args.n} poses interleaved, "
        f"median µs per call ({args.clock} clock) over {args.repeats} repeats; "
        f"load average {load_average}"
    )
    print(
        f"{'robot':<10}{'class':>33}{'redik':>8}{'ik-geo':>8}{'ik-geo/redik':>14}"
        f"{'labelled':>10}{'labelled/ik-geo':>17}"
        f"{'solutions':>11}{'ik-geo sols':>12}{'ik-geo FK err':>15}"
    )
    for name in args.robots:
        robot = load(name)
        if robot.dof != 6 or not robot.revolute.all():
            continue
        row = measure_ik_geo(robot, args.n, args.repeats, args.seed, ik_geo, CLOCKS[args.clock])
        if row is None:
            print(f"{name:<10}  (no ik-geo class for this geometry)")
            continue
        print(
            f"{name:<10}{row['kind']:>33}{row['redik_us']:>8.2f}{row['ik_geo_us']:>8.2f}"
            f"{row['ik_geo_us'] / row['redik_us']:>13.2f}×{row['labelled_us']:>10.2f}"
            f"{row['labelled_us'] / row['ik_geo_us']:>16.2f}×{row['solutions']:>11.2f}"
            f"{row['ik_geo_solutions']:>12.2f}{row['ik_geo_error']:>15.1e}"
        )


def measure_ik_geo(
    robot: Robot,
    n: int,
    repeats: int,
    seed: int,
    ik_geo: Any,
    clock: Callable[[], float] = time.perf_counter,
) -> dict | None:
    """Time :meth:`DecomposedSolver.raw` and ik-geo's ``get_ik`` on the same poses
    (module docstring); None when ik-geo has no class for the arm (a reversed chain)."""
    solver = solver_for(robot, "decomposed")
    if solver.reversed or solver.kind not in IK_GEO_CLASSES:
        return None
    G = solver.geometry
    axes, points, home = G[0:6], G[6:12], G[12]
    offsets = np.vstack([points[0], np.diff(points, axis=0), home - points[5]])
    factory = getattr(ik_geo.Robot, IK_GEO_CLASSES[solver.kind])
    reference = factory(axes.tolist(), offsets.tolist())
    R_home = G[13:16]
    rng = np.random.default_rng(seed)
    targets = [robot.fk(q) for q in robot.random_q(rng, size=n)]
    # ik-geo's chain ends with the identity rotation at q = 0: its target is R R_Mᵀ, passed
    # as a list of columns (its forward_kinematics returns the transpose of redik's).
    inputs = [((T[:3, :3] @ R_home.T).T.tolist(), T[:3, 3].tolist()) for T in targets]
    ours, theirs, labelled = [], [], []
    for _ in range(repeats):
        for index, (T, (R, p)) in enumerate(zip(targets, inputs, strict=True)):
            start = clock()
            solver(T, limits=None)
            labelled.append(clock() - start)
            # Whichever runs first on a pose pays for bringing it into cache: alternate.
            if index % 2:
                start = clock()
                reference.get_ik(R, p)
                middle = clock()
                solver.raw(T, limits=None)
                end = clock()
                theirs.append(middle - start)
                ours.append(end - middle)
            else:
                start = clock()
                solver.raw(T, limits=None)
                middle = clock()
                reference.get_ik(R, p)
                end = clock()
                ours.append(middle - start)
                theirs.append(end - middle)
    counts, reference_counts, worst = [], [], 0.0
    for T, (R, p) in zip(targets, inputs, strict=True):
        counts.append(len(solver.raw(T, limits=None)))
        exact = [q for q, least_squares in reference.get_ik(R, p) if not least_squares]
        reference_counts.append(len(exact))
        for q in exact:
            worst = max(worst, float(np.abs(robot.fk(np.asarray(q)) - T).max()))
    return {
        "kind": solver.kind,
        "redik_us": 1e6 * statistics.median(ours),
        "ik_geo_us": 1e6 * statistics.median(theirs),
        "labelled_us": 1e6 * statistics.median(labelled),
        "solutions": float(np.mean(counts)),
        "ik_geo_solutions": float(np.mean(reference_counts)),
        "ik_geo_error": worst,
    }


def measure(
    robot: Robot,
    n: int,
    n_batch: int,
    repeats: int,
    seed: int,
    *,
    dls: bool = True,
    clock: Callable[[], float] = time.perf_counter,
) -> dict:
    """Time one scene (module docstring); µs per pose, ``nan`` for dls when skipped."""
    solver = solver_for(robot)
    rng = np.random.default_rng(seed)
    every = np.stack([robot.fk(q) for q in robot.random_q(rng, size=max(n, n_batch))])
    targets = every[:n]
    batch = _batch(solver)
    single_us = _median_per_call(lambda T: solver(T), targets, repeats, clock)
    batch_us = _median_per_batch(lambda: batch(every), len(every), repeats, clock)
    solutions = float(batch(every).valid.sum() / len(every))
    dls_us, dls_success = float("nan"), float("nan")
    if dls:
        home = np.asarray(robot.home, dtype=float)
        results = []

        def solve(T: np.ndarray) -> None:
            results.append(solve_pose(robot, T, home, method="dls", seed=0).success)

        dls_us = _median_per_call(solve, targets, repeats, clock)
        dls_success = float(np.mean(results))
    return {
        "single_us": single_us,
        "batch_us": batch_us,
        "dls_us": dls_us,
        "dls_success": dls_success,
        "solutions": solutions,
    }


def _batch(solver: AnalyticSolver) -> Callable[[np.ndarray], BatchSolutions]:
    """The vectorised solver of ``solver``'s family on world-frame targets."""
    base_inverse = np.linalg.inv(solver.base)
    limits = (solver.lower, solver.upper)
    family = BATCH[solver.family]
    return lambda targets: family(base_inverse @ targets, dict(solver.params), limits)


def _median_per_call(
    call: Callable[[np.ndarray], object],
    targets: np.ndarray,
    repeats: int,
    clock: Callable[[], float],
) -> float:
    samples = []
    for _ in range(repeats):
        for T in targets:
            start = clock()
            call(T)
            samples.append(clock() - start)
    return 1e6 * statistics.median(samples)


def _median_per_batch(
    call: Callable[[], object], n: int, repeats: int, clock: Callable[[], float]
) -> float:
    samples = []
    for _ in range(repeats):
        start = clock()
        call()
        samples.append(clock() - start)
    return 1e6 * statistics.median(samples) / n
