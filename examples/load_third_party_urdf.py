"""Load third-party URDFs from the package index and solve a pose on them.

example-robot-data's UR5 (meshes named ``package://example-robot-data/...``) and pybullet's
KUKA LBR iiwa (meshes relative to the URDF). Fixed links such as the UR5's ``tool0`` flange
stay frames, so they can be the end-effector. Needs the "models" extra:
pip install "redik[models]".

Run: python examples/load_third_party_urdf.py
"""

import time

import numpy as np

import redik

for package_name, end_effector in (("example-robot-data:ur5", "tool0"),
                                   ("pybullet_data:kuka_iiwa", "lbr_iiwa_link_7")):  # fmt: skip
    path = redik.models.scene_path(package_name)  # = redik.models.example_robot_data("ur5"), …
    start = time.perf_counter()
    robot = redik.load(path, ee=end_effector)  # meshes resolved and loaded
    loaded_in = time.perf_counter() - start
    kinematic = redik.load(path, ee=end_effector, meshes=False)  # no mesh file needed
    print(f"{package_name}: {path.name}, {robot.dof} joints {list(robot.joint_names)}")
    print(f"  {robot.model.nmesh} meshes, loaded in {loaded_in * 1e3:.0f} ms "
          f"({kinematic.model.nmesh} meshes with meshes=False)")  # fmt: skip
    print("  frames (bodies):", ", ".join(robot.frame_names("body")))

    q_goal = robot.random_q(np.random.default_rng(1))
    T_target = robot.fk(q_goal)
    result = redik.solve_pose(robot, T_target, seed=0)
    position_error, rotation_error = redik.lie.pose_errors(robot.fk(result.q), T_target)
    print(f"  solve_pose to {end_effector}: {result.summary()}")
    print(f"  checked by FK: {position_error:.1e} m, {rotation_error:.1e} rad")
    # The meshes change no kinematics: the kinematics-only model reaches the same pose.
    np.testing.assert_allclose(kinematic.fk(result.q), robot.fk(result.q), atol=1e-12)

try:
    redik.load(redik.models.example_robot_data("ur5"), ee="tool_0")
except redik.UnknownFrame as error:
    print("a wrong frame name:", str(error).split("; sites")[0])
