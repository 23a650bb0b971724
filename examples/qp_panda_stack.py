"""A Panda reaches a pose while, strictly below it, staying clear of its joint limits.

Level 0: the end-effector pose. Level 1: joint-limit avoidance and a nominal posture,
optimised only in what level 0 leaves free. The position box keeps every iterate inside
the limits. Run: python examples/qp_panda_stack.py
"""

import numpy as np

import redik
from redik.limits import ConfigurationLimit, VelocityLimit
from redik.qp import Problem
from redik.tasks import FrameTask, JointLimitAvoidanceTask, PostureTask

robot = redik.load("panda")
rng = np.random.default_rng(7)
q_goal = robot.random_q(rng)
T_target = robot.fk(q_goal)

pose = FrameTask("ee", target=T_target)  # priority 0, on the end-effector site "ee"
stack = [pose, JointLimitAvoidanceTask(gain=0.2), PostureTask(gain=0.2)]  # priority 1
problem = Problem(robot, stack, backend="daqp")  # limits default: the position box

q0 = np.clip(q_goal + rng.uniform(-0.4, 0.4, robot.dof), robot.lower, robot.upper)
result = redik.solve_problem(problem, q0, redik.SolveOptions(pos_tol=1e-6, rot_tol=1e-5))
print(result.summary())
print("within limits:", robot.within_limits(result.q))
print("error per iteration:", np.array2string(result.error_history, precision=2))

# Online control at 100 Hz: one QP per tick, the step bounded by a velocity limit.
online = Problem(
    robot, [FrameTask("ee", target=T_target, gain=0.5)], [ConfigurationLimit(), VelocityLimit(2.0)]
)
q = q0.copy()
for _ in range(200):
    q += online.step(q, dt=0.01)
print("after 2 s at 100 Hz:", redik.lie.pose_errors(robot.fk(q), T_target))
