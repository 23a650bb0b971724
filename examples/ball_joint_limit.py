"""A shoulder ball joint with a 1 rad cone (MuJoCo's ball ``range``) reaching past it.

The arm has a ball shoulder (range 0–1 rad), an elbow hinge and a wrist hinge. The hand is
asked to a point the shoulder can only reach by rotating 1.4 rad. ``ConfigurationLimit`` boxes
hinges and slides only; ``redik.BallJointLimit`` adds the cone, so the solve stops at the
rim, 1.000 rad (every iterate inside it), with the hand 184 mm short: the closest the cone
allows (the wrist at 1 rad is 233 mm from the target, less the 50 mm hand turned towards
it). Run: python examples/ball_joint_limit.py
"""

import mujoco
import numpy as np

import redik

XML = """
<mujoco model="ball_shoulder_arm">
  <compiler angle="radian"/>
  <worldbody>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" type="ball" range="0 1"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <body name="fore" pos="0.3 0 0">
        <joint name="elbow" axis="0 1 0" range="-2 2"/>
        <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.025"/>
        <body name="hand" pos="0.25 0 0">
          <joint name="wrist" axis="0 0 1" range="-1.5 1.5"/>
          <geom type="box" size="0.03 0.02 0.01" pos="0.03 0 0"/>
          <site name="ee" pos="0.05 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

robot = redik.Robot(mujoco.MjModel.from_xml_string(XML), joints="all")
print(robot, robot.joint_types)


# The straight arm turned 1.4 rad about z: the target of the hand.
q_far = robot.home.copy()
q_far[:4] = [np.cos(0.7), 0.0, 0.0, np.sin(0.7)]
target = robot.fk(q_far, "ee")[:3, 3]
tasks = [redik.PositionTask("ee", target=target), redik.PostureTask(priority=1)]

cone = redik.BallJointLimit().bind(robot)
for limits in ([redik.ConfigurationLimit()], [redik.ConfigurationLimit(), cone]):
    result = redik.solve_problem(redik.Problem(robot, tasks, limits), robot.home)
    miss = np.linalg.norm(robot.fk(result.q, "ee")[:3, 3] - target)
    largest = max(cone.angles_at(q)[0] for q in result.history)
    names = " + ".join(type(limit).__name__ for limit in limits)
    print(f"{names}: {result.status}, shoulder {cone.angles_at(result.q)[0]:.3f} rad ", end="")
    print(f"(largest over the iterates {largest:.3f}), hand {miss * 1000:.1f} mm from target")
