"""redik — optimisation-based, redundancy-resolving inverse kinematics on MuJoCo.

Conventions (frames, twist order, units) are in :mod:`redik.conventions`.
"""

from redik import (
    analytic,
    batch,
    criteria,
    dh,
    lie,
    limits,
    loading,
    model_builder,
    models,
    plot,
    qp,
    redundancy,
    scene_library,
    tasks,
    trajectory,
    workspace,
)
from redik.batch import BatchResult, solve_batch
from redik.exceptions import (
    BackendError,
    InfeasibleProblem,
    InvalidConfiguration,
    InvalidInput,
    InvalidPose,
    InvalidRotation,
    ModelError,
    ModelWarning,
    NearRotationWarning,
    RedikError,
    RedikWarning,
    TrackingWarning,
    UnknownFrame,
)
from redik.iterative import finite_difference_jacobian, gradient, hybrid, newton
from redik.limits import (
    BallJointLimit,
    CollisionAvoidanceLimit,
    MinkLimit,
    PositionLimit,
    VelocityLimit,
)
from redik.model_builder import dh_to_mjcf, read_dh, read_screws, screws_to_mjcf
from redik.pose_ik import solve_all, solve_pose
from redik.problem import Problem, QPResult
from redik.qp import available_backends, make_backend
from redik.redundancy import SelfMotion, explore_self_motion, nullspace_velocity
from redik.result import STATUSES, IKResult
from redik.robot import Frame, Robot
from redik.scenes import list_scenes, load, scene_path
from redik.tasks import (
    DampingTask,
    JointLimitAvoidanceTask,
    ManipulabilityTask,
    OrientationTask,
    PoseTask,
    PositionTask,
    PostureTask,
)
from redik.trajectory import CartesianPath, CircularPath, JointTrajectory, PosePath, follow_path

__version__ = "0.1.0"

__all__ = [
    "STATUSES",
    "BackendError",
    "BallJointLimit",
    "BatchResult",
    "CartesianPath",
    "CircularPath",
    "CollisionAvoidanceLimit",
    "DampingTask",
    "Frame",
    "IKResult",
    "InfeasibleProblem",
    "InvalidConfiguration",
    "InvalidInput",
    "InvalidPose",
    "InvalidRotation",
    "JointLimitAvoidanceTask",
    "JointTrajectory",
    "ManipulabilityTask",
    "MinkLimit",
    "ModelError",
    "ModelWarning",
    "NearRotationWarning",
    "OrientationTask",
    "PosePath",
    "PoseTask",
    "PositionLimit",
    "PositionTask",
    "PostureTask",
    "Problem",
    "QPResult",
    "RedikError",
    "RedikWarning",
    "Robot",
    "SelfMotion",
    "TrackingWarning",
    "UnknownFrame",
    "VelocityLimit",
    "analytic",
    "available_backends",
    "batch",
    "criteria",
    "dh",
    "dh_to_mjcf",
    "explore_self_motion",
    "finite_difference_jacobian",
    "follow_path",
    "gradient",
    "hybrid",
    "lie",
    "limits",
    "list_scenes",
    "load",
    "loading",
    "make_backend",
    "model_builder",
    "models",
    "newton",
    "nullspace_velocity",
    "plot",
    "qp",
    "read_dh",
    "read_screws",
    "redundancy",
    "scene_library",
    "scene_path",
    "screws_to_mjcf",
    "solve_all",
    "solve_batch",
    "solve_pose",
    "tasks",
    "trajectory",
    "workspace",
]
