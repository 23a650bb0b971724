"""redik — optimisation-based, redundancy-resolving inverse kinematics on MuJoCo.

Conventions (frames, twist order, units) are in :mod:`redik.conventions`.
"""

from . import analytic, dh, lie, model_builder, scene_library
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
from .model_builder import dh_to_mjcf, read_dh, read_screws, screws_to_mjcf
from .result import STATUSES, IKResult
from .robot import Frame, Robot
from .scenes import list_scenes, load, scene_path

__version__ = "0.1.0"

__all__ = [
    "STATUSES",
    "BackendError",
    "Frame",
    "IKResult",
    "InfeasibleProblem",
    "InvalidConfiguration",
    "InvalidInput",
    "InvalidPose",
    "InvalidRotation",
    "ModelError",
    "RedikError",
    "Robot",
    "UnknownFrame",
    "analytic",
    "dh",
    "dh_to_mjcf",
    "lie",
    "list_scenes",
    "load",
    "model_builder",
    "read_dh",
    "read_screws",
    "scene_library",
    "scene_path",
    "screws_to_mjcf",
]
