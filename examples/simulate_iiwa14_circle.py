"""Closed-loop headless simulation: the QP steers the iiwa14's position servos around a circle.

Each 10 ms tick the QP (pose task over a posture task, position and velocity limits) gives
the joint step; the servos track the integrated reference with feed-forward; MuJoCo steps
the physics. Prints the tracking error and writes a plot and a video (MP4 when
imageio-ffmpeg is installed, else GIF) — rendered offscreen, no display needed.

Run: MUJOCO_GL=egl python examples/simulate_iiwa14_circle.py   (writes to $REDIK_OUT or .)
"""

import os
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")  # before MuJoCo is imported: offscreen rendering

import redik
from redik.apps.render import render_states, save_video
from redik.apps.sim import plot_tracking, simulate
from redik.apps.trajectory import CircularPath
from redik.limits import ConfigurationLimit, VelocityLimit
from redik.qp import Problem
from redik.tasks import FrameTask, PostureTask

robot = redik.load("iiwa14")
T0 = robot.fk(robot.home)
path = CircularPath(T0, center=T0[:3, 3] + [0.0, 0.0, 0.1], normal=[1.0, 0.0, 0.0], duration=4.0)
pose = FrameTask("ee", target=T0)
problem = Problem(
    robot,
    [pose, PostureTask(robot.home, cost=0.1, priority=1)],
    limits=[ConfigurationLimit(), VelocityLimit(2.0)],
)
result = simulate(robot, problem, pose, path, control_rate=100.0)
print(result.summary())

out = Path(os.environ.get("REDIK_OUT", "."))
print(f"wrote {plot_tracking(result, out / 'tracking.png', title='iiwa14 circle, 100 Hz')}")
try:
    import imageio_ffmpeg  # noqa: F401  (only to choose the format)

    video = out / "tracking.mp4"
except ImportError:
    video = out / "tracking.gif"
frames = render_states(robot, result.qpos[::8], width=320, height=400, target=path.pose(0.0))
print(f"wrote {save_video(video, frames, fps=12.5)}")
