"""Baxter holds a box in both hands and carries it: the grip is a constraint held exactly.

The box is rigid, so the hands' relative pose must not change while it moves. Priority 0
holds the grip: a MuJoCo ``<weld>`` equality between the two grippers, added to the model
and held by ``redik.EqualityConstraintTask`` (or, without touching the model, by
``redik.RelativeFrameTask``: the right gripper's pose in the left one's). Priority 1 moves
the box (through the left gripper's pose); priority 2 is the posture. The box is lifted by
10 cm and turned by 20° about the vertical; at every waypoint the grip is held to round-off
while the box follows its path. Needs ``pip install "redik[models]"``.
Run: python examples/two_hands_hold_box.py
"""

import mujoco
import numpy as np

import redik
from redik.lie import inverse, make_pose, pose_errors, se3_log, so3_exp

spec = redik.models.loading.load_spec(redik.models.example_robot_data("baxter"), meshes=False)
weld = spec.add_equality(name="grip", type=mujoco.mjtEq.mjEQ_WELD)
weld.objtype = mujoco.mjtObj.mjOBJ_BODY
weld.name1, weld.name2 = "left_gripper", "right_gripper"
model = spec.compile()
robot = redik.Robot(model, joints=["left_[sew][0-9]", "right_[sew][0-9]"])

# Grasp: the grippers, pointing down, on the two ends of a 40 cm box.
down = np.diag([1.0, -1.0, -1.0])
T_box = make_pose(np.eye(3), [0.75, 0.0, 0.0])
left_in_box = make_pose(down, [0.0, 0.2, 0.0])
right_in_box = make_pose(down, [0.0, -0.2, 0.0])
grasp = [
    redik.FrameTask("left_gripper", target=T_box @ left_in_box),
    redik.FrameTask("right_gripper", target=T_box @ right_in_box),
    redik.PostureTask(priority=1),
]
result = redik.solve_problem(redik.Problem(robot, grasp), robot.home)
q = result.q
print("grasp:", result.summary())

# The weld's relative pose is the grasp's: the right gripper's origin and orientation in the
# left one's frame (MuJoCo's eq_data: anchor, relpos, relquat, torquescale).
T_grip = inverse(robot.fk(q, "left_gripper")) @ robot.fk(q, "right_gripper")
relquat = np.empty(4)
mujoco.mju_mat2Quat(relquat, T_grip[:3, :3].reshape(9))
grip = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, "grip")
model.eq_data[grip, :11] = [0.0, 0.0, 0.0, *T_grip[:3, 3], *relquat, 1.0]

holds = {
    "EqualityConstraintTask (the model's weld)": redik.EqualityConstraintTask(model, 1.0, ["grip"]),
    "RelativeFrameTask": redik.RelativeFrameTask(
        "right_gripper", "body", "left_gripper", "body", target=T_grip
    ),
}
for name, hold in holds.items():
    carry = redik.FrameTask("left_gripper", priority=1)
    problem = redik.Problem(robot, [hold, carry, redik.PostureTask(priority=2)])
    q_carry, worst_grip, worst_box = q, 0.0, 0.0
    for s in np.linspace(0.0, 1.0, 6):
        T_goal = make_pose(so3_exp(np.array([0.0, 0.0, np.radians(20.0) * s])), [0.0, 0.0, 0.1 * s])
        T_goal = T_goal @ T_box
        carry.set_target(T_goal @ left_in_box)
        result = redik.solve_problem(problem, q_carry)
        q_carry = result.q
        T_left, T_right = robot.fk(q_carry, "left_gripper"), robot.fk(q_carry, "right_gripper")
        slip = se3_log(inverse(T_grip) @ inverse(T_left) @ T_right)  # the grip's own error
        worst_grip = max(worst_grip, float(np.linalg.norm(slip)))
        worst_box = max(worst_box, pose_errors(T_left @ inverse(left_in_box), T_goal)[0])
    print(f"{name}: {result.status}; grip held to {worst_grip:.1e}, box {worst_box:.1e} m "
          f"from its path, within limits {robot.within_limits(q_carry)}")  # fmt: skip
