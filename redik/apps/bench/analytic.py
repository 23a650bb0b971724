"""Closed-form IK against ik-geo: every IK-Geo class, the labelled PUMA 560 and UR5e, batches.

Four tables, one run:

1. *scenes* — ``solver_for(robot)`` one pose per call (robot limits, labels), the same solver's
   ``batch`` on a stack, and :func:`redik.solve_pose` (``dls`` from home) for reference, on the
   bundled PUMA 560, UR5e and planar 2R; median µs per pose.
2. *labelled vs ik-geo* — on the PUMA 560 and UR5e: the labelled call ``solver(T)`` (robot
   limits), the raw array ``solver.raw(T, limits=None)`` and ik-geo's ``get_ik`` (Elias &
   Wen's Rust IK-Geo, ``ik_geo.Robot`` of the same class built from the same screws), called
   in rotating order on each pose; medians and the ratios redik/ik-geo.
3. *per IK-Geo class* — ``--arms`` random arms of each class made as ik-geo's own setups make
   them (unit axes, offsets uniform in [−1, 1]³, zero offsets for intersections, equal axes
   for parallels), ``--poses`` targets each (FK of q uniform in ±π), redik's ``raw`` and
   ik-geo's ``get_ik`` interleaved on the same arms and targets: median µs, the ratio, and
   exactness — the largest FK error of redik's solutions (MuJoCo's ``robot.fk``), the share
   of targets whose generating configuration each returns (redik within 1e-8 rad, ik-geo
   within 1e-6), solutions per target (ik-geo's flagged least-squares answers left out), and,
   on ``--multistart`` targets per class, the roots of a 600-start numeric ``solve_all``
   that redik's set lacks and the roots redik found that the multistart missed.
4. *arms special at both ends* — the Kinova Jaco (:func:`jaco`), the Shadow hand's first
   finger (:func:`shadow_first_finger`) and random arms with two special axis pairs: method,
   µs, solutions, generating configuration found, FK error, multistart.

``--clock cpu`` times with the process CPU clock: on a shared, loaded machine it leaves out
the time spent waiting for a core. Without ik-geo installed the comparisons print a note.
"""

from __future__ import annotations

import argparse
import functools
import importlib
import itertools
import statistics
import time
from collections.abc import Callable
from types import ModuleType
from typing import Any

import numpy as np

from redik.apps import measured
from redik.apps.bench import load_average
from redik.kinematics.robot import Robot, load
from redik.lie import wrap_angle
from redik.models.dh import DHRow
from redik.solvers.analytic import solver_for
from redik.solvers.analytic.geometry import Chain, arm_screws, random_arm, screws_of
from redik.solvers.analytic.solver import SmallArmSolver
from redik.solvers.pose import solve_all, solve_pose

SCENES = ("puma560", "ur5e", "planar_2r")
CLOCKS: dict[str, Callable[[], float]] = {"wall": time.perf_counter, "cpu": time.process_time}

#: IK-Geo's classes, in its naming; the first five have closed forms in both libraries, the
#: last three are searched by ik-geo (1-D, 1-D, 2-D) and eliminated by redik.
CLASSES = (
    "spherical_two_intersecting",
    "spherical_two_parallel",
    "spherical",
    "three_parallel_two_intersecting",
    "three_parallel",
    "two_parallel",
    "two_intersecting",
    "gen_six_dof",
)

FULL_TURN = [(-np.pi, np.pi)] * 6


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The benchmark's options on ``redik bench analytic``'s parser."""
    parser.add_argument("--n", type=int, default=300, help="poses per scene (default 300)")
    parser.add_argument("--batch", type=int, default=2000, help="targets batched (default 2000)")
    parser.add_argument("--repeats", type=int, default=3, help="repeats (default 3)")
    parser.add_argument("--arms", type=int, default=10, help="random arms per class (default 10)")
    parser.add_argument("--poses", type=int, default=20, help="targets per arm (default 20)")
    parser.add_argument(
        "--multistart", type=int, default=2, help="targets per class checked by a 600-start search"
    )
    parser.add_argument("--seed", type=int, default=0, help="seed of the arms and targets")
    parser.add_argument("--clock", choices=sorted(CLOCKS), default="wall", help="wall or cpu")
    parser.add_argument("--no-dls", action="store_true", help="skip the iterative reference")
    parser.add_argument(
        "--tables", nargs="+", type=int, default=[1, 2, 3, 4], help="the tables to print (1-4)"
    )


def run(args: argparse.Namespace) -> int:
    """Print the tables of the module docstring that ``--tables`` names; returns 0."""
    clock = CLOCKS[args.clock]
    print(f"redik bench analytic ({args.clock} clock); {load_average('load')}")
    ik_geo: ModuleType | None
    try:
        ik_geo = importlib.import_module("ik_geo")
    except ImportError:
        ik_geo = None
        print("ik-geo is not installed (pip install ik-geo): its columns are skipped")
    if 1 in args.tables:
        scenes_table(args, clock)
    if 2 in args.tables and ik_geo is not None:
        labelled_table(args, ik_geo, clock)
    if 3 in args.tables and ik_geo is not None:
        classes_table(args, ik_geo, clock)
    if 4 in args.tables:
        special_table(args, clock)
    return 0


# --------------------------------------------------------------------------------------
# Arms


def jaco() -> Robot:
    """The Kinova Jaco² 6-DOF curved-wrist arm (j2n6s300) from Kinova's classic DH table.

    Kinova, *Jaco² 6 DOF Advanced Specification Guide* (DH parameters, classic convention):
    D1 = 0.2755, D2 = 0.41, D3 = 0.2073, D4 = D5 = 0.0741, D6 = 0.16, e2 = 0.0098 m and the
    wrist angle aa = 30°, with d4b = D3 + sin(aa)/sin(2aa)·D4, d5b = sin(aa)/sin(2aa)·(D4 + D5),
    d6b = sin(aa)/sin(2aa)·D5 + D6; rows (α, a, d) = (π/2, 0, D1), (π, D2, 0), (π/2, 0, −e2),
    (2aa, 0, −d4b), (2aa, 0, −d5b), (π, 0, −d6b). Consecutive axes meet or are parallel
    (1∩2, 2∥3, 3∩4, 4∩5, 5∩6), but the wrist axes do not share a point: no closed form.
    """
    D1, D2, D3, D4, D5, D6, e2 = 0.2755, 0.41, 0.2073, 0.0741, 0.0741, 0.16, 0.0098
    aa = np.pi / 6
    k = np.sin(aa) / np.sin(2 * aa)
    rows = [
        DHRow(0.0, D1, np.pi / 2),
        DHRow(D2, 0.0, np.pi),
        DHRow(0.0, -e2, np.pi / 2),
        DHRow(0.0, -(D3 + k * D4), 2 * aa),
        DHRow(0.0, -k * (D4 + D5), 2 * aa),
        DHRow(0.0, -(k * D5 + D6), np.pi),
    ]
    return Robot.from_dh(rows, limits=FULL_TURN, name="jaco")


_SHADOW_FIRST_FINGER = """
<mujoco model="shadow_first_finger">
  <compiler angle="radian"/>
  <default><geom type="sphere" size="0.005" mass="0.01"/></default>
  <worldbody>
    <body name="forearm" quat="0 1 0 1"><geom/>
      <body name="wrist" pos="0.01 0 0.21301" quat="1 0 0 1">
        <joint name="WRJ2" axis="0 1 0" range="-3.14159 3.14159"/><geom/>
        <body name="palm" pos="0 0 0.034">
          <joint name="WRJ1" axis="1 0 0" range="-3.14159 3.14159"/><geom/>
          <body name="ffknuckle" pos="0.033 0 0.095">
            <joint name="FFJ4" axis="0 -1 0" range="-3.14159 3.14159"/><geom/>
            <body name="ffproximal">
              <joint name="FFJ3" axis="1 0 0" range="-3.14159 3.14159"/><geom/>
              <body name="ffmiddle" pos="0 0 0.045">
                <joint name="FFJ2" axis="1 0 0" range="-3.14159 3.14159"/><geom/>
                <body name="ffdistal" pos="0 0 0.025">
                  <joint name="FFJ1" axis="1 0 0" range="-3.14159 3.14159"/><geom/>
                  <site name="ee" pos="0 0 0.026"/>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def shadow_first_finger() -> Robot:
    """The Shadow hand's wrist and first finger as one 6R chain.

    The wrist and first finger of MuJoCo Menagerie's right Shadow hand as one 6R chain
    (WRJ2, WRJ1, FFJ4, FFJ3, FFJ2, FFJ1; body poses and axes from ``shadow_hand/
    right_hand.xml``, ranges opened to a full turn): axes 3∩4 and 4∥5∥6.
    """
    return Robot.from_xml_string(_SHADOW_FIRST_FINGER, name="shadow_first_finger")


def two_special_arms(seed: int = 12) -> list[tuple[str, Robot]]:
    """Random DH arms with two special consecutive axis pairs.

    Random DH arms with two special consecutive pairs (``a_k = 0``: axes k+1, k+2 meet;
    ``α_k = 0``: parallel), one per combination of two of the first five links and of the
    kind of each: 40 arms, named like ``"1∩2 & 5∥6"``.
    """
    rng = np.random.default_rng(seed)
    arms = []
    for j, k in itertools.combinations(range(5), 2):
        for kinds in itertools.product(("a", "alpha"), repeat=2):
            lengths, offsets = rng.uniform(0.1, 0.5, 6), rng.uniform(0.1, 0.5, 6)
            twists = rng.choice([-1.0, 1.0], 6) * rng.uniform(0.3, 1.3, 6)
            rows = [DHRow(*row) for row in zip(lengths, offsets, twists, strict=True)]
            names = []
            for joint, kind in zip((j, k), kinds, strict=True):
                row = rows[joint]
                if kind == "a":
                    rows[joint] = DHRow(0.0, row.d, row.alpha)
                else:
                    rows[joint] = DHRow(row.a, row.d, 0.0)
                names.append(f"{joint + 1}{'∩' if kind == 'a' else '∥'}{joint + 2}")
            name = " & ".join(names)
            arms.append((name, Robot.from_dh(rows, limits=FULL_TURN, name="two_special")))
    return arms


def robot_of(h: np.ndarray, p: np.ndarray, name: str = "ik_geo_arm") -> Robot:
    """The :class:`~redik.Robot` of an IK-Geo arm ``(h, p)`` (home rotation the identity)."""
    return Robot.from_screws(*arm_screws(h, p), limits=FULL_TURN, name=name)


def ik_geo_arm(robot: Robot, kind: str, ik_geo: Any) -> Callable[[np.ndarray], list]:
    """ik-geo's solver of a class, for the robot's screw chain.

    ik-geo's solver of class ``kind`` for the robot's screw chain: ``T -> [(q, least
    squares), …]``. IK-Geo writes the chain as offsets between points of consecutive axes and
    reads intersections from zero offsets, so a point where two consecutive axes meet is used
    for both; its chain ends with the identity rotation at q = 0 and takes the target's
    rotation as a list of columns.
    """
    chain = Chain.from_screws(*screws_of(robot))
    points = chain.a.copy()
    for i in range(5):
        meeting = chain.meeting_point(i, i + 1)
        if meeting is not None:
            points[i] = points[i + 1] = meeting
    offsets = np.vstack([points[0], np.diff(points, axis=0), chain.M[:3, 3] - points[5]])
    reference = getattr(ik_geo.Robot, kind)(chain.h.tolist(), offsets.tolist())
    R_home = chain.M[:3, :3]

    def call(T: np.ndarray) -> list:
        return reference.get_ik((T[:3, :3] @ R_home.T).T.tolist(), T[:3, 3].tolist())

    return call


def distance(a: np.ndarray, b: np.ndarray) -> float:
    """The largest joint difference, angles modulo 2π."""
    return float(np.abs(wrap_angle(np.asarray(a) - np.asarray(b))).max())


def multistart(robot: Robot, T: np.ndarray, seed: int) -> np.ndarray:
    """The distinct roots a 600-start numeric search finds (tight position tolerance)."""
    found = solve_all(robot, T, n_starts=600, seed=seed, pos_tol=1e-9, respect_limits=False)
    return np.array([r.q for r in found]).reshape(-1, 6)


def compare_roots(found: np.ndarray, numeric: np.ndarray, tol: float = 1e-5) -> tuple[int, int]:
    """How a root set and a multistart's differ.

    ``(missing, extra)``: multistart roots not in ``found``, and roots of ``found`` the
    multistart did not reach.
    """
    missing = sum(min((distance(x, s) for s in found), default=np.inf) > tol for x in numeric)
    extra = sum(min((distance(s, x) for x in numeric), default=np.inf) > tol for s in found)
    return int(missing), int(extra)


# --------------------------------------------------------------------------------------
# Timing


def interleaved(
    calls: dict[str, Callable[[np.ndarray], object]],
    targets: list[np.ndarray],
    repeats: int,
    clock: Callable[[], float],
) -> dict[str, float]:
    """Median µs of each call, interleaved on the same targets.

    Median µs of each call over every target and repeat, the calls in rotating order on
    each target (whichever runs first pays for bringing the target into cache).
    """
    names = list(calls)
    samples: dict[str, list[float]] = {name: [] for name in names}
    for repeat in range(repeats):
        for index, T in enumerate(targets):
            shift = (index + repeat) % len(names)
            for name in names[shift:] + names[:shift]:
                start = clock()
                calls[name](T)
                samples[name].append(clock() - start)
    return {name: 1e6 * statistics.median(values) for name, values in samples.items()}


def scenes_table(args: argparse.Namespace, clock: Callable[[], float]) -> None:
    """Table 1 of the module docstring."""
    print(f"\n1. scenes: {args.n} poses one by one, {args.batch} batched; median µs per pose")
    print(f"{'robot':<10}{'single':>9}{'batched':>9}{'dls':>10}{'dls/single':>12}{'solutions':>11}")
    for name in SCENES:
        robot = load(name)
        solver = solver_for(robot)
        rng = np.random.default_rng(args.seed)
        every = np.stack([robot.fk(q) for q in robot.random_q(rng, size=max(args.n, args.batch))])
        targets = list(every[: args.n])
        single = interleaved({"single": solver}, targets, args.repeats, clock)["single"]
        batch = getattr(solver, "batch", None)
        batched = solutions = float("nan")
        if batch is not None:
            batch(every[:2])
            samples = []
            for _ in range(args.repeats):
                start = clock()
                result = batch(every)
                samples.append(clock() - start)
            batched = 1e6 * statistics.median(samples) / len(every)
            solutions = float(result.valid.sum() / len(every))
        dls = float("nan")
        if not args.no_dls:
            home = np.asarray(robot.home, dtype=float)

            def numeric(T: np.ndarray, robot: Robot = robot, home: np.ndarray = home) -> None:
                solve_pose(robot, T, home, method="dls", seed=0)

            dls = interleaved({"dls": numeric}, targets[:100], 1, clock)["dls"]
        print(
            f"{name:<10}{single:>9.2f}{batched:>9.2f}{dls:>10.1f}{dls / single:>11.0f}×"
            f"{solutions:>11.2f}"
        )
        measured.record(
            "closed form on the bundled scenes",
            robot=name,
            single_us=single,
            batched_us=batched,
            dls_us=dls,
            dls_over_single=dls / single,
            solutions=solutions,
        )


def labelled_table(args: argparse.Namespace, ik_geo: Any, clock: Callable[[], float]) -> None:
    """Table 2 of the module docstring."""
    print(
        f"\n2. labelled and raw closed form vs ik-geo, {args.n} poses, rotating order, "
        f"{args.repeats} repeats; median µs"
    )
    print(
        f"{'robot':<10}{'class':>33}{'labelled':>10}{'raw':>8}{'ik-geo':>8}"
        f"{'labelled/ik-geo':>17}{'raw/ik-geo':>12}"
    )
    for name in ("puma560", "ur5e"):
        robot = load(name)
        solver = solver_for(robot)
        if isinstance(solver, SmallArmSolver):  # no raw form to time
            continue
        reference = ik_geo_arm(robot, solver.kind, ik_geo)
        rng = np.random.default_rng(args.seed)
        targets = [robot.fk(q) for q in robot.random_q(rng, size=args.n)]
        calls: dict[str, Callable[[np.ndarray], object]] = {
            "labelled": solver,
            "raw": functools.partial(solver.raw, limits=None),
            "ik-geo": reference,
        }
        for call in calls.values():
            call(targets[0])
        m = interleaved(calls, targets, args.repeats, clock)
        print(
            f"{name:<10}{solver.kind:>33}{m['labelled']:>10.2f}{m['raw']:>8.2f}"
            f"{m['ik-geo']:>8.2f}{m['labelled'] / m['ik-geo']:>16.2f}×"
            f"{m['raw'] / m['ik-geo']:>11.2f}×"
        )
        measured.record(
            "closed form, labelled call beside ik-geo",
            robot=name,
            kind=solver.kind,
            labelled_us=m["labelled"],
            raw_us=m["raw"],
            ik_geo_us=m["ik-geo"],
            labelled_over_ik_geo=m["labelled"] / m["ik-geo"],
            raw_over_ik_geo=m["raw"] / m["ik-geo"],
        )


def measure_class(
    kind: str, args: argparse.Namespace, ik_geo: Any, clock: Callable[[], float]
) -> dict[str, Any]:
    """Table 3's row of one IK-Geo class (module docstring)."""
    rng = np.random.default_rng([args.seed, CLASSES.index(kind)])
    ours, theirs = [], []
    found = found_ik_geo = total = checked = missing = extra = 0
    counts, counts_ik_geo, worst, methods = [], [], 0.0, set()
    for index in range(args.arms):
        robot = robot_of(*random_arm(kind, rng), name=f"{kind}_{index}")
        solver = solver_for(robot)
        methods.add(f"{solver.method}:{solver.kind}")
        reference = ik_geo_arm(robot, kind, ik_geo)
        qs = rng.uniform(-np.pi, np.pi, (args.poses, 6))
        targets = [robot.fk(q) for q in qs]
        raw = lambda T, solver=solver: solver.raw(T, limits=None)  # noqa: E731
        raw(targets[0])
        timed = interleaved({"redik": raw, "ik-geo": reference}, targets, args.repeats, clock)
        ours.append(timed["redik"])
        theirs.append(timed["ik-geo"])
        for q, T in zip(qs, targets, strict=True):
            solutions = raw(T)
            exact = [np.asarray(x) for x, least_squares in reference(T) if not least_squares]
            total += 1
            counts.append(len(solutions))
            counts_ik_geo.append(len(exact))
            worst = max([worst, *(float(np.abs(robot.fk(s) - T).max()) for s in solutions)])
            found += min((distance(s, q) for s in solutions), default=np.inf) < 1e-8
            found_ik_geo += min((distance(s, q) for s in exact), default=np.inf) < 1e-6
        for T in targets[: max(0, args.multistart - checked)]:
            lacking, more = compare_roots(raw(T), multistart(robot, T, seed=checked))
            missing, extra, checked = missing + lacking, extra + more, checked + 1
    return {
        "kind": kind,
        "method": ", ".join(sorted(methods)),
        "redik_us": statistics.median(ours),
        "ik_geo_us": statistics.median(theirs),
        "found": found / total,
        "found_ik_geo": found_ik_geo / total,
        "solutions": float(np.mean(counts)),
        "solutions_ik_geo": float(np.mean(counts_ik_geo)),
        "fk_error": worst,
        "checked": checked,
        "missing": missing,
        "extra": extra,
    }


def classes_table(args: argparse.Namespace, ik_geo: Any, clock: Callable[[], float]) -> None:
    """Table 3 of the module docstring."""
    print(
        f"\n3. per IK-Geo class: {args.arms} random arms × {args.poses} targets, redik raw and "
        f"ik-geo get_ik interleaved, median over arms of the median µs; generating q found "
        f"(redik 1e-8 rad, ik-geo 1e-6); {args.multistart} targets per class against a "
        "600-start multistart (roots it found that redik lacks / redik's roots it missed)"
    )
    print(
        f"{'class':<33}{'redik µs':>9}{'ik-geo µs':>10}{'ratio':>8}{'found':>7}{'ik-geo':>7}"
        f"{'sols':>6}{'ik-geo':>7}{'FK max':>9}{'multistart':>11}  redik method"
    )
    for kind in CLASSES:
        row = measure_class(kind, args, ik_geo, clock)
        ratio = row["redik_us"] / row["ik_geo_us"]
        multi = f"{row['missing']}/{row['extra']} of {row['checked']}" if row["checked"] else "-"
        print(
            f"{kind:<33}{row['redik_us']:>9.1f}{row['ik_geo_us']:>10.1f}{ratio:>7.2f}×"
            f"{row['found']:>7.0%}{row['found_ik_geo']:>7.0%}{row['solutions']:>6.2f}"
            f"{row['solutions_ik_geo']:>7.2f}{row['fk_error']:>9.1e}{multi:>11}  {row['method']}"
        )
        measured.record(
            "closed form per IK-Geo class beside ik-geo",
            kind=kind,
            redik_us=row["redik_us"],
            ik_geo_us=row["ik_geo_us"],
            ratio=ratio,
            found_pct=100 * row["found"],
            ik_geo_found_pct=100 * row["found_ik_geo"],
            solutions=row["solutions"],
            ik_geo_solutions=row["solutions_ik_geo"],
            fk_error=row["fk_error"],
            multistart=multi,
            method=row["method"],
        )


def special_table(args: argparse.Namespace, clock: Callable[[], float]) -> None:
    """Table 4 of the module docstring."""
    print(
        f"\n4. arms whose standard elimination is degenerate: {args.poses} targets each, "
        f"median µs, generating q found, {args.multistart} targets against the multistart"
    )
    print(
        f"{'arm':<22}{'method':>22}{'µs':>9}{'sols':>6}{'found':>7}{'FK max':>9}{'multistart':>11}"
    )
    arms = [("jaco (Kinova DH)", jaco()), ("shadow first finger", shadow_first_finger())]
    refused = {"1∥2 & 2∥3", "1∩2 & 5∩6", "1∩2 & 5∥6", "1∥2 & 5∩6", "1∥2 & 5∥6", "4∥5 & 5∥6"}
    arms += [(name, robot) for name, robot in two_special_arms() if name in refused]
    for name, robot in arms:
        solver = solver_for(robot)
        rng = np.random.default_rng(args.seed)
        qs = rng.uniform(-np.pi, np.pi, (args.poses, 6))
        targets = [robot.fk(q) for q in qs]
        raw = lambda T, solver=solver: solver.raw(T, limits=None)  # noqa: E731
        raw(targets[0])
        timed = interleaved({"redik": raw}, targets, args.repeats, clock)["redik"]
        sols = [raw(T) for T in targets]
        pairs = list(zip(sols, qs, targets, strict=True))
        found = np.mean([min((distance(s, q) for s in x), default=9) < 1e-8 for x, q, _ in pairs])
        worst = max(float(np.abs(robot.fk(s) - T).max()) for x, _, T in pairs for s in x)
        results = [
            compare_roots(sols[i], multistart(robot, targets[i], i)) for i in range(args.multistart)
        ]
        multi = f"{sum(r[0] for r in results)}/{sum(r[1] for r in results)} of {len(results)}"
        print(
            f"{name:<22}{solver.method + ':' + solver.kind:>22}{timed:>9.1f}"
            f"{np.mean([len(x) for x in sols]):>6.2f}{found:>7.0%}{worst:>9.1e}{multi:>11}"
        )
        measured.record(
            "closed form, arms special at both ends",
            arm=name,
            method=f"{solver.method}:{solver.kind}",
            median_us=timed,
            solutions=float(np.mean([len(x) for x in sols])),
            found_pct=100 * float(found),
            fk_error=worst,
            multistart=multi,
        )
