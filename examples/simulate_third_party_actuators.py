"""Closed-loop simulation on actuation you did not write: servos without gravcomp, torque motors.

MuJoCo Menagerie's arms drive each joint with a position servo (``kp`` 500–4500, no
``gravcomp``): held by the servo alone, an arm sags by ``g(q) / kp``. Other models use
``<motor>`` (torque) actuators, which a joint angle must never be sent to. ``simulate`` reads
each actuator's kind and feeds the inverse-dynamics torque forward (``mj_inverse``: gravity,
Coriolis, inertia, joint damping); motors get the computed-torque law. This script builds
both variants of the bundled iiwa14 with ``MjSpec`` and runs the same 10 cm circle on each,
with and without the feed-forward, then shows what ``simulate`` refuses.

Run: python examples/simulate_third_party_actuators.py
"""

import warnings

import mujoco

import redik
from redik.apps.sim import TrackingWarning, joint_drives, simulate
from redik.apps.trajectory import CircularPath
from redik.limits import ConfigurationLimit, VelocityLimit
from redik.qp import Problem
from redik.tasks import FrameTask, PostureTask


def iiwa14(actuation: str) -> redik.Robot:
    """The bundled iiwa14, gravcomp removed, with Menagerie's servos or torque motors."""
    spec = mujoco.MjSpec.from_file(str(redik.models.scene_path("iiwa14")))
    for body in spec.bodies:
        body.gravcomp = 0.0
    for actuator in spec.actuators:
        if actuation == "servo":
            actuator.set_to_position(kp=2000.0, kv=200.0)  # Menagerie's iiwa14 gains
        elif actuation == "motor":
            actuator.set_to_motor()
            actuator.ctrlrange = [-320.0, 320.0]
        else:  # a velocity servo: simulate() refuses it by name
            actuator.set_to_velocity(kv=30.0)
    return redik.Robot(spec.compile(), name=f"iiwa14 ({actuation})")


def circle_run(robot: redik.Robot, feedforward: bool = True):
    T0 = robot.fk(robot.home)
    path = CircularPath(T0, T0[:3, 3] + [0.0, 0.0, 0.1], [1.0, 0.0, 0.0], duration=4.0)
    pose = FrameTask("ee", target=T0)
    problem = Problem(
        robot,
        [pose, PostureTask(robot.home, cost=0.1, priority=1)],
        limits=[ConfigurationLimit(), VelocityLimit(2.0)],
    )
    return simulate(robot, problem, pose, path, feedforward=feedforward, error_bound=(3e-3, 0.01))


for actuation in ("servo", "motor"):
    robot = iiwa14(actuation)
    print(f"{robot.name}: joints driven by {set(joint_drives(robot).kinds)}")
    print(f"  feed-forward:    {circle_run(robot).summary()}")
    if actuation == "servo":
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", TrackingWarning)
            result = circle_run(robot, feedforward=False)
        print(f"  no feed-forward: {result.summary()}")
        print(f"  warned: {caught[0].category.__name__}" if caught else "  no warning")

try:
    joint_drives(iiwa14("velocity"))
except redik.ModelError as error:
    print(f"refused: {error}")
