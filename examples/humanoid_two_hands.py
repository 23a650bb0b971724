"""Unitree G1 (a floating-base humanoid URDF from example-robot-data) reaches with both hands.

The whole model moves: the free joint of the pelvis (7 ``qpos``, 6 tangent coordinates),
the legs, the waist and both arms, 35 tangent coordinates in all, integrated on SE(3)
(``mj_integratePos``). Priority 0: both hand poses and both feet staying where they stand.
Priority 1: the posture. Limits: joint boxes and collision avoidance between the arms and
the body (collision meshes). Needs ``pip install "redik[models]"``.
Run: python examples/humanoid_two_hands.py
"""

import numpy as np

import redik
from redik.lie import make_pose, pose_errors

robot = redik.load("example-robot-data:g1", joints="all", floating_base=True)
print(robot)

q0 = robot.home
feet = {foot: robot.fk(q0, foot) for foot in ("left_ankle_roll_link", "right_ankle_roll_link")}
hands = {
    "left_rubber_hand": make_pose(np.eye(3), [0.35, 0.12, 0.15]),
    "right_rubber_hand": make_pose(np.eye(3), [0.35, -0.12, 0.15]),
}
tasks = [redik.FrameTask(frame, target=T, priority=0) for frame, T in {**hands, **feet}.items()]
tasks.append(redik.PostureTask(priority=1))
arms = ["left_shoulder_*", "left_elbow*", "left_wrist*"]
arms += [name.replace("left", "right") for name in arms]
collisions = redik.CollisionAvoidanceLimit(
    [(arms, ["torso_link", "pelvis*", "*hip*", "*knee*", "head_link", "logo_link"])],
    minimum_distance=0.01,
    detection_distance=0.08,
)
problem = redik.Problem(robot, tasks, [redik.ConfigurationLimit(), collisions])

result = redik.solve_problem(problem, q0)
print(result.summary())
for frame, T in {**hands, **feet}.items():
    p_err, r_err = pose_errors(robot.fk(result.q, frame), T)
    print(f"  {frame}: position error {p_err:.1e} m, rotation error {r_err:.1e} rad")
base = result.q[:7]
print("pelvis moved to", np.round(base[:3], 3), "quaternion", np.round(base[3:], 3))
distance, pair = collisions.minimum_distance_at(result.q)
print(f"closest geoms {pair}: {distance * 1000:.1f} mm apart ({len(collisions.pairs)} pairs)")
print("within joint limits:", robot.within_limits(result.q))

# The same stack without the collision limit reaches the hands too, but a shoulder link ends
# inside the torso (by 1.1 mm: the printed distance is negative).
free = redik.solve_problem(redik.Problem(robot, tasks), q0)
distance, pair = collisions.minimum_distance_at(free.q)
print(f"without the limit: {free.summary()}; closest geoms {pair}: {distance * 1000:.1f} mm")
