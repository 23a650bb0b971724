"""QP core: per-step time of every back-end beside mink.solve_ik, and convergence on FK targets.

Part 0 is the control step beside the anchors (:mod:`redik.apps.bench._qp_anchors`): redik's
weighted and strict steps, PlaCo's (when ``placo`` is importable) and ``mink.solve_ik`` on one
panda URDF, and redik's and mink's G1 step with 50 collision pairs (``--g1-pairs``: 0 for none,
or all 162), interleaved; it prints the medians and the ratios redik/PlaCo, strict/weighted and
mink/redik.

Part 1 times one differential-IK step of the panda stack (FrameTask + JointLimitAvoidanceTask
+ PostureTask at equal priority, joint position box) for each back-end, and mink's
``solve_ik`` on the equivalent stack (``FrameTask``, ``PostureTask``, and a ``PostureTask``
towards the mid-range with cost ``√2 w / (q_max − q_min)`` standing in for joint-limit
avoidance; ``ConfigurationLimit``) with the same solver. Both are timed interleaved, step
by step at the same ``q``, so machine load hits both alike; the table gives medians and
their ratio. A step includes forward kinematics in both; both use the same solver
tolerances (:data:`redik.qp.backends.QPSOLVERS_SETTINGS`).

Part 2 solves the FK targets (seeded random configurations, start at ``home``) to
``pos_tol``/``rot_tol`` with both loops — the same weighted stack (costs small enough not
to bias the converged pose) — and reports success, median iterations, median time to
converge and the worst joint-limit overshoot of any iterate. redik's strict-priority
stack (joint-space tasks at priority 1) is reported beside them.

Part 1b times the same three tasks as one weighted level and as two strict levels (pose,
then posture and joint-limit avoidance), interleaved at the same ``q``: the price of strict
priorities, as a ratio.

Part 4 is the whole-body case: multi-frame pose targets (every frame's pose at a
configuration drawn inside the limits) on the third-party humanoids and bimanual robots
(G1, Talos, Baxter, PR2; example-robot-data, ``meshes=False``), solved from ``home`` by
:func:`redik.solve_problem` (a :class:`~redik.tasks.FrameTask` per frame at priority 0, a
posture at priority 1) and by mink's plain loop on the same targets (a ``mink.FrameTask``
per frame, ``mink.ConfigurationLimit``, daqp, ``lm_damping=1``, ``damping=1e-3`` as mink's
examples; ``integrate_inplace`` until every frame meets the tolerances or 500 iterations).
Each model is reduced to the joints redik moves (the others deleted, held at 0) so that both
solve on one ``MjModel``. Strict success (1e-6 m, 1e-5 rad, inside the limits) is checked by
forward kinematics; times are medians and 95th percentiles over all targets, failures
included, interleaved target by target.

Part 3 is the latency of ``solve_pose(method="qp")`` with its defaults (restarts included)
over ``--latency-targets`` random reachable targets per robot, from ``home`` and from
random seeds: success, p50/p95/p99/max of the CPU time of the calling thread (on a
shared machine the wall time also counts the time slices other processes take: a 10 ms
preemption in a 1 ms solve; its p99 is printed beside), the p99 iterations, and the CPU
p99 in units of the median single QP step measured in the same run. One warm-up call
precedes each robot's timings.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time
import warnings

import mink
import numpy as np

from redik import lie
from redik.apps import measured
from redik.apps.bench import _qp_anchors as qp_anchors
from redik.apps.bench import _whole_body as whole_body
from redik.core.exceptions import BackendError, InfeasibleProblem
from redik.kinematics.robot import Robot, load
from redik.limits import ConfigurationLimit
from redik.qp import Problem
from redik.qp.backends import QPSOLVERS_SETTINGS, available_backends
from redik.solvers.task_stack import SolveOptions, solve_problem
from redik.tasks import FrameTask, JointLimitAvoidanceTask, PostureTask

MINK_SOLVER = {"daqp": "daqp", "proxsuite": "proxqp", "qpsolvers:daqp": "daqp", "cvxpy": None}
"""The mink (qpsolvers) solver compared with each redik back-end."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The benchmark's command-line options."""
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--backends", nargs="+", default=None, help="default: all installed")
    parser.add_argument("--steps", type=int, default=400, help="timed steps per back-end")
    parser.add_argument("--targets", type=int, default=500, help="FK targets (part 2, convergence)")
    parser.add_argument("--converge-backends", nargs="*", default=["daqp", "proxsuite", "quadprog"])
    parser.add_argument("--max-iterations", type=int, default=200)
    parser.add_argument("--pos-tol", type=float, default=1e-6)
    parser.add_argument("--rot-tol", type=float, default=1e-5)
    parser.add_argument(
        "--cost", type=float, default=1e-2, help="posture/limit cost (part 1, steps)"
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--latency-robots", nargs="*", default=["panda", "iiwa14", "ur5e"])
    parser.add_argument("--latency-targets", type=int, default=200)
    parser.add_argument("--multiframe-robots", nargs="*", default=list(whole_body.WHOLE_BODIES))
    parser.add_argument("--multiframe-targets", type=int, default=20)
    parser.add_argument(
        "--anchor-steps", type=int, default=3000, help="panda steps (part 0, anchors)"
    )
    parser.add_argument("--g1-steps", type=int, default=1000, help="G1 steps (part 0, anchors)")
    parser.add_argument(
        "--g1-pairs",
        type=int,
        default=qp_anchors.G1_PAIRS,
        help="G1 collision pairs (part 0, anchors; 0: none, more than there are: all)",
    )
    parser.add_argument(
        "--parts", nargs="+", default=list(PARTS), choices=list(PARTS), help="default: all"
    )


class _MinkStack:
    """mink's equivalent of the redik stack, on a configuration of the full model."""

    def __init__(self, robot, cost: float, solver: str):
        model = robot.model
        self.robot = robot
        self.solver = solver
        # The tolerances redik's back-end of the same name uses, for a like-for-like QP.
        self.settings = QPSOLVERS_SETTINGS.get(solver, {})
        self.configuration = mink.Configuration(model, robot.full_qpos(robot.home))
        self.frame = mink.FrameTask(robot.ee.name, robot.ee.kind, 1.0, 1.0)
        posture_cost = np.zeros(model.nv)
        posture_cost[robot.dof_indices] = cost
        self.posture = mink.PostureTask(model, cost=posture_cost)
        self.posture.set_target(robot.full_qpos(robot.home))
        limits = JointLimitAvoidanceTask(cost).bind(robot)
        limit_cost = np.zeros(model.nv)
        limit_cost[robot.dof_indices] = cost * math.sqrt(2.0) * limits.scale
        self.limit_avoidance = mink.PostureTask(model, cost=limit_cost)
        self.limit_avoidance.set_target(robot.full_qpos(limits.middle))
        self.tasks = [self.frame, self.posture, self.limit_avoidance]
        self.limits = [mink.ConfigurationLimit(model)]

    def set_target(self, T: np.ndarray) -> None:
        self.frame.set_target(mink.SE3.from_matrix(T))

    def step(self, qpos: np.ndarray) -> np.ndarray:
        self.configuration.update(qpos)
        return self.solve()

    def solve(self) -> np.ndarray:
        return mink.solve_ik(
            self.configuration,
            self.tasks,
            1.0,
            self.solver,
            damping=1e-6,
            limits=self.limits,
            **self.settings,
        )


def _redik_problem(robot, cost: float, backend: str, strict: bool) -> Problem:
    priority = 1 if strict else 0
    tasks = [
        FrameTask(robot.ee.name, target=robot.fk(robot.home)),
        JointLimitAvoidanceTask(cost, priority=priority),
        PostureTask(cost=cost, priority=priority),
    ]
    return Problem(robot, tasks, [ConfigurationLimit()], backend=backend, damping=1e-6)


def _time_steps(robot, backend: str, solver: str | None, args, targets) -> tuple:
    problem = _redik_problem(robot, args.cost, backend, strict=False)
    reference = _MinkStack(robot, args.cost, solver) if solver else None
    redik_times, mink_times = [], []
    steps_per_target = 8
    for i in range(math.ceil(args.steps / steps_per_target)):
        T = targets[i % len(targets)]
        problem.tasks[0].set_target(T)
        if reference:
            reference.set_target(T)
        q = robot.home.copy()
        for _ in range(steps_per_target):
            if reference:
                qpos = robot.full_qpos(q)
                start = time.perf_counter()
                reference.step(qpos)
                mink_times.append(time.perf_counter() - start)
            start = time.perf_counter()
            dq = problem.step(q)
            redik_times.append(time.perf_counter() - start)
            q = q + dq
    redik_us = statistics.median(redik_times) * 1e6
    mink_us = statistics.median(mink_times) * 1e6 if mink_times else float("nan")
    return redik_us, mink_us


def _time_priorities(robot, backend: str, args, targets) -> tuple[float, float]:
    """Median step time of one weighted level and of two strict levels.

    Median step time of the same three tasks as one weighted level and as two strict levels (pose,
    then posture + joint-limit avoidance), interleaved at the same ``q``.
    """
    one = _redik_problem(robot, args.cost, backend, strict=False)
    two = _redik_problem(robot, args.cost, backend, strict=True)
    times: tuple[list, list] = ([], [])
    steps_per_target = 8
    for i in range(math.ceil(args.steps / steps_per_target)):
        T = targets[i % len(targets)]
        one.tasks[0].set_target(T)
        two.tasks[0].set_target(T)
        q = robot.home.copy()
        for _ in range(steps_per_target):
            for problem, record in zip((one, two), times, strict=True):
                start = time.perf_counter()
                dq = problem.step(q)
                record.append(time.perf_counter() - start)
            q = q + dq
    return statistics.median(times[0]) * 1e6, statistics.median(times[1]) * 1e6


def _converge_redik(robot, backend, args, targets, strict: bool) -> dict:
    cost = 1.0 if strict else 1e-4
    problem = _redik_problem(robot, cost, backend, strict)
    results = []
    overshoot = 0.0
    start_all = time.perf_counter()
    for T in targets:
        problem.tasks[0].set_target(T)
        start = time.perf_counter()
        options = SolveOptions(args.pos_tol, args.rot_tol, args.max_iterations)
        result = solve_problem(problem, robot.home, options)
        elapsed = time.perf_counter() - start
        results.append((result.success, result.iterations, elapsed))
        over = np.maximum(robot.lower - result.history, result.history - robot.upper)
        overshoot = max(overshoot, float(np.max(over)))
    return _summary(results, overshoot, time.perf_counter() - start_all)


def _converge_mink(robot, solver, args, targets) -> dict:
    stack = _MinkStack(robot, 1e-4, solver)
    configuration = stack.configuration
    site = robot.ee
    results = []
    overshoot = 0.0
    start_all = time.perf_counter()
    for T in targets:
        stack.set_target(T)
        configuration.update(robot.full_qpos(robot.home))
        success, iterations = False, 0
        start = time.perf_counter()
        while True:
            data = configuration.data
            if site.kind == "site":
                R, p = data.site_xmat[site.id].reshape(3, 3), data.site_xpos[site.id]
            else:
                R, p = data.xmat[site.id].reshape(3, 3), data.xpos[site.id]
            position_error = float(np.linalg.norm(T[:3, 3] - p))
            if position_error <= args.pos_tol and lie.rotation_angle(R, T[:3, :3]) <= args.rot_tol:
                success = True
                break
            if iterations >= args.max_iterations:
                break
            try:
                velocity = stack.solve()
            except mink.exceptions.NoSolutionFound:
                break
            configuration.integrate_inplace(velocity, 1.0)
            iterations += 1
            q = configuration.data.qpos[robot.qpos_indices]
            overshoot = max(overshoot, float(np.max(np.maximum(robot.lower - q, q - robot.upper))))
        results.append((success, iterations, time.perf_counter() - start))
    return _summary(results, overshoot, time.perf_counter() - start_all)


def _summary(results, overshoot: float, total: float) -> dict:
    successes = [r for r in results if r[0]]
    return {
        "success": len(successes) / len(results),
        "iterations": statistics.median(r[1] for r in successes) if successes else float("nan"),
        "time_ms": statistics.median(r[2] for r in successes) * 1e3 if successes else float("nan"),
        "overshoot": max(overshoot, 0.0),
        "total_s": total,
    }


def _latency(robot, args) -> list[dict]:
    """``solve_pose(method="qp")`` wall times over random reachable targets, per seed mode."""
    from redik.solvers.pose import solve_pose

    rng = np.random.default_rng(args.seed)
    targets = [robot.fk(q) for q in robot.random_q(rng, size=args.latency_targets)]
    seeds = robot.random_q(rng, size=args.latency_targets)
    solve_pose(robot, targets[0], method="qp")  # warm-up: imports, first allocations
    step_problem = Problem(robot, [FrameTask(robot.ee.name, target=targets[0])], backend="daqp")
    rows = []
    for mode in ("home", "random"):
        times, walls, successes, iterations, step_times = [], [], 0, [], []
        for i, T in enumerate(targets):
            q0 = robot.home if mode == "home" else seeds[i]
            start, start_wall = time.thread_time(), time.perf_counter()
            result = solve_pose(robot, T, q0, method="qp", seed=i)
            times.append(time.thread_time() - start)
            walls.append(time.perf_counter() - start_wall)
            successes += result.success
            iterations.append(result.iterations)
            # A reference measured alongside: one QP step of the same robot.
            start = time.thread_time()
            step_problem.step(q0)
            step_times.append(time.thread_time() - start)
        ms = np.array(times) * 1e3
        step_ms = statistics.median(step_times) * 1e3
        rows.append(
            {
                "mode": mode,
                "success": successes / len(targets),
                "p50": float(np.percentile(ms, 50)),
                "p95": float(np.percentile(ms, 95)),
                "p99": float(np.percentile(ms, 99)),
                "max": float(ms.max()),
                "wall_p99": float(np.percentile(walls, 99)) * 1e3,
                "iterations_p99": float(np.percentile(iterations, 99)),
                "p99_steps": float(np.percentile(ms, 99)) / step_ms,
            }
        )
    return rows


def _load() -> str:
    return " ".join(f"{value:.2f}" for value in os.getloadavg())


# Part 4: multi-frame targets on whole-body models (models and stacks: ._whole_body)

MINK_ITERATIONS = 500
"""The budget of mink's plain loop in part 4."""


def _redik_whole_body(robot: Robot, goal: dict, args) -> np.ndarray:
    options = SolveOptions(args.pos_tol, args.rot_tol)
    return solve_problem(whole_body.stack(robot, goal), robot.home, options).q


def _mink_kind(model, frame: str) -> str:
    import mujoco

    return "site" if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, frame) >= 0 else "body"


def _mink_whole_body(robot: Robot, goal: dict, args) -> np.ndarray:
    """The final ``q`` of mink's plain loop from home (module docstring)."""
    model = robot.model
    configuration = mink.Configuration(model, robot.full_qpos(robot.home))
    tasks = []
    for frame, T in goal.items():
        task = mink.FrameTask(frame, _mink_kind(model, frame), 1.0, 1.0, lm_damping=1.0)
        task.set_target(mink.SE3.from_matrix(T))
        tasks.append(task)
    limits = [mink.ConfigurationLimit(model)]
    for _ in range(MINK_ITERATIONS):
        q = robot.q_of(configuration.q)
        if whole_body.reaches(robot, q, goal, args.pos_tol, args.rot_tol):
            break
        try:
            velocity = mink.solve_ik(configuration, tasks, 1.0, "daqp", 1e-3, limits=limits)
        except mink.exceptions.NoSolutionFound:
            break  # the loop has no answer to a failed QP
        configuration.integrate_inplace(velocity, 1.0)
    return robot.q_of(configuration.q)


def _multiframe(key: str, args) -> dict:
    """Success and time of both loops on the same targets, interleaved target by target."""
    robot, frames = whole_body.whole_body(key, reduced=True)
    rng = np.random.default_rng(args.seed)
    goals = [whole_body.goal(robot, frames, rng) for _ in range(args.multiframe_targets)]
    runners = {"redik": _redik_whole_body, "mink": _mink_whole_body}
    for run in runners.values():
        run(robot, goals[0], args)  # warm-up: compilation, caches
    rows: dict[str, tuple[list[float], list[float]]] = {name: ([], []) for name in runners}
    for goal in goals:
        for name, run in runners.items():
            start = time.perf_counter()
            q = run(robot, goal, args)
            rows[name][1].append(time.perf_counter() - start)
            rows[name][0].append(whole_body.reaches(robot, q, goal, args.pos_tol, args.rot_tol))
    return {
        name: {
            "success": float(np.mean(ok)),
            "p50": float(np.median(seconds)) * 1e3,
            "p95": float(np.percentile(seconds, 95)) * 1e3,
        }
        for name, (ok, seconds) in rows.items()
    } | {"robot": robot, "frames": len(frames)}


PARTS = ("anchors", "steps", "priorities", "convergence", "latency", "multiframe")
"""The parts, in the order they run (module docstring: 0, 1, 1b, 2, 3, 4)."""


def run(args: argparse.Namespace) -> int:
    """Run the parts asked for (module docstring)."""
    with warnings.catch_warnings():
        # qpsolvers warns on every dense-to-sparse conversion mink's calls make.
        warnings.simplefilter("ignore")
        robot = load(args.robot)
        rng = np.random.default_rng(args.seed)
        targets = [robot.fk(q) for q in robot.random_q(rng, size=args.targets)]
        backends = args.backends or available_backends()
        parts = {
            "anchors": lambda: _print_anchors(args),
            "steps": lambda: _print_steps(robot, backends, args, targets),
            "priorities": lambda: _print_priorities(robot, backends, args, targets),
            "convergence": lambda: _print_convergence(robot, args, targets),
            "latency": lambda: _print_latency(args),
            "multiframe": lambda: _print_multiframe(args),
        }
        for name in PARTS:
            if name in args.parts:
                parts[name]()
    return 0


def _print_anchors(args) -> None:
    try:
        import cmeel  # noqa: F401 - example-robot-data's models come with it
    except ImportError:
        print("anchors: example-robot-data is not installed (redik[models])\n")
        return
    with_placo = qp_anchors.placo_available()
    print(
        f"control step beside the anchors: panda URDF tracking a path, {args.anchor_steps} "
        f"steps, medians (µs), interleaved; load average {_load()}"
    )
    medians, agreement = qp_anchors.panda_steps(args.anchor_steps, with_placo)
    for name, us in medians.items():
        print(f"  {name:<16}{us:>9.1f}")
    weighted, strict = medians["redik weighted"], medians["redik strict"]
    print(f"  redik strict / weighted: {strict / weighted:.2f}")
    print(f"  mink / redik weighted: {medians['mink weighted'] / weighted:.2f}")
    if with_placo:
        print(f"  redik weighted / PlaCo soft hand: {weighted / medians['placo soft']:.2f}")
        print(f"  redik strict / PlaCo hard hand: {strict / medians['placo hard']:.2f}")
    else:
        print("  PlaCo not installed (requirements-placo.txt, CONTRIBUTING.md)")
    for name, difference in agreement.items():
        print(f"  max |Δq({name}) − Δq(redik weighted)| = {difference:.1e}")
    placo_soft, placo_hard = medians.get("placo soft"), medians.get("placo hard")
    measured.record(
        "control step beside PlaCo and mink (panda URDF)",
        redik_weighted_us=weighted,
        redik_strict_us=strict,
        placo_soft_us=placo_soft,
        placo_hard_us=placo_hard,
        mink_us=medians["mink weighted"],
        strict_over_weighted=strict / weighted,
        weighted_over_placo=weighted / placo_soft if placo_soft else None,
        mink_over_redik=medians["mink weighted"] / weighted,
    )
    medians, difference, pairs = qp_anchors.g1_steps(args.g1_steps, args.g1_pairs)
    print(
        f"\nG1 (4 frame tasks, posture, joint box, {pairs} collision pairs), "
        f"{args.g1_steps} steps, medians (µs), interleaved; load average {_load()}"
    )
    for name, us in medians.items():
        print(f"  {name:<16}{us:>9.1f}")
    ratio = medians["mink weighted"] / medians["redik weighted"]
    print(f"  mink / redik weighted: {ratio:.2f}")
    print(f"  max |Δq(mink) − Δq(redik)| = {difference:.1e}")
    if pairs:  # the limits differ on purpose there (redik.limits.collision_avoidance_limit)
        print("  (where a pair is inside the minimum distance, redik pushes it out, mink holds it)")
    print()
    measured.record(
        f"G1 step beside mink ({pairs} collision pairs)",
        redik_us=medians["redik weighted"],
        mink_us=medians["mink weighted"],
        mink_over_redik=ratio,
    )


def _print_steps(robot, backends, args, targets) -> None:
    print(
        f"{robot!r}: per-step time, weighted stack (cost {args.cost}), medians, "
        f"load average {_load()}"
    )
    print(f"{'redik back-end':<16}{'mink solver':<13}{'redik µs':>10}{'mink µs':>10}{'ratio':>8}")
    for backend in backends:
        solver = MINK_SOLVER.get(backend, backend)
        try:
            redik_us, mink_us = _time_steps(robot, backend, solver, args, targets)
        except (BackendError, InfeasibleProblem, mink.exceptions.NoSolutionFound) as error:
            print(f"{backend:<16}failed: {error}")
            continue
        if solver:
            ratio = f"{mink_us / redik_us:>7.2f}x"
            print(f"{backend:<16}{solver:<13}{redik_us:>10.1f}{mink_us:>10.1f}{ratio}")
            measured.record(
                "QP step beside mink.solve_ik",
                redik_back_end=backend,
                mink_solver=solver,
                redik_us=redik_us,
                mink_us=mink_us,
                mink_over_redik=mink_us / redik_us,
            )
        else:
            print(f"{backend:<16}{'-':<13}{redik_us:>10.1f}{'-':>10}{'-':>8}")


def _print_priorities(robot, backends, args, targets) -> None:
    print(
        f"\nstrict priorities: one weighted level vs pose > (posture, limits), medians, "
        f"load average {_load()}"
    )
    print(f"{'redik back-end':<16}{'1 level µs':>12}{'2 levels µs':>13}{'ratio':>8}")
    for backend in backends:
        try:
            one_us, two_us = _time_priorities(robot, backend, args, targets)
        except (BackendError, InfeasibleProblem) as error:
            print(f"{backend:<16}failed: {error}")
            continue
        print(f"{backend:<16}{one_us:>12.1f}{two_us:>13.1f}{two_us / one_us:>7.2f}x")
        measured.record(
            "strict priorities: two levels vs one",
            redik_back_end=backend,
            one_level_us=one_us,
            two_levels_us=two_us,
            ratio=two_us / one_us,
        )


def _print_convergence(robot, args, targets) -> None:
    print(
        f"\n{len(targets)} FK targets from home, pos_tol {args.pos_tol:g} m, rot_tol "
        f"{args.rot_tol:g} rad, max_iterations {args.max_iterations} (redik: per attempt, "
        f"restarts included)"
    )
    print(f"{'loop':<34}{'success':>9}{'iters':>7}{'ms/solve':>10}{'overshoot':>11}")
    for backend in args.converge_backends:
        solver = MINK_SOLVER.get(backend, backend)
        rows = [
            (
                f"redik {backend} (weighted 1e-4)",
                _converge_redik(robot, backend, args, targets, False),
            ),
            (f"redik {backend} (strict)", _converge_redik(robot, backend, args, targets, True)),
        ]
        if solver:
            rows.append(
                (f"mink {solver} (weighted 1e-4)", _converge_mink(robot, solver, args, targets))
            )
        for name, s in rows:
            print(
                f"{name:<34}{s['success']:>8.1%}{s['iterations']:>7}{s['time_ms']:>10.2f}"
                f"{s['overshoot']:>11.1e}"
            )
            measured.record(
                "solve_problem on FK targets beside mink's loop",
                loop=name,
                success_pct=100 * s["success"],
                iterations=s["iterations"],
                per_solve_ms=s["time_ms"],
                overshoot=s["overshoot"],
            )


def _print_latency(args) -> None:
    if not args.latency_robots:
        return
    print(
        f"\nsolve_pose(method='qp') latency, {args.latency_targets} random reachable "
        f"targets per robot, defaults (restarts included), CPU time of the thread, "
        f"load average {_load()}"
    )
    print(
        f"{'robot':<9}{'seed':<8}{'success':>8}{'p50 ms':>8}{'p95 ms':>8}{'p99 ms':>8}"
        f"{'max ms':>8}{'p99 it':>8}{'p99/step':>10}{'wall p99':>10}"
    )
    for name in args.latency_robots:
        for row in _latency(load(name), args):
            print(
                f"{name:<9}{row['mode']:<8}{row['success']:>7.1%}{row['p50']:>8.2f}"
                f"{row['p95']:>8.2f}{row['p99']:>8.2f}{row['max']:>8.2f}"
                f"{row['iterations_p99']:>8.0f}{row['p99_steps']:>9.0f}x"
                f"{row['wall_p99']:>10.2f}"
            )
            measured.record(
                "solve_pose(method='qp') latency",
                robot=name,
                seeds=row["mode"],
                success_pct=100 * row["success"],
                p50_ms=row["p50"],
                p95_ms=row["p95"],
                p99_ms=row["p99"],
                max_ms=row["max"],
                p99_iterations=row["iterations_p99"],
                p99_in_steps=row["p99_steps"],
                wall_p99_ms=row["wall_p99"],
            )


def _print_multiframe(args) -> None:
    if not args.multiframe_robots:
        return
    try:
        import cmeel  # noqa: F401 - example-robot-data's models come with it
    except ImportError:
        print("\nmulti-frame targets: example-robot-data is not installed (redik[models])")
        return
    print(
        f"\nmulti-frame targets from home, {args.multiframe_targets} per robot (strict: "
        f"{args.pos_tol:g} m, {args.rot_tol:g} rad, inside the limits); redik.solve_problem "
        f"vs mink's loop (lm_damping 1, damping 1e-3, {MINK_ITERATIONS} iterations); time "
        f"over all targets; load average {_load()}"
    )
    print(
        f"{'robot':<8}{'frames':>7}{'nq':>5}{'redik':>8}{'p50 ms':>9}{'p95 ms':>9}"
        f"{'mink':>8}{'p50 ms':>9}{'p95 ms':>9}"
    )
    for key in args.multiframe_robots:
        row = _multiframe(key, args)
        redik_row, mink_row = row["redik"], row["mink"]
        print(
            f"{key:<8}{row['frames']:>7}{row['robot'].nq:>5}{redik_row['success']:>7.0%}"
            f"{redik_row['p50']:>9.1f}{redik_row['p95']:>9.1f}{mink_row['success']:>7.0%}"
            f"{mink_row['p50']:>9.1f}{mink_row['p95']:>9.1f}"
        )
        measured.record(
            "multi-frame targets, solve_problem beside mink's loop",
            robot=key,
            frames=row["frames"],
            nq=row["robot"].nq,
            redik_success_pct=100 * redik_row["success"],
            redik_p50_ms=redik_row["p50"],
            redik_p95_ms=redik_row["p95"],
            mink_success_pct=100 * mink_row["success"],
            mink_p50_ms=mink_row["p50"],
            mink_p95_ms=mink_row["p95"],
        )
