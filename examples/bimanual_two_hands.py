"""Baxter (a bimanual URDF from example-robot-data) puts both grippers on target poses.

Priority 0: the two gripper poses. Priority 1: a posture. Limits: the joint box, and
collision avoidance between the two arms and between each arm and the head and a table
added to the model. The arms (7 joints each) move; the head and fingers are held. Then
the left arm alone runs the serial-chain fast path (compiled DLS) on ``robot.chain``.
Needs ``pip install "redik[models]"``. Run: python examples/bimanual_two_hands.py
"""

import numpy as np

import redik
from redik.lie import make_pose, pose_errors

spec = redik.models.loading.load_spec(redik.models.example_robot_data("baxter"), meshes=False)
table = spec.worldbody.add_geom(name="table", size=[0.3, 0.6, 0.02], pos=[0.85, 0.0, -0.2])
table.type = redik.models.loading.mujoco.mjtGeom.mjGEOM_BOX
robot = redik.Robot(spec.compile(), joints=["left_[sew][0-9]", "right_[sew][0-9]"])
print(robot, "moves", robot.joint_names)

down = np.diag([1.0, -1.0, -1.0])  # gripper z axis pointing down
targets = {
    "left_gripper": make_pose(down, [0.75, 0.2, 0.0]),
    "right_gripper": make_pose(down, [0.75, -0.2, 0.0]),
}
tasks = [redik.FrameTask(frame, target=T, priority=0) for frame, T in targets.items()]
tasks.append(redik.PostureTask(priority=1))
arms = ["left_*", "right_*"]
collisions = redik.CollisionAvoidanceLimit(
    [(["left_*"], ["right_*"]), (arms, ["head", "screen", "sonar_ring", "table"])],
    minimum_distance=0.01,
    detection_distance=0.1,
)
problem = redik.Problem(robot, tasks, [redik.ConfigurationLimit(), collisions])

result = redik.solve_problem(problem, robot.home)
print(result.summary())
for frame, T in targets.items():
    p_err, r_err = pose_errors(robot.fk(result.q, frame), T)
    print(f"  {frame}: position error {p_err:.1e} m, rotation error {r_err:.1e} rad")
distance, pair = collisions.minimum_distance_at(result.q)
print(f"closest geoms {pair}: {distance * 1000:.1f} mm apart ({len(collisions.pairs)} pairs)")
print("within joint limits:", robot.within_limits(result.q))

# Hands 10 cm apart: without the limit the forearms collide; with it they keep 1 cm and the
# grippers stop short of their targets (the limit outranks every task).
close = [
    redik.FrameTask(f"{side}_gripper", target=make_pose(down, [0.75, y, 0.0]), priority=0)
    for side, y in (("left", 0.05), ("right", -0.05))
]
for limits in ([redik.ConfigurationLimit()], [redik.ConfigurationLimit(), collisions]):
    stack = redik.Problem(robot, [*close, redik.PostureTask(priority=1)], limits)
    q = redik.solve_problem(stack, robot.home).q
    errors = [pose_errors(robot.fk(q, task.frame_name), task.target)[0] for task in close]
    closest = collisions.minimum_distance_at(q)[0]
    print(f"{len(limits) - 1} collision limit: closest {closest * 1000:+.1f} mm, ", end="")
    print(f"hand position errors {np.round(errors, 3)} m")

# The left arm alone, the right arm held where it is: compiled damped least squares.
left = robot.chain("left_gripper", result.q)
T = make_pose(np.eye(3), [0.0, 0.0, 0.1]) @ targets["left_gripper"]  # 10 cm higher
arm = redik.solve_pose(left, T, left.q_of(), seed=0)
print("left chain", left.joint_names, "->", arm.summary())
