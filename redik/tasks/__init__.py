"""Tasks: what the joint step should achieve, each a term of a QP objective.

The contract (error, Jacobian, weight, gain, priority, and mink's protocol) is in
:mod:`redik.tasks.task`; one task per module.
"""

from .damping_task import DampingTask
from .joint_limit_avoidance_task import JointLimitAvoidanceTask
from .kinematics import KinematicState
from .manipulability_task import ManipulabilityTask
from .orientation_task import OrientationTask
from .pose_task import PoseTask
from .position_task import PositionTask
from .posture_task import PostureTask
from .task import ResidualTask, Task

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
