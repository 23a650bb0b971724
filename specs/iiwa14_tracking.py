"""iiwa14 tracking a circle in closed-loop MuJoCo simulation, headless.

Each control tick the QP (pose task over a posture task, position and velocity limits)
computes the joint step, the scene's position servos track the integrated reference with
velocity and inertial feed-forward, and ``mj_step`` advances the physics (``redik.apps.sim``).
The end-effector traces a 10 cm circle in 4 s (peak 0.3 m/s). Success: the run completes
(MuJoCo reports no instability), and the simulated end-effector stays within 3 mm and
0.01 rad of the moving reference and settles within 0.05 mm — the bound
``tests/test_sim.py`` holds too.
"""

import numpy as np

import redik
from redik.apps.sim import plot_tracking, simulate
from redik.apps.trajectory import CircularPath
from redik.limits import ConfigurationLimit, VelocityLimit
from redik.qp import Problem
from redik.tasks import FrameTask, PostureTask

CRITERIA = {
    "completed": "== 1",
    "max_position_error": "<= 3e-3",
    "max_rotation_error": "<= 1e-2",
    "final_position_error": "<= 5e-5",
}


def run(ctx):
    robot = redik.load("iiwa14")
    T_home = robot.fk(robot.home)
    path = CircularPath(T_home, T_home[:3, 3] + [0.0, 0.0, 0.1], [1.0, 0.0, 0.0], duration=4.0)
    pose = FrameTask("ee", target=T_home)
    problem = Problem(
        robot,
        [pose, PostureTask(robot.home, cost=0.1, priority=1)],
        limits=[ConfigurationLimit(), VelocityLimit(2.0)],
    )
    rate = ctx.size(full=250.0, fast=100.0)
    ticks = iter(ctx.progress(range(round(path.duration * rate)), desc="iiwa14 ticks"))
    result = simulate(
        robot, problem, pose, path, control_rate=rate, on_tick=lambda k, n: next(ticks)
    )
    plot_tracking(result, ctx.path("tracking.png"), title=f"iiwa14 circle at {rate:g} Hz")
    arrays = ("times", "q", "q_command", "position_error", "rotation_error")
    np.savez(ctx.path("tracking.npz"), **{name: getattr(result, name) for name in arrays})
    return {
        "completed": float(result.status == "completed"),
        "max_position_error": result.max_position_error,
        "rms_position_error": result.rms_position_error,
        "max_rotation_error": result.max_rotation_error,
        "final_position_error": result.final_position_error,
        "control_hz": rate,
    }
