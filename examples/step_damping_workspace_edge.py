"""Online IK at the edge of the workspace: undamped steps reverse every tick, damped ones do not.

The Panda starts at MuJoCo Menagerie's ``home`` (q₂ = 0) and is asked to trace a vertical
10 cm circle holding its orientation; the circle's top is 39 mm beyond the stretched elbow,
out of reach. At that fold of the workspace the Gauss–Newton step of ``problem.step`` jumps
across the singularity, the 2 rad/s velocity box clips it, and the next tick jumps back.
``Problem(..., step_damping=10)`` solves the step as damped least squares (λ = μ‖We‖²):
smooth, and missing the top by the gap only. Both runs drive the arm's servos in MuJoCo.

Run: python examples/step_damping_workspace_edge.py
"""

import warnings

import numpy as np

import redik
from redik.apps.sim import TrackingWarning, simulate
from redik.apps.trajectory import CircularPath
from redik.limits import ConfigurationLimit, VelocityLimit
from redik.qp import Problem
from redik.tasks import FrameTask

robot = redik.load("panda")
q0 = np.array([0.0, 0.0, 0.0, -1.57079, 0.0, 1.57079, -0.7853])  # Menagerie's home
T0 = robot.fk(q0)
path = CircularPath(T0, center=T0[:3, 3] + [0.0, 0.0, 0.1], normal=[1.0, 0.0, 0.0], duration=4.0)

for step_damping in (0.0, 10.0):
    pose = FrameTask("ee", target=T0)
    limits = [ConfigurationLimit(), VelocityLimit(2.0)]
    problem = Problem(robot, [pose], limits=limits, step_damping=step_damping)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TrackingWarning)  # the top is out of reach: expected
        result = simulate(robot, problem, pose, path, q0=q0, control_rate=100.0)
    velocity = np.diff(result.q_command, axis=0) * result.control_rate
    reversals = np.sum(
        (np.sign(velocity[1:]) * np.sign(velocity[:-1]) < 0)
        & (np.abs(np.diff(velocity, axis=0)) > 1.0)
    )
    print(f"step_damping = {step_damping:g}: {reversals} joint-velocity reversals > 1 rad/s")
    print(f"  {result.summary()}")
