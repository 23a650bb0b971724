"""Pose IK on panda, iiwa14 and ur5e, like with like: redik, Robotics Toolbox, TRAC-IK, mink.

Protocol. For each robot, ``--n`` targets are the poses of configurations
drawn uniformly within the joint limits (generator seeded by ``--seed``); each target is
solved once from the middle of the joint ranges and once from a random configuration (drawn
by the same generator). Every library is set up **once** per robot and then called as its
own documentation recommends:

- redik: :func:`redik.solve_pose` (default restarts, ``seed`` = the target's index);
- Robotics Toolbox: ``ets.ik_LM(T, q0, ilimit=30, slimit=100, tol=5e-13, joint_limits=True)``
  — its C++ Levenberg–Marquardt with its default budget and the tolerance that makes its
  residual ``E = ½‖e‖²`` as strict as ours — on an ``ETS`` built once from the scene's DH
  table (:func:`rtb_ets`; building it per call costs more than the solve);
- TRAC-IK: ``pytracik.ik`` on a ``TRAC_IK`` solver made once from a URDF of the same table,
  as the ``TracIK`` wrapper of pytracik does (``Speed``, 5 ms timeout, ε = 1e-6);
- mink: a ``mink.solve_ik`` loop (``dt`` = 1, up to 500 steps, daqp) until both tolerances
  hold, once at mink's defaults (``ConfigurationLimit`` gain 0.95, damping 1e-12) and once
  at the setting that does best on these robots (gain 0.2, damping 1e-6).

Each solver first solves one untimed target (loading compiled code). The solvers are then
interleaved: target ``i`` is solved by every solver (the order rotating with ``i``) before
target ``i + 1``, so a change of machine load touches all alike. Each returned ``q`` is
scored by one function, :class:`Score` — MuJoCo's ``mj_kinematics`` on its own ``MjData``,
independent of every solver: ``‖p_d − p‖ ≤ 1e-6 m``, ``angle(Rᵀ R_d) ≤ 1e-5 rad`` and
``lower ≤ q ≤ upper``, never a solver's own flag. Times are wall clock per call (median,
p95, p99, max); the last column is the median over Robotics Toolbox's median in the same
run. The load average is printed at start and end.
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable

import mujoco
import numpy as np

from redik import lie
from redik.apps import measured
from redik.apps.bench import load_average
from redik.kinematics.robot import Robot
from redik.models.dh import Convention, DHRow
from redik.solvers.pose import METHODS, solve_pose

ROBOTS = ("panda", "iiwa14", "ur5e")
POS_TOL = 1e-6
ROT_TOL = 1e-5
RTB_TOL = 5e-13
"""Robotics Toolbox's tolerance on ``E = ½‖e‖²``: ``‖e‖ ≤ 1e-6``, as strict as ours."""
MINK_MAX_ITERATIONS = 500
MINK_SETTINGS = {"mink": (0.95, 1e-12), "mink tuned": (0.2, 1e-6)}
"""``(ConfigurationLimit gain, solve_ik damping)``: mink's defaults, and its best setting."""
SEED_MODES = ("middle", "random")
REFERENCE = "rtb ik_LM"
REFERENCES = ("rtb", "tracik", "mink")
"""The libraries ``--references`` chooses from."""

Solver = Callable[[np.ndarray, np.ndarray, int], np.ndarray | None]
"""``solver(T_target, q0, index) -> q`` (None when the solver returns nothing)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add this benchmark's options to its ``redik bench`` subparser."""
    parser.add_argument("--n", type=int, default=200, help="targets per robot (default 200)")
    parser.add_argument("--robots", nargs="+", default=list(ROBOTS), help="scenes to use")
    parser.add_argument(
        "--methods",
        nargs="+",
        default=["dls"],
        help=f"redik methods among {METHODS} (default: dls)",
    )
    parser.add_argument("--quick", action="store_true", help="50 targets per robot")
    parser.add_argument("--seed", type=int, default=0, help="seed of the targets and starts")
    parser.add_argument(
        "--references",
        nargs="*",
        default=list(REFERENCES),
        help=f"libraries to compare among {REFERENCES} (default: all; none: redik alone)",
    )
    parser.add_argument(
        "--no-references", action="store_true", help="skip Robotics Toolbox, TRAC-IK and mink"
    )


def run(args: argparse.Namespace) -> int:
    """Measure every solver on every robot and print the table; exit code 2 on bad names."""
    n = 50 if args.quick else args.n
    unknown = [m for m in args.methods if m not in METHODS]
    if unknown:
        print(f"unknown method(s) {unknown}; choose among {METHODS}")
        return 2
    references = [] if args.no_references else list(args.references)
    unknown = [r for r in references if r not in REFERENCES]
    if unknown:
        print(f"unknown reference(s) {unknown}; choose among {REFERENCES}")
        return 2
    print(
        f"redik bench pose: {n} targets per robot and seed mode; success = pos ≤ {POS_TOL:g} m, "
        f"rot ≤ {ROT_TOL:g} rad, inside the limits, scored by MuJoCo FK of the returned q"
    )
    print(load_average("load average at start"))
    rows = []
    for name in args.robots:
        robot = _load(name)
        solvers = {f"redik {m}": _redik_solver(robot, m) for m in args.methods}
        solvers.update(_reference_solvers(robot, references))
        available = {label: solver for label, solver in solvers.items() if solver is not None}
        rows += _measure(robot, available, n, args.seed)
    _print_table(rows)
    print(load_average("load average at end"))
    return 0


# --------------------------------------------------------------------------------------
# Measuring


def _load(name: str) -> Robot:
    from redik.kinematics.robot import load

    return load(name)


class Score:
    """The one verdict on every solver's ``q``: MuJoCo FK on an ``MjData`` of its own.

    ``score(q, T_target)`` is True when ``q`` is a finite ``n``-vector inside the limits whose
    end-effector pose is within :data:`POS_TOL` and :data:`ROT_TOL` of ``T_target``.
    """

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.data = mujoco.MjData(robot.model)
        self.data.qpos[:] = robot.full_qpos(robot.home)
        self.T = np.eye(4)

    def __call__(self, q: np.ndarray | None, T_target: np.ndarray) -> bool:
        """True when ``q`` reaches ``T_target`` strictly inside the limits."""
        robot = self.robot
        if q is None or np.shape(q) != (robot.dof,) or not np.all(np.isfinite(q)):
            return False
        self.data.qpos[robot.qpos_indices] = q
        mujoco.mj_kinematics(robot.model, self.data)
        frame = robot.frame(None)
        if frame.kind == "site":
            p, R = self.data.site_xpos[frame.id], self.data.site_xmat[frame.id]
        else:
            p, R = self.data.xpos[frame.id], self.data.xmat[frame.id]
        self.T[:3, :3] = R.reshape(3, 3)
        self.T[:3, 3] = p
        position_error, rotation_error = lie.pose_errors(self.T, T_target)
        return (
            position_error <= POS_TOL
            and rotation_error <= ROT_TOL
            and bool(np.all(q >= robot.lower) and np.all(q <= robot.upper))
        )


def _measure(
    robot: Robot, solvers: dict[str, Solver], n: int, seed: int
) -> list[tuple[str, str, str, float, np.ndarray]]:
    """Interleaved: target ``i`` in both seed modes by every solver, then ``i + 1``."""
    rng = np.random.default_rng(seed)
    q_targets = robot.random_q(rng, size=n)
    targets = [robot.fk(q) for q in q_targets]
    starts = {"middle": np.tile(robot.midrange, (n, 1)), "random": robot.random_q(rng, size=n)}
    score = Score(robot)
    labels = list(solvers)
    for solver in solvers.values():  # untimed: loads compiled code, fills first-call caches
        solver(robot.fk(robot.home), robot.midrange, 0)
    times = {(mode, label): np.empty(n) for mode in SEED_MODES for label in labels}
    successes = dict.fromkeys(times, 0)
    for i, T_target in enumerate(targets):
        order = labels[i % len(labels) :] + labels[: i % len(labels)]
        for mode in SEED_MODES:
            for label in order:
                q0 = starts[mode][i].copy()
                start = time.perf_counter()
                q = solvers[label](T_target, q0, i)
                times[mode, label][i] = time.perf_counter() - start
                successes[mode, label] += score(q, T_target)
    return [
        (robot.name, mode, label, 100.0 * successes[mode, label] / n, 1e3 * times[mode, label])
        for mode in SEED_MODES
        for label in labels
    ]


def _print_table(rows: list[tuple[str, str, str, float, np.ndarray]]) -> None:
    reference = {(r[0], r[1]): float(np.median(r[4])) for r in rows if r[2] == REFERENCE}
    print(
        f"\n{'robot':8s} {'seeds':7s} {'solver':14s} {'success %':>9s} {'median ms':>10s} "
        f"{'p95 ms':>8s} {'p99 ms':>8s} {'max ms':>8s} {'median / rtb':>13s}"
    )
    for robot, mode, label, success, milliseconds in rows:
        median = float(np.median(milliseconds))
        p95, p99 = np.percentile(milliseconds, (95, 99))
        rtb_median = reference.get((robot, mode))
        ratio = f"{median / rtb_median:13.2f}" if rtb_median else f"{'—':>13s}"
        print(
            f"{robot:8s} {mode:7s} {label:14s} {success:9.1f} {median:10.3f} {p95:8.3f} "
            f"{p99:8.3f} {milliseconds.max():8.3f} {ratio}"
        )
        measured.record(
            "pose IK, every library on the same targets",
            robot=robot,
            seeds=mode,
            solver=label,
            success_pct=success,
            median_ms=median,
            p95_ms=p95,
            p99_ms=p99,
            max_ms=milliseconds.max(),
            median_over_rtb=median / rtb_median if rtb_median else None,
        )


# --------------------------------------------------------------------------------------
# Solvers, each set up once per robot


def _redik_solver(robot: Robot, method: str) -> Solver | None:
    if method == "qp":
        try:
            from redik.solvers.pose.qp import solve_pose_qp  # noqa: F401
        except ImportError:
            print("note: method 'qp' skipped (redik.solvers.pose.qp is not available)")
            return None

    def solve(T_target: np.ndarray, q0: np.ndarray, index: int) -> np.ndarray:
        return solve_pose(
            robot, T_target, q0, method=method, pos_tol=POS_TOL, rot_tol=ROT_TOL, seed=index
        ).q

    return solve


def _reference_solvers(robot: Robot, references: list[str]) -> dict[str, Solver | None]:
    solvers: dict[str, Solver | None] = {}
    if "rtb" in references:
        solvers[REFERENCE] = _rtb_solver(robot)
    if "tracik" in references:
        solvers["TRAC-IK"] = _tracik_solver(robot)
    if "mink" in references:
        for label, (gain, damping) in MINK_SETTINGS.items():
            solvers[label] = _mink_solver(robot, gain, damping)
    return solvers


def _mink_solver(robot: Robot, limit_gain: float, damping: float) -> Solver | None:
    """A ``mink.solve_ik`` loop (daqp, configuration limits) until both tolerances hold."""
    try:
        import mink
    except ImportError:
        print("note: mink not installed; skipped")
        return None
    configuration = mink.Configuration(robot.model)
    frame = robot.frame(None)
    task = mink.FrameTask(frame.name, frame.kind, position_cost=1.0, orientation_cost=1.0)
    limits = [mink.ConfigurationLimit(robot.model, gain=limit_gain)]
    indices = robot.qpos_indices
    data = configuration.data
    if frame.kind == "site":
        position, rotation = data.site_xpos[frame.id], data.site_xmat[frame.id]
    else:
        position, rotation = data.xpos[frame.id], data.xmat[frame.id]

    def solve(T_target: np.ndarray, q0: np.ndarray, index: int) -> np.ndarray:
        configuration.update(robot.full_qpos(q0))
        task.set_target(mink.SE3.from_matrix(T_target))
        for _ in range(MINK_MAX_ITERATIONS):
            if (
                math.dist(T_target[:3, 3], position) <= POS_TOL
                and lie.rotation_angle(rotation.reshape(3, 3), T_target[:3, :3]) <= ROT_TOL
            ):
                break
            try:
                velocity = mink.solve_ik(
                    configuration, [task], 1.0, "daqp", damping=damping, limits=limits
                )
            except mink.NoSolutionFound:  # the QP failed: the q reached so far is scored
                break
            configuration.integrate_inplace(velocity, 1.0)
        return configuration.q[indices].copy()

    return solve


def _dh_table(robot: Robot) -> tuple[tuple[DHRow, ...], Convention, np.ndarray, np.ndarray]:
    """``(rows, convention, tool, base)`` of a scene built from a DH table.

    ``base`` places the table's frame 0 in the scene: ``robot.fk(q) = base · T_0n(q) · tool``.
    """
    from redik.models.builder import read_dh
    from redik.models.dh import forward, parse_convention

    rows, convention, tool = read_dh(robot.model)
    convention = parse_convention(convention)
    base = robot.fk(robot.home) @ lie.inverse(forward(rows, robot.home, convention, tool))
    return rows, convention, tool, base


def rtb_ets(robot: Robot):
    """Robotics Toolbox's model of a DH scene: an ``ETS`` built once from its table.

    Each row ``T_i(q) = pre · M(q) · post`` (:func:`redik.models.dh.split_row`, ``M`` = ``R_z`` or
    ``T_z``) becomes a joint between constant transforms; consecutive constants (and the base
    and tool) are merged, so the sequence is ``C_0 M_1 C_1 ⋯ M_n C_n`` with no joint
    offsets, which the C++ solvers of rtb require.

    Raises:
        ModelError: the scene carries no DH table.
    """
    import roboticstoolbox as rtb

    from redik.models.dh import split_row

    rows, convention, tool, base = _dh_table(robot)
    constant = base
    elements = []
    for row, lower, upper in zip(rows, robot.lower, robot.upper, strict=True):
        pre, post = split_row(row, convention)
        qlim = [lower, upper] if math.isfinite(lower) and math.isfinite(upper) else None
        joint = rtb.ET.tz(qlim=qlim) if row.is_prismatic else rtb.ET.Rz(qlim=qlim)
        elements += [rtb.ET.SE3(constant @ pre), joint]
        constant = post
    elements.append(rtb.ET.SE3(constant @ tool))
    # roboticstoolbox's package exports the class ETS under the name of its module ETS.
    return rtb.ETS(elements)  # type: ignore[operator]


def _rtb_solver(robot: Robot) -> Solver | None:
    """Robotics Toolbox's C++ ``ik_LM`` on :func:`rtb_ets`, built once."""
    try:
        import roboticstoolbox  # noqa: F401
    except ImportError:
        print("note: Robotics Toolbox (roboticstoolbox-python) not installed; ik_LM skipped")
        return None
    ets = rtb_ets(robot)

    def solve(T_target: np.ndarray, q0: np.ndarray, index: int) -> np.ndarray:
        solution = ets.ik_LM(T_target, q0=q0, ilimit=30, slimit=100, tol=RTB_TOL, joint_limits=True)
        return np.asarray(solution[0], dtype=float)

    return solve


def _tracik_solver(robot: Robot) -> Solver | None:
    """TRAC-IK (``pytracik``) on a URDF written from the scene's DH table, made once."""
    try:
        import pytracik
    except ImportError:
        print("note: TRAC-IK (pytracik) not installed; skipped")
        return None
    rows, convention, tool, base = _dh_table(robot)
    solver = pytracik.TRAC_IK(
        "base", "tool", _dh_to_urdf(rows, convention, tool, robot), 0.005, POS_TOL,
        pytracik.SolveType.Speed,
    )  # fmt: skip
    q_check = robot.random_q(np.random.default_rng(1))
    if not np.allclose(base @ pytracik.fk(solver, q_check), robot.fk(q_check), atol=1e-9):
        print(f"note: the TRAC-IK model of {robot.name} does not match the scene; skipped")
        return None
    base_inverse = lie.inverse(base)

    def solve(T_target: np.ndarray, q0: np.ndarray, index: int) -> np.ndarray | None:
        local = base_inverse @ T_target
        w, x, y, z = lie.quat_from_matrix(local[:3, :3])
        answer = pytracik.ik(solver, q0, *local[:3, 3], x, y, z, w)
        return np.asarray(answer[1:], dtype=float) if answer[0] >= 0 else None

    return solve


def _dh_to_urdf(rows, convention: Convention, tool: np.ndarray, robot: Robot) -> str:
    """A URDF with one joint per DH row: ``origin`` then a motion about the joint's z."""
    from redik.models.dh import split_row

    def origin(T: np.ndarray) -> str:
        xyz = " ".join(f"{v:.12g}" for v in T[:3, 3])
        rpy = " ".join(f"{v:.12g}" for v in lie.euler_angles(T[:3, :3], "zyx")[::-1])
        return f'<origin xyz="{xyz}" rpy="{rpy}"/>'

    # Each row as (fixed transform, motion about z, fixed transform), the motion Rz(q) or Tz(q).
    before_after = [split_row(row, convention) for row in rows]
    parts = ['<?xml version="1.0"?>', f'<robot name="{robot.name}">', '<link name="base"/>']
    for i, (before, after) in enumerate(before_after, start=1):
        kind = "prismatic" if rows[i - 1].is_prismatic else "revolute"
        lower, upper = robot.lower[i - 1], robot.upper[i - 1]
        lower = lower if math.isfinite(lower) else -1e3
        upper = upper if math.isfinite(upper) else 1e3
        parent = "base" if i == 1 else f"m{i - 1}"
        parts += [
            f'<link name="l{i}"/>',
            f'<joint name="j{i}" type="{kind}"><parent link="{parent}"/><child link="l{i}"/>'
            f'{origin(before)}<axis xyz="0 0 1"/>'
            f'<limit lower="{lower:.12g}" upper="{upper:.12g}" effort="1" velocity="1"/></joint>',
            f'<link name="m{i}"/>',
            f'<joint name="f{i}" type="fixed"><parent link="l{i}"/><child link="m{i}"/>'
            f"{origin(after)}</joint>",
        ]
    parts += [
        '<link name="tool"/>',
        f'<joint name="tool" type="fixed"><parent link="m{len(rows)}"/><child link="tool"/>'
        f"{origin(tool)}</joint>",
        "</robot>",
    ]
    return "\n".join(parts)
