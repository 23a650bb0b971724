"""A Panda reaches a pose and, strictly below it, gets as close as it can to a nominal posture.

``redik.solve_problem`` keeps iterating after the pose converges until the posture level is
stationary: its gradient, projected onto what the pose and the active limits leave free,
vanishes. The result is the constrained optimum, min ½‖q − q_nom‖² s.t. pose(q) = T,
which stopping at pose convergence is not. Run: python examples/qp_lower_level_optimum.py
"""

import numpy as np

import redik
from redik.qp import Problem
from redik.tasks import FrameTask, PostureTask

robot = redik.load("panda")
rng = np.random.default_rng(3)
q0 = np.clip(robot.random_q(rng), robot.lower + 0.3, robot.upper - 0.3)
T_target = robot.fk(np.clip(q0 + rng.uniform(-0.3, 0.3, robot.dof), robot.lower, robot.upper))
q_nominal = np.clip(q0 + rng.uniform(-0.5, 0.5, robot.dof), robot.lower, robot.upper)

problem = Problem(
    robot, [FrameTask("ee", target=T_target), PostureTask(q_nominal, gain=0.2, priority=1)]
)


def posture_cost(q: np.ndarray) -> float:
    return 0.5 * float(np.sum((q - q_nominal) ** 2))


# Stop when the pose converges ... and finish the posture level.
early = redik.solve_problem(problem, q0, redik.SolveOptions(stationarity_tol=None))
result = redik.solve_problem(problem, q0)
for name, r in (("stop at pose convergence", early), ("finish the lower level", result)):
    stationarity = problem.stationarity(r.q)[0]
    print(
        f"{name:<26} {r.summary()}; posture cost {posture_cost(r.q):.6f}, "
        f"projected gradient {stationarity:.1e}"
    )
print("stationary:", result.stationary, "within limits:", robot.within_limits(result.q))
