"""Tasks: what the joint step should achieve, each a term of a QP objective.

The contract (error, Jacobian, cost, gain, priority, and mink's protocol) is in
:mod:`redik.tasks.task`; one task per module. :class:`FrameTask` is the pose task, with
mink's name and signature; :class:`SingleFrameTask` is the base class of the tasks on one
frame's target (:class:`FrameTask`, :class:`PositionTask`, :class:`OrientationTask`).
"""

from redik.tasks.damping_task import DampingTask
from redik.tasks.frame_task import FrameTask
from redik.tasks.joint_limit_avoidance_task import JointLimitAvoidanceTask
from redik.tasks.kinematics import KinematicState
from redik.tasks.manipulability_task import ManipulabilityTask
from redik.tasks.orientation_task import OrientationTask
from redik.tasks.position_task import PositionTask
from redik.tasks.posture_task import PostureTask
from redik.tasks.single_frame_task import SingleFrameTask
from redik.tasks.task import ResidualTask, Task

__all__ = [
    "DampingTask",
    "FrameTask",
    "JointLimitAvoidanceTask",
    "KinematicState",
    "ManipulabilityTask",
    "OrientationTask",
    "PositionTask",
    "PostureTask",
    "ResidualTask",
    "SingleFrameTask",
    "Task",
]
