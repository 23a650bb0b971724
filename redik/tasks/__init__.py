"""Tasks: what the joint step should achieve, each a term of a QP objective.

The contract (error, Jacobian, weight, gain, priority, and mink's protocol) is in
:mod:`redik.tasks.task`; one task per module.
"""

from redik.tasks.damping_task import DampingTask
from redik.tasks.joint_limit_avoidance_task import JointLimitAvoidanceTask
from redik.tasks.kinematics import KinematicState
from redik.tasks.manipulability_task import ManipulabilityTask
from redik.tasks.orientation_task import OrientationTask
from redik.tasks.pose_task import PoseTask
from redik.tasks.position_task import PositionTask
from redik.tasks.posture_task import PostureTask
from redik.tasks.task import ResidualTask, Task

__all__ = [
    "DampingTask",
    "JointLimitAvoidanceTask",
    "KinematicState",
    "ManipulabilityTask",
    "OrientationTask",
    "PoseTask",
    "PositionTask",
    "PostureTask",
    "ResidualTask",
    "Task",
]
