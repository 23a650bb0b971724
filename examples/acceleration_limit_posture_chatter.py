"""A posture regulator below a pose task chatters at the edge of reach; an acceleration
limit stops it.

The Panda starts at MuJoCo Menagerie's ``home`` and traces a vertical 10 cm circle whose top
is 39 mm beyond the stretched elbow. Level 0 (the pose) is damped (``step_damping=10``);
level 1 is a posture regulator of gain 1 back to ``home``. Near the fold, the null space the
posture moves in turns by a large angle per tick, and its step flips between corners of
the 2 rad/s velocity box at every tick: a two-tick cycle at 400 rad/s² that no servo
follows. ``AccelerationLimit(20)`` bounds the change of commanded velocity per tick
(|q̈| ≤ 20 rad/s²) and brakes before the joint limits. Both runs drive the arm's servos in
MuJoCo (``simulate``).

Run: python examples/acceleration_limit_posture_chatter.py
"""

import warnings

import numpy as np

import redik
from redik.apps.sim import TrackingWarning, simulate
from redik.apps.trajectory import CircularPath
from redik.limits import AccelerationLimit, ConfigurationLimit, VelocityLimit
from redik.qp import Problem
from redik.tasks import FrameTask, PostureTask

robot = redik.load("panda")
q0 = np.array([0.0, 0.0, 0.0, -1.57079, 0.0, 1.57079, -0.7853])  # Menagerie's home
T0 = robot.fk(q0)
path = CircularPath(T0, center=T0[:3, 3] + [0.0, 0.0, 0.1], normal=[1.0, 0.0, 0.0], duration=4.0)

for extra in ([], [AccelerationLimit(20.0)]):
    pose = FrameTask("ee", target=T0)
    limits = [ConfigurationLimit(), VelocityLimit(2.0), *extra]
    problem = Problem(robot, [pose, PostureTask(q0, priority=1)], limits, step_damping=10.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TrackingWarning)  # the top is out of reach: expected
        result = simulate(robot, problem, pose, path, q0=q0, control_rate=100.0)
    velocity = np.diff(result.q_command, axis=0) * result.control_rate
    flips = (np.sign(velocity[1:]) * np.sign(velocity[:-1]) < 0) & (
        np.abs(np.diff(velocity, axis=0)) > 0.1
    )
    cycles = int(np.sum(flips[1:] & flips[:-1]))  # reversing at two ticks in a row
    acceleration = np.abs(np.diff(velocity, axis=0)).max() * result.control_rate
    name = "with AccelerationLimit(20)" if extra else "velocity box only"
    print(f"{name}: {cycles} two-tick velocity reversals, max |q̈| {acceleration:.0f} rad/s²")
    print(f"  {result.summary()}")
