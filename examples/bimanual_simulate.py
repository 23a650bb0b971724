"""Closed-loop headless simulation of Baxter: the left gripper draws a circle, the right holds.

URDFs carry no actuators, so this script adds a position servo to each of the 14 arm joints
(and gravity compensation on the links) with ``MjSpec`` before compiling, and steps with
the ``implicitfast`` integrator (the servos' damping on the light wrist links is stiff for
explicit Euler). Physics contacts are off because Baxter's URDF collision shapes overlap at
rest; the QP's collision limit still keeps the arms and the head apart. Each 10 ms tick the
QP (both gripper poses at priority 0, a posture at priority 1; joint position, velocity and
collision limits) gives the joint step, and MuJoCo steps the physics.
Needs ``pip install "redik[models]"``. Run: python examples/bimanual_simulate.py
"""

import mujoco
import numpy as np

import redik
from redik.apps.sim import simulate
from redik.apps.trajectory import CircularPath
from redik.lie import make_pose, pose_errors

spec = redik.models.loading.load_spec(redik.models.example_robot_data("baxter"), meshes=False)
arms = [joint.name for joint in spec.joints if joint.name[:-1].endswith(("_s", "_e", "_w"))]
for name in arms:
    servo = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
    servo.set_to_position(kp=800.0, kv=80.0)
for body in spec.bodies:
    body.gravcomp = 1.0
spec.option.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
# The URDF's light wrist links make the servos' damping stiff for explicit Euler.
spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
robot = redik.Robot(spec.compile(), joints=arms)
print(robot, f"with {robot.model.nu} position servos")

down = np.diag([1.0, -1.0, -1.0])
left = redik.FrameTask("left_gripper", target=make_pose(down, [0.75, 0.25, 0.1]))
right = redik.FrameTask("right_gripper", target=make_pose(down, [0.75, -0.25, 0.1]))
q0 = redik.solve_problem(
    redik.Problem(robot, [left, right, redik.PostureTask(priority=1)]), robot.home
).q

T_left = robot.fk(q0, "left_gripper")
circle = CircularPath(T_left, T_left[:3, 3] + [0.0, 0.08, 0.0], normal=[0, 0, 1], duration=4.0)
collisions = redik.CollisionAvoidanceLimit(
    [(["left_*"], ["right_*"]), (["left_*", "right_*"], ["head", "screen", "sonar_ring"])]
)
problem = redik.Problem(
    robot,
    [left, right, redik.PostureTask(q0, cost=0.1, priority=1)],
    [redik.ConfigurationLimit(), redik.VelocityLimit(2.0), collisions],
)
result = simulate(robot, problem, left, circle, q0=q0, control_rate=100.0)
print("left gripper (the circle):", result.summary())

# The right gripper's pose in every simulated state.
drift = [pose_errors(robot.fk(q, "right_gripper"), right.target)[0] for q in result.q]
print(f"right gripper (held): largest drift {max(drift) * 1000:.2f} mm")
