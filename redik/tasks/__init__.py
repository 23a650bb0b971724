"""Tasks: what the joint step should achieve, each a term of a QP objective.

The contract (error, Jacobian, cost, gain, priority, and mink's protocol) is in
:mod:`redik.tasks.task`; one task per module. :class:`FrameTask` is the pose task, with
mink's name and signature; :class:`SingleFrameTask` is the base class of the tasks on one
frame's target (:class:`FrameTask`, :class:`PositionTask`, :class:`OrientationTask`).
:class:`RelativeFrameTask` (a frame's pose in another frame) and
:class:`EqualityConstraintTask` (a model's connect and weld constraints) hold two frames
together, as mink's tasks of those names do.
"""

from redik.tasks.damping_task import DampingTask
from redik.tasks.equality_constraint_task import EqualityConstraintTask
from redik.tasks.frame_task import FrameTask
from redik.tasks.joint_limit_avoidance_task import JointLimitAvoidanceTask
from redik.tasks.kinematics import KinematicState
from redik.tasks.manipulability_task import ManipulabilityTask
from redik.tasks.orientation_task import OrientationTask
from redik.tasks.position_task import PositionTask
from redik.tasks.posture_task import PostureTask
from redik.tasks.relative_frame_task import RelativeFrameTask
from redik.tasks.single_frame_task import SingleFrameTask
from redik.tasks.task import ResidualTask, Task

__all__ = [
    "DampingTask",
    "EqualityConstraintTask",
    "FrameTask",
    "JointLimitAvoidanceTask",
    "KinematicState",
    "ManipulabilityTask",
    "OrientationTask",
    "PositionTask",
    "PostureTask",
    "RelativeFrameTask",
    "ResidualTask",
    "SingleFrameTask",
    "Task",
]
