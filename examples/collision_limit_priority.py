"""A collision limit ranked below the hand: the hand reaches into a bin, the arm keeps clear.

A planar 3R arm's tip is asked to the centre of a spherical bin (priority 0); a posture
regulator sits at priority 1; a post stands where that posture would put the middle link.
The collision limit (all links against the bin and the post) is tried

- absent: the tip reaches the target, the middle link goes through the post;
- hard (the default, ``priority=None``): nothing collides, the tip stops outside the bin;
- ``priority=1``, ranked below the tip and above the posture: the tip (and the last link
  with it, unavoidably) enters the bin, and the rest of the arm keeps clear of the post;
- ``priority=2``, below the posture, which uses the last free direction: as if absent.

Run: python examples/collision_limit_priority.py
"""

import mujoco

import redik
from redik.limits import CollisionAvoidanceLimit, ConfigurationLimit
from redik.qp import Problem
from redik.tasks import PositionTask, PostureTask

XML = """
<mujoco model="planar_3r_bin_and_post">
  <compiler angle="radian"/>
  <worldbody>
    <geom name="bin" type="sphere" pos="1.6 1.2 0" size="0.2"/>
    <geom name="post" type="sphere" pos="1.38 -0.04 0" size="0.1"/>
    <body name="link1">
      <joint name="joint1" axis="0 0 1" range="-3 3"/>
      <geom name="link1" type="capsule" fromto="0.1 0 0 0.9 0 0" size="0.05"/>
      <body name="link2" pos="1 0 0">
        <joint name="joint2" axis="0 0 1" range="-2.8 2.8"/>
        <geom name="link2" type="capsule" fromto="0.1 0 0 0.9 0 0" size="0.05"/>
        <body name="link3" pos="1 0 0">
          <joint name="joint3" axis="0 0 1" range="-2.8 2.8"/>
          <geom name="link3" type="capsule" fromto="0.1 0 0 0.9 0 0" size="0.05"/>
          <site name="tip" pos="1 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
  <keyframe><key name="home" qpos="0.3 0.6 0.6"/></keyframe>
</mujoco>
"""
robot = redik.Robot(mujoco.MjModel.from_xml_string(XML), ee="tip")
links = ["link1", "link2", "link3"]
post = CollisionAvoidanceLimit([(["link1", "link2"], ["post"])]).bind(robot)
bin_ = CollisionAvoidanceLimit([(["link3"], ["bin"])]).bind(robot)

for priority in ("absent", None, 1, 2):
    limits = [ConfigurationLimit()]
    if priority != "absent":
        limits.append(
            CollisionAvoidanceLimit(
                [(links, ["bin", "post"])],
                minimum_distance=0.01,
                detection_distance=0.1,
                priority=priority,
            )
        )
    tasks = [PositionTask("tip", target=[1.6, 1.2, 0.0]), PostureTask(priority=1)]
    result = redik.solve_problem(Problem(robot, tasks, limits), robot.home)
    label = "no collision limit" if priority == "absent" else f"priority={priority}"
    print(
        f"{label:>18}: {result.status:>9}, tip {result.position_error * 1000:6.1f} mm from "
        f"target; arm to post {post.minimum_distance_at(result.q)[0] * 1000:+7.1f} mm, "
        f"last link to bin {bin_.minimum_distance_at(result.q)[0] * 1000:+7.1f} mm"
    )
