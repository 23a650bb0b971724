"""Every Panda configuration that reaches one pose, and the best of them.

Explores the self-motion manifold of a pose (curves cut by the joint limits), picks the
sample closest to the home posture and the one with the largest manipulability, and
compares them with what a local optimiser finds from the same start: the QP core
(FrameTask at priority 0, PostureTask at priority 1) and the gradient projection method.
Writes the manifold plot and an animation of the arm moving with its hand held still to
$REDIK_OUT (default: the current directory).

Run: MUJOCO_GL=egl python examples/selfmotion_panda.py
"""

import os
from pathlib import Path

import numpy as np

import redik
from redik.apps.render import render_frames, save_gif
from redik.apps.selfmotion_plot import plot_joint_pairs
from redik.qp import Problem
from redik.solvers.redundancy import Manipulability, PostureDistance, explore_self_motion
from redik.tasks import FrameTask
from redik.tasks.posture_task import PostureTask

out = Path(os.environ.get("REDIK_OUT", "."))
robot = redik.load("panda")
q_start = np.array([0.6, 0.3, -0.4, -1.9, 0.5, 2.0, -0.3])
T = robot.fk(q_start)

motion = explore_self_motion(robot, T, seed=0, initial=q_start)
print(
    f"{len(motion)} samples in {motion.n_components} arcs ({motion.elapsed:.2f} s); "
    f"max errors {motion.position_error.max():.1e} m, {motion.rotation_error.max():.1e} rad"
)
for k in range(motion.n_components):
    print(f"  arc {k}: {np.sum(motion.component == k)} samples, ends {motion.ends[k]}")


def value(criterion, q):
    return criterion.value(robot, q, robot.jacobian(q, reference="world"))


# Distance to home: the best sample of the manifold versus the QP's local optimum.
posture = PostureDistance(robot.home)
problem = Problem(
    robot, [FrameTask("ee", target=T, priority=0), PostureTask(robot.home, priority=1)]
)
q_qp = q_start.copy()
for _ in range(200):  # the posture level keeps acting after the pose is met
    q_qp = q_qp + problem.step(q_qp)
gp_posture = redik.solvers.redundancy.gradient_projection_ik(robot, T, q_start, posture)
print("distance to home [rad]:")
print(f"  start                       {value(posture, q_start):.4f}")
print(f"  QP (PostureTask, level 1)   {value(posture, q_qp):.4f}")
print(f"  gradient projection         {value(posture, gp_posture.q):.4f}")
print(f"  best of the manifold        {motion.criteria['posture_distance'].min():.4f}")

manipulability = Manipulability()
gp_manip = redik.solvers.redundancy.gradient_projection_ik(robot, T, q_start, manipulability)
print("manipulability √det(JJᵀ):")
print(f"  start                       {value(manipulability, q_start):.4f}")
print(f"  gradient projection         {value(manipulability, gp_manip.q):.4f}")
print(f"  best of the manifold        {motion.criteria['manipulability'].max():.4f}")
print("best posture:", np.round(motion.best("posture_distance"), 3))

plot_joint_pairs(motion, "posture_distance", lower=robot.lower, upper=robot.upper,
                 path=out / "selfmotion_panda.png")  # fmt: skip
path = motion.walk(motion.component[motion.best_index("posture_distance")])
picks = path[np.linspace(0, len(path) - 1, 24).round().astype(int)]
frames = render_frames(robot, motion.samples[picks], 320, 240, target=T)
save_gif(out / "selfmotion_panda.gif", frames, fps=12)
print(f"wrote {out / 'selfmotion_panda.png'} and {out / 'selfmotion_panda.gif'}")
