"""redik — optimisation-based, redundancy-resolving inverse kinematics on MuJoCo.

Conventions (frames, twist order, units) are in :mod:`redik.core.conventions`.
"""

from redik import _compat, criteria, lie, limits, models, qp, tasks  # noqa: F401 (_compat: old paths)
from redik.apps import plot, trajectory, workspace
from redik.apps.trajectory import (
    CartesianPath,
    CircularPath,
    JointTrajectory,
    PosePath,
    follow_path,
)
from redik.core.exceptions import (
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
from redik.core.result import STATUSES, IKResult
from redik.kinematics.robot import Frame, Robot, load
from redik.limits import (
    BallJointLimit,
    CollisionAvoidanceLimit,
    MinkLimit,
    PositionLimit,
    VelocityLimit,
)
from redik.models import builder as model_builder
from redik.models import dh, loading, scene_library
from redik.models.builder import dh_to_mjcf, read_dh, read_screws, screws_to_mjcf
from redik.models.scenes import list_scenes, scene_path
from redik.qp import available_backends, make_backend
from redik.solvers import analytic, batch, redundancy
from redik.solvers.batch import BatchResult, solve_batch
from redik.solvers.iterative import finite_difference_jacobian, gradient, hybrid, newton
from redik.solvers.pose import solve_all, solve_pose
from redik.solvers.problem import Problem, QPResult
from redik.solvers.redundancy import SelfMotion, explore_self_motion, nullspace_velocity
from redik.tasks import (
    DampingTask,
    JointLimitAvoidanceTask,
    ManipulabilityTask,
    OrientationTask,
    PoseTask,
    PositionTask,
    PostureTask,
)

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
