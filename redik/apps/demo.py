"""The main job on a bundled scene, end to end: ``redik demo`` (and ``make demo``).

1. **Target.** A pose of the Dexter-style 8R arm (``dexter8r``), reached by a configuration
   away from ``home``, so the answer is not the start.
2. **QP solve.** :class:`redik.qp.problem.Problem` with the pose task at priority 0 and, at
   priority 1 (strictly inside the pose task's null space), joint-limit avoidance and a
   nominal posture (``home``), iterated from ``home`` to 1e-6 m / 1e-5 rad.
3. **Self-motion.** :func:`redik.solvers.redundancy.explore_self_motion` covers the 2-D surface of
   configurations that hold the same pose (8 joints − 6 constraints), seeded with the QP
   solution; each sample is scored by joint-limit margin, manipulability and distance to
   the nominal posture, and the QP's choice is compared with the best samples.
4. **Outputs** in the folder: ``summary.json`` (all numbers), ``selfmotion.npz`` (samples),
   ``manifold.png`` (joint pairs coloured by criterion), ``solution.png`` (headless render
   of the QP solution) and ``selfmotion.gif`` (the arm walking across its self-motion
   with the end-effector held still). A short summary is printed.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from redik.apps.render import render_frames, save_gif, save_png
from redik.apps.selfmotion_plot import plot_joint_pairs
from redik.core.result import IKResult
from redik.kinematics.robot import Robot, load
from redik.lie import pose_errors
from redik.qp import Problem
from redik.solvers.pose import solve_pose
from redik.solvers.redundancy import (
    SelfMotion,
    default_criteria,
    evaluate_criteria,
    explore_self_motion,
)
from redik.solvers.task_stack import solve_problem
from redik.tasks import FrameTask, JointLimitAvoidanceTask, PostureTask

SCENE = "dexter8r"
TARGET_OFFSET = np.array([0.5, 0.3, -0.3, 0.6, 0.4, -0.5, -0.4, 0.6])
"""Joint offset from ``home`` of the configuration that defines the demo's target pose."""


@dataclasses.dataclass
class DemoResult:
    """What the demo computed and where it wrote it."""

    robot: Robot
    target: np.ndarray
    solution: IKResult
    motion: SelfMotion
    summary: dict
    files: list[Path]


def run_demo(
    out: str | Path,
    *,
    seed: int = 0,
    max_samples: int = 1500,
    spacing: float = 0.25,
    log: Callable[[str], None] = print,
) -> DemoResult:
    """Run the demo (module docstring), writing into ``out``; returns the numbers too."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    robot = load(SCENE)
    nominal = robot.home.copy()
    q_target = np.clip(robot.home + TARGET_OFFSET, robot.lower, robot.upper)
    target = robot.fk(q_target)

    log(f"[1/4] QP solve on {robot.name} ({robot.dof} joints, redundancy {robot.dof - 6})")
    pose = FrameTask("ee", target=target)
    problem = Problem(
        robot,
        [
            pose,
            JointLimitAvoidanceTask(cost=1.0, priority=1),
            PostureTask(nominal, cost=0.3, priority=1),
        ],
    )
    started = time.perf_counter()
    solution = solve_problem(problem, robot.home)
    solve_seconds = time.perf_counter() - started
    position_error, rotation_error = pose_errors(robot.fk(solution.q), target)

    log(f"[2/4] exploring the self-motion surface (spacing {spacing} rad)")
    motion = explore_self_motion(
        robot, target, spacing=spacing, seed=seed, n_starts=16, initial=solution.q[None],
        max_samples=max_samples, nominal=nominal,
    )  # fmt: skip
    qp_scores = {
        name: float(values[0])
        for name, values in evaluate_criteria(
            robot, solution.q[None], default_criteria(robot, nominal), robot.frame(None)
        ).items()
    }

    log("[3/4] writing data and plots")
    files = [out / "selfmotion.npz", out / "manifold.png"]
    motion.save(files[0])
    plot_joint_pairs(
        motion, "posture_distance", lower=robot.lower, upper=robot.upper, path=files[1],
        marks={"QP solution": solution.q, "best posture sample": motion.best("posture_distance")},
    )  # fmt: skip

    log("[4/4] rendering headless (MUJOCO_GL=egl)")
    tour = _hold_pose(robot, target, _densify(motion.samples[motion.walk(0)], 0.1))
    drift = max(pose_errors(robot.fk(q), target)[0] for q in tour)
    files += _render(robot, solution.q, tour, target, out)

    summary = {
        "scene": robot.name,
        "target": target.tolist(),
        "qp": {
            "status": solution.status.value,
            "success": bool(solution.success and robot.within_limits(solution.q)),
            "iterations": solution.iterations,
            "position_error": position_error,
            "rotation_error": rotation_error,
            "seconds": solve_seconds,
            "q": solution.q.tolist(),
            "criteria": qp_scores,
        },
        "self_motion": {**motion.summary(), "spacing": spacing},
        "qp_vs_best_sample": {
            name: {
                "qp": qp_scores[name],
                "best_sample": float(motion.criteria[name][motion.best_index(name)]),
                "maximize": motion.maximize[name],
            }
            for name in motion.criteria
        },
        "tour_frames": len(tour),
        "tour_max_end_effector_drift": drift,
    }
    files.append(out / "summary.json")
    files[-1].write_text(json.dumps(summary, indent=2) + "\n")
    return DemoResult(robot, target, solution, motion, summary, files)


def format_summary(result: DemoResult) -> str:
    """The few lines ``redik demo`` prints."""
    s = result.summary
    qp, sm = s["qp"], s["self_motion"]
    lines = [
        f"{s['scene']}: QP (pose | joint-limit avoidance + posture) {qp['status']} in "
        f"{qp['iterations']} iterations, {qp['seconds'] * 1e3:.1f} ms; error "
        f"{qp['position_error']:.1e} m, {qp['rotation_error']:.1e} rad",
        f"self-motion: {sm['samples']} samples on {len(sm['components'])} component(s) of "
        f"dimension {sm['dimension']} in {sm['elapsed_s']:.1f} s; max error "
        f"{sm['max_position_error']:.1e} m, {sm['max_rotation_error']:.1e} rad",
    ]
    for name, row in s["qp_vs_best_sample"].items():
        better = "higher" if row["maximize"] else "lower"
        lines.append(
            f"  {name:<20} QP solution {row['qp']:.4g}   best sample {row['best_sample']:.4g}"
            f"  ({better} is better)"
        )
    lines.append(
        f"tour: {s['tour_frames']} frames, end-effector drift ≤ "
        f"{s['tour_max_end_effector_drift']:.1e} m"
    )
    lines.append("wrote " + ", ".join(str(path) for path in result.files))
    return "\n".join(lines)


def _render(
    robot: Robot, q: np.ndarray, tour: np.ndarray, target: np.ndarray, out: Path
) -> list[Path]:
    """A PNG of ``q`` and a GIF along ``tour`` (target frame drawn), rendered offscreen."""
    png = save_png(out / "solution.png", render_frames(robot, [q], 400, 320, target=target)[0])
    gif = save_gif(
        out / "selfmotion.gif", render_frames(robot, tour, 320, 256, target=target), 25.0
    )
    return [png, gif]


def _hold_pose(robot: Robot, target: np.ndarray, path: np.ndarray) -> np.ndarray:
    """Each point of ``path`` corrected back onto ``target`` by minimum-norm Newton steps."""
    return np.array([solve_pose(robot, target, q0=q, method="newton", restarts=0).q for q in path])


def _densify(path: np.ndarray, step: float) -> np.ndarray:
    """Joint-space points along ``path`` at most ``step`` apart (linear between samples)."""
    points = [path[0]]
    for a, b in itertools.pairwise(path):
        count = max(1, int(np.ceil(np.linalg.norm(b - a) / step)))
        points += [a + (b - a) * k / count for k in range(1, count + 1)]
    return np.array(points)
