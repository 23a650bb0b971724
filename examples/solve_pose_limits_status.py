"""Why a solve failed: "limits" (reached only outside the joint limits) versus "unreachable".

A planar 2R arm whose elbow bends only ±1 rad is asked for a pose that needs 2.9 rad. With the
limits respected the solve fails; one solve without them (run on failure only) converges
outside the limits, so the status is "limits" and the message names the joints at their
limits. A target beyond the arm's 2 m reach stays "unreachable".

Run: python examples/solve_pose_limits_status.py
"""

import numpy as np

import redik
from redik.solvers.pose import solve_pose

NARROW_2R = """
<mujoco model="narrow_2r">
  <compiler angle="radian"/>
  <worldbody>
    <body name="upper_arm">
      <joint name="shoulder" type="hinge" axis="0 0 1" range="-1 1"/>
      <geom type="capsule" fromto="0 0 0 1 0 0" size="0.03"/>
      <body name="forearm" pos="1 0 0">
        <joint name="elbow" type="hinge" axis="0 0 1" range="-1 1"/>
        <geom type="capsule" fromto="0 0 0 1 0 0" size="0.03"/>
        <site name="ee" pos="1 0 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

robot = redik.Robot.from_xml_string(NARROW_2R)
inside = solve_pose(robot, robot.fk(np.array([0.3, 0.9])), seed=0)
print(f"elbow 0.9 rad:  {inside.status}")

folded = solve_pose(robot, robot.fk(np.array([0.3, 2.9])), seed=0)
print(f"elbow 2.9 rad:  {folded.status}: {folded.message}")
print("  closest q within the limits:", np.round(folded.q, 3))
plain = solve_pose(robot, robot.fk(np.array([0.3, 2.9])), seed=0, diagnose_limits=False)
print(f"  without the diagnosis: {plain.status}")

far = redik.lie.make_pose(np.eye(3), np.array([3.0, 0.0, 0.0]))
print(f"3 m away:       {solve_pose(robot, far, seed=0).status}")
