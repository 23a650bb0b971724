"""Pose IK on panda, iiwa14 and ur5e: strict success and time per solve, beside mink.

Protocol (issue 3): for each robot, ``--n`` targets are the FK of configurations drawn
uniformly within the joint limits; each target is solved once from the middle of the joint
ranges and once from a random configuration. Success is checked here, by the FK of the
returned ``q`` — ``‖p_d − p‖ ≤ 1e-6 m``, ``angle(Rᵀ R_d) ≤ 1e-5 rad`` and inside the limits —
never by a solver's own flag. Every redik method runs with its default restarts; mink runs a
``solve_ik`` loop from the one start with the same tolerances. When installed (the optional
``bench`` extra), Robotics Toolbox's C++ ``ik_LM`` (tol 5e-13, 100 restarts, limits on) and
TRAC-IK (``pytracik``, both on the same DH tables as the scenes) run too. Times are wall
clock per solve (median, p95); ratios are medians against mink measured in the same run.
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable

import numpy as np

from .. import lie
from ..pose_ik import METHODS, solve_pose
from ..robot import Robot

ROBOTS = ("panda", "iiwa14", "ur5e")
POS_TOL = 1e-6
ROT_TOL = 1e-5
MINK_MAX_ITER = 500

Solver = Callable[[np.ndarray, np.ndarray, int], np.ndarray | None]
"""``solver(T_target, q0, index) -> q`` (None when the solver reports nothing)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--n", type=int, default=500, help="targets per robot (default 500)")
    parser.add_argument("--robots", nargs="+", default=list(ROBOTS), help="scenes to use")
    parser.add_argument(
        "--methods",
        nargs="+",
        default=["dls", "newton", "hybrid", "qp"],
        help=f"redik methods among {METHODS} (default: dls newton hybrid qp)",
    )
    parser.add_argument(
        "--quick", action="store_true", help="50 targets, dls only (with the references)"
    )
    parser.add_argument("--seed", type=int, default=0, help="seed of the targets")
    parser.add_argument(
        "--no-references", action="store_true", help="skip mink, Robotics Toolbox and TRAC-IK"
    )


def run(args: argparse.Namespace) -> int:
    n = 50 if args.quick else args.n
    methods = ["dls"] if args.quick else list(args.methods)
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        print(f"unknown method(s) {unknown}; choose among {METHODS}")
        return 2
    print(
        f"redik bench pose: {n} targets per robot and seed mode, success = pos ≤ {POS_TOL:g} m, "
        f"rot ≤ {ROT_TOL:g} rad, inside the limits, checked by FK of the returned q"
    )
    rows = []
    for name in args.robots:
        robot = _load(name)
        rng = np.random.default_rng(args.seed)
        q_targets = robot.random_q(rng, size=n)
        targets = [robot.fk(q) for q in q_targets]
        starts = {
            "middle": np.tile(robot.midrange, (n, 1)),
            "random": robot.random_q(rng, size=n),
        }
        solvers = {m: _redik_solver(robot, m) for m in methods}
        if not args.no_references:
            solvers.update(_reference_solvers(robot))
        for mode, q0s in starts.items():
            for label, solver in solvers.items():
                if solver is None:
                    continue
                rows.append((robot.name, mode, label, *_measure(robot, solver, targets, q0s)))
    _print_table(rows)
    return 0


# --------------------------------------------------------------------------------------
# Measuring


def _load(name: str) -> Robot:
    from ..scenes import load

    return load(name)


def strict_success(robot: Robot, q: np.ndarray | None, T_target: np.ndarray) -> bool:
    """The benchmark's verdict: FK of ``q`` within both tolerances and ``q`` inside limits."""
    if q is None or np.shape(q) != (robot.dof,) or not np.all(np.isfinite(q)):
        return False
    position_error, rotation_error = lie.pose_errors(robot.fk(q), T_target)
    return position_error <= POS_TOL and rotation_error <= ROT_TOL and robot.within_limits(q)


def _measure(
    robot: Robot, solver: Solver, targets: list[np.ndarray], q0s: np.ndarray
) -> tuple[float, float, float]:
    times, successes = [], 0
    for index, (T_target, q0) in enumerate(zip(targets, q0s, strict=True)):
        start = time.perf_counter()
        q = solver(T_target, q0.copy(), index)
        times.append(time.perf_counter() - start)
        successes += strict_success(robot, q, T_target)
    milliseconds = 1e3 * np.array(times)
    return (
        100.0 * successes / len(targets),
        float(np.median(milliseconds)),
        float(np.percentile(milliseconds, 95)),
    )


def _print_table(rows: list[tuple[str, str, str, float, float, float]]) -> None:
    mink_median = {(r[0], r[1]): r[4] for r in rows if r[2] == "mink"}
    print(
        f"\n{'robot':8s} {'seeds':7s} {'solver':14s} {'success %':>9s} "
        f"{'median ms':>10s} {'p95 ms':>9s} {'median / mink':>14s}"
    )
    for robot, mode, label, success, median, p95 in rows:
        reference = mink_median.get((robot, mode))
        ratio = f"{median / reference:14.3f}" if reference else f"{'—':>14s}"
        print(f"{robot:8s} {mode:7s} {label:14s} {success:9.1f} {median:10.3f} {p95:9.3f} {ratio}")


# --------------------------------------------------------------------------------------
# Solvers


def _redik_solver(robot: Robot, method: str) -> Solver | None:
    if method == "qp":
        try:
            from ..qp.solve import solve_pose_qp  # noqa: F401
        except ImportError:
            print("note: method 'qp' skipped (redik.qp.solve is not available)")
            return None

    def solve(T_target: np.ndarray, q0: np.ndarray, index: int) -> np.ndarray:
        return solve_pose(
            robot, T_target, q0, method=method, pos_tol=POS_TOL, rot_tol=ROT_TOL, seed=index
        ).q

    return solve


def _reference_solvers(robot: Robot) -> dict[str, Solver | None]:
    solvers: dict[str, Solver | None] = {"mink": _mink_solver(robot)}
    solvers["rtb ik_LM"] = _rtb_solver(robot)
    solvers["TRAC-IK"] = _tracik_solver(robot)
    return solvers


def _mink_solver(robot: Robot) -> Solver | None:
    """A ``mink.solve_ik`` loop (daqp, configuration limits) until both tolerances hold."""
    import mink

    configuration = mink.Configuration(robot.model)
    task = mink.FrameTask(
        robot.ee.name, robot.ee.kind, position_cost=1.0, orientation_cost=1.0, lm_damping=1e-3
    )
    limits = [mink.ConfigurationLimit(robot.model)]
    indices = robot.qpos_indices
    frame = robot.ee

    def solve(T_target: np.ndarray, q0: np.ndarray, index: int) -> np.ndarray:
        configuration.update(robot.full_qpos(q0))
        task.set_target(mink.SE3.from_matrix(T_target))
        data = configuration.data
        for _ in range(MINK_MAX_ITER):
            if frame.kind == "site":
                p, R = data.site_xpos[frame.id], data.site_xmat[frame.id].reshape(3, 3)
            else:
                p, R = data.xpos[frame.id], data.xmat[frame.id].reshape(3, 3)
            if (
                float(np.linalg.norm(T_target[:3, 3] - p)) <= POS_TOL
                and lie.rotation_angle(R, T_target[:3, :3]) <= ROT_TOL
            ):
                break
            velocity = mink.solve_ik(
                configuration, [task], 1.0, "daqp", damping=1e-12, limits=limits
            )
            configuration.integrate_inplace(velocity, 1.0)
        return configuration.q[indices].copy()

    return solve


def _rtb_solver(robot: Robot) -> Solver | None:
    """Robotics Toolbox's C++ ``ik_LM`` on a ``DHRobot`` built from the scene's DH table."""
    try:
        import roboticstoolbox as rtb
    except ImportError:
        print("note: Robotics Toolbox (roboticstoolbox-python) not installed; ik_LM skipped")
        return None
    from ..model_builder import read_dh

    rows, convention, tool = read_dh(robot.model)
    links = []
    for row, lower, upper in zip(rows, robot.lower, robot.upper, strict=True):
        qlim = None if not math.isfinite(lower) else [lower, upper]
        if convention == "modified":
            kind = rtb.PrismaticMDH if row.is_prismatic else rtb.RevoluteMDH
        else:
            kind = rtb.PrismaticDH if row.is_prismatic else rtb.RevoluteDH
        if row.is_prismatic:
            link = kind(a=row.a, alpha=row.alpha, theta=row.theta, offset=row.d, qlim=qlim)
        else:
            link = kind(a=row.a, d=row.d, alpha=row.alpha, offset=row.theta, qlim=qlim)
        links.append(link)
    # The C++ solver ignores the DHRobot's base and tool: solve for the DH flange frame,
    # T_flange = base⁻¹ T_target tool⁻¹, where the scene may place the DH base elsewhere.
    dh_robot = rtb.DHRobot(links, name=robot.name)
    tool_inverse = lie.inverse(tool)
    base = robot.fk(robot.home) @ tool_inverse @ lie.inverse(dh_robot.fkine(robot.home).A)
    base_inverse = lie.inverse(base)
    q_check = robot.random_q(np.random.default_rng(1))
    if not np.allclose(base @ dh_robot.fkine(q_check).A @ tool, robot.fk(q_check), atol=1e-9):
        print(f"note: the rtb DH model of {robot.name} does not match the scene; ik_LM skipped")
        return None

    def solve(T_target: np.ndarray, q0: np.ndarray, index: int) -> np.ndarray | None:
        solution = dh_robot.ik_LM(
            base_inverse @ T_target @ tool_inverse, q0=q0, ilimit=30, slimit=100, tol=5e-13,
            joint_limits=True,
        )  # fmt: skip
        return np.asarray(solution[0], dtype=float)

    return solve


def _tracik_solver(robot: Robot) -> Solver | None:
    """TRAC-IK (``pytracik``) on a URDF written from the scene's DH table."""
    try:
        import pytracik
    except ImportError:
        print("note: TRAC-IK (pytracik) not installed; skipped")
        return None
    from ..model_builder import read_dh

    rows, convention, tool = read_dh(robot.model)
    solver = pytracik.TRAC_IK(
        "base", "tool", _dh_to_urdf(rows, convention, tool, robot), 0.005, POS_TOL,
        pytracik.SolveType.Speed,
    )  # fmt: skip
    # The URDF starts at the DH base frame; the scene may place that frame elsewhere.
    base = robot.fk(robot.home) @ lie.inverse(np.asarray(pytracik.fk(solver, robot.home)))
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


def _dh_to_urdf(rows, convention: str, tool: np.ndarray, robot: Robot) -> str:
    """A URDF with one joint per DH row: ``origin`` then a motion about the joint's z."""
    from ..dh import parse_convention, split_row

    def origin(T: np.ndarray) -> str:
        xyz = " ".join(f"{v:.12g}" for v in T[:3, 3])
        rpy = " ".join(f"{v:.12g}" for v in lie.euler_angles(T[:3, :3], "zyx")[::-1])
        return f'<origin xyz="{xyz}" rpy="{rpy}"/>'

    # Each row as (fixed transform, motion about z, fixed transform), the motion Rz(q) or Tz(q).
    before_after = [split_row(row, parse_convention(convention)) for row in rows]
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
