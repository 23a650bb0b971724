"""A humanoid on a floating base in closed-loop simulation: refused free, tracked held.

Unitree G1 (example-robot-data's URDF) loaded with ``floating_base=True`` hangs from a free
joint that no actuator drives. With gravity and nothing under it, it would fall, so
``simulate`` refuses it; ``hold_base=True`` holds the pelvis at its initial pose, and the left
hand traces a 5 cm circle on position servos (one per joint, gravity compensated). The run's
status and contacts are printed with its summary.
Needs ``pip install "redik[models]"``. Run: python examples/simulate_humanoid_held_base.py
"""

import mujoco
import numpy as np

import redik
from redik.apps.sim import simulate
from redik.apps.trajectory import CircularPath

PARTS = ("shoulder", "elbow", "wrist")  # the left arm's joints: left_shoulder_pitch_joint, …

spec = redik.models.loading.load_spec(
    redik.models.example_robot_data("g1"), meshes=False, floating_base=True
)
for body in spec.bodies:
    body.gravcomp = 1.0
joints = [joint.name for joint in spec.joints if joint.type != mujoco.mjtJoint.mjJNT_FREE]
for name in joints:
    servo = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
    servo.set_to_position(kp=100.0, kv=10.0)
spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
arm = [name for name in joints if name.startswith(tuple(f"left_{part}" for part in PARTS))]
robot = redik.Robot(spec.compile(), ee="left_rubber_hand", joints=arm)
print(robot, "on its free joint 'floating_base'")

hand = redik.FrameTask("left_rubber_hand", target=robot.fk(robot.home))
problem = redik.Problem(
    robot,
    [hand, redik.PostureTask(robot.home, cost=0.1, priority=1)],
    [redik.ConfigurationLimit(), redik.VelocityLimit(2.0)],
)
T0 = robot.fk(robot.home)
circle = CircularPath(T0, T0[:3, 3] + [0.0, 0.05, 0.0], normal=[1.0, 0.0, 0.0], duration=2.0)

try:
    simulate(robot, problem, hand, circle)
except redik.ModelError as error:
    print("refused:", error)

result = simulate(robot, problem, hand, circle, hold_base=True)
print(f"held base {result.held_base!r}, status {result.status}:", result.summary())
base_motion = np.abs(result.qpos[:, :7] - result.qpos[0, :7]).max()
print(f"the pelvis moved {base_motion:.1e} (held); {len(result.contacts)} contact pair(s)")
