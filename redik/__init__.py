"""redik — optimisation-based, redundancy-resolving inverse kinematics on MuJoCo.

Conventions (frames, twist order, units) are in :mod:`redik.conventions`.
"""

from . import lie
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
from .robot import Frame, Robot
from .scenes import list_scenes, load, scene_path

__version__ = "0.1.0"

__all__ = [
    "BackendError",
    "Frame",
    "InfeasibleProblem",
    "InvalidConfiguration",
    "InvalidInput",
    "InvalidPose",
    "InvalidRotation",
    "ModelError",
    "RedikError",
    "Robot",
    "UnknownFrame",
    "lie",
    "list_scenes",
    "load",
    "scene_path",
]
