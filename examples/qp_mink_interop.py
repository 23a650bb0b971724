"""redik and mink tasks in one problem, and a redik task inside mink.solve_ik.

Run: python examples/qp_mink_interop.py
"""

import mink
import numpy as np

import redik
from redik.qp import Problem
from redik.tasks import FrameTask, JointLimitAvoidanceTask

robot = redik.load("panda")
T_target = robot.fk(robot.random_q(np.random.default_rng(4)))

# A mink FrameTask at priority 0 (mink tasks have none) and a redik task below it.
frame = mink.FrameTask("ee", "site", position_cost=1.0, orientation_cost=1.0)
frame.set_target(mink.SE3.from_matrix(T_target))
problem = Problem(robot, [frame, JointLimitAvoidanceTask(priority=1)])
print("redik Problem with a mink task:", redik.solve_problem(problem, robot.home).summary())

# The other way round: a redik task, bound to the robot, inside mink.solve_ik.
configuration = mink.Configuration(robot.model, robot.full_qpos(robot.home))
# Weighted, as mink sums everything: the small limit term biases the pose by ~1e-6.
tasks = [
    FrameTask("ee", target=T_target).bind(robot),
    JointLimitAvoidanceTask(cost=1e-3).bind(robot),
]
limits = [mink.ConfigurationLimit(robot.model)]
for _ in range(200):
    velocity = mink.solve_ik(configuration, tasks, 1.0, "daqp", damping=1e-6, limits=limits)
    configuration.integrate_inplace(velocity, 1.0)
q = configuration.q[robot.qpos_indices]
print("mink.solve_ik with redik tasks:", redik.lie.pose_errors(robot.fk(q), T_target))

# redik.FrameTask is mink's FrameTask: the same arguments, the same error and Jacobian, and
# mink's lm_damping (λ‖α W e‖² added to the Hessian, damping the step towards a target out of
# reach). Out of reach, the damped step stays short where the undamped one is long.
far = T_target.copy()
far[:3, 3] *= 3.0
for lm_damping in (0.0, 1.0):
    task = redik.FrameTask("ee", "site", position_cost=1.0, orientation_cost=1.0,
                           lm_damping=lm_damping)  # fmt: skip
    task.set_target(mink.SE3.from_matrix(far))
    step = Problem(robot, [task], limits=[]).step(robot.home)
    print(f"redik.FrameTask lm_damping={lm_damping}: |Δq| = {np.linalg.norm(step):.3f} rad")
