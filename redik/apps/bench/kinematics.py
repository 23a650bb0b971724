"""FK + Jacobian cost per call: redik's hot path and checked API beside raw MuJoCo calls.

The reference is the bare sequence a hand-written loop would make (set qpos,
``mj_kinematics``, ``mj_comPos``, ``mj_jacSite``) measured in the same run; redik's overhead is
reported as a difference and a ratio against it.
"""

from __future__ import annotations

import argparse
import statistics
import time

import mujoco
import numpy as np

from redik.apps import measured
from redik.kinematics.robot import load


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add this benchmark's options to its ``redik bench`` subparser."""
    parser.add_argument("--robots", nargs="+", default=["panda", "iiwa14", "ur5e"])
    parser.add_argument("--calls", type=int, default=20000, help="calls per repeat")
    parser.add_argument("--repeats", type=int, default=7, help="repeats; the median is reported")


def _median_us(fn, calls: int, repeats: int) -> float:
    """Median over ``repeats`` of the time per call of ``fn`` (µs), ``calls`` calls each."""
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            fn()
        samples.append((time.perf_counter() - start) / calls * 1e6)
    return statistics.median(samples)


def _cases(robot) -> dict:
    """The timed calls, the bare MuJoCo sequence (the reference) first."""
    model, data = robot.model, robot.state.data
    q = robot.random_q(0)
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    site = robot.ee.id
    T, J = np.eye(4), np.empty((6, robot.dof))

    def raw():
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        mujoco.mj_jacSite(model, data, jacp, jacr, site)

    def checked():
        robot.fk(q)
        robot.jacobian(q, reference="world")

    return {
        "raw MuJoCo (qpos, kin, comPos, jac)": raw,
        "robot.kinematics (hot path)": lambda: robot.state.kinematics(q, robot.ee, T, J),
        "robot.fk + robot.jacobian (checked)": checked,
        "python call overhead (empty lambda)": lambda: None,
    }


def run(args: argparse.Namespace) -> int:
    """Print the median time per call of each case and its ratio to the raw MuJoCo calls."""
    print(f"{'robot':<8}{'case':<38}{'median µs':>11}{'vs raw':>9}")
    for name in args.robots:
        reference = None
        for label, fn in _cases(load(name)).items():
            median = _median_us(fn, args.calls, args.repeats)
            reference = reference or median
            print(f"{name:<8}{label:<38}{median:>11.2f}{median / reference:>8.2f}×")
            measured.record(
                "FK + world Jacobian per call",
                robot=name,
                case=label,
                median_us=median,
                vs_raw=median / reference,
            )
    return 0
