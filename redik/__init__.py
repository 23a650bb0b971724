"""redik — optimisation-based, redundancy-resolving inverse kinematics on MuJoCo.

Conventions (frames, twist order, units) are in :mod:`redik.conventions`.
"""

from . import (
    analytic,
    batch,
    dh,
    lie,
    model_builder,
    plot,
    redundancy,
    scene_library,
    trajectory,
    workspace,
)
from .batch import BatchResult, solve_batch
from .exceptions import (
    BackendError,
    InfeasibleProblem,
    InvalidConfiguration,
    InvalidInput,
    InvalidPose,
    InvalidRotation,
    ModelError,
    RedikError,
    UnknownFrame,
)
from .iterative import finite_difference_jacobian, gradient, newton
from .model_builder import dh_to_mjcf, read_dh, read_screws, screws_to_mjcf
from .pose_ik import solve_all, solve_pose
from .redundancy import SelfMotion, explore_self_motion, nullspace_velocity
from .result import STATUSES, IKResult
from .robot import Frame, Robot
from .scenes import list_scenes, load, scene_path
from .trajectory import CartesianPath, CircularPath, JointTrajectory, follow_path

__version__ = "0.1.0"

__all__ = [
    "STATUSES",
    "BackendError",
    "BatchResult",
    "CartesianPath",
    "CircularPath",
    "Frame",
    "IKResult",
    "InfeasibleProblem",
    "InvalidConfiguration",
    "InvalidInput",
    "InvalidPose",
    "InvalidRotation",
    "JointTrajectory",
    "ModelError",
    "RedikError",
    "Robot",
    "SelfMotion",
    "UnknownFrame",
    "analytic",
    "batch",
    "dh",
    "dh_to_mjcf",
    "explore_self_motion",
    "finite_difference_jacobian",
    "follow_path",
    "gradient",
    "lie",
    "list_scenes",
    "load",
    "model_builder",
    "newton",
    "nullspace_velocity",
    "plot",
    "read_dh",
    "read_screws",
    "redundancy",
    "scene_library",
    "scene_path",
    "screws_to_mjcf",
    "solve_all",
    "solve_batch",
    "solve_pose",
    "trajectory",
    "workspace",
]
