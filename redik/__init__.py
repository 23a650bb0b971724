"""redik — optimisation-based, redundancy-resolving inverse kinematics on MuJoCo.

The names on ``redik`` itself are the entry points most code needs — one way to solve each
kind of problem, the tasks and limits they take, the results they return and the errors
they raise — listed with what each solves in the README's *Public API* section
(``tests/test_readme.py`` holds ``__all__`` to it). Everything else lives in its layer's
package (:mod:`redik.lie`, :mod:`redik.models`, :mod:`redik.kinematics`, :mod:`redik.tasks`,
:mod:`redik.limits`, :mod:`redik.qp`, :mod:`redik.solvers`, :mod:`redik.apps`…).

Conventions (frames, twist order, units) are in :mod:`redik.core.conventions`.
"""

import importlib as _importlib
import warnings as _warnings

from redik import (  # noqa: F401 (_compat: the old flat import paths)
    _compat,
    apps,
    core,
    criteria,
    kinematics,
    lie,
    limits,
    models,
    qp,
    solvers,
    tasks,
)
from redik.apps.trajectory import CartesianPath, JointTrajectory, follow_path
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
    TargetNotSet,
    TrackingWarning,
    UnknownFrame,
)
from redik.core.result import IKResult, Status
from redik.kinematics.robot import Robot, load
from redik.limits import (
    AccelerationLimit,
    BallJointLimit,
    CollisionAvoidanceLimit,
    PositionLimit,
    VelocityLimit,
)
from redik.models.scenes import list_scenes
from redik.solvers.batch import BatchResult, solve_batch
from redik.solvers.iterative import solve_equations
from redik.solvers.pose import solve_all, solve_pose
from redik.solvers.problem import Problem, QPResult
from redik.solvers.redundancy import SelfMotion, explore_self_motion, nullspace_velocity
from redik.tasks import (
    DampingTask,
    FrameTask,
    JointLimitAvoidanceTask,
    ManipulabilityTask,
    OrientationTask,
    PoseTask,
    PositionTask,
    PostureTask,
)

# Loaded with redik, as in the previous release, so that ``redik.solvers.analytic.ur(...)`` or
# ``redik.apps.workspace.sample(...)`` work after a bare ``import redik`` — without binding the
# module names on ``redik`` itself (they are not part of its API).
for _module in (
    "redik.apps.plot",
    "redik.apps.workspace",
    "redik.models.builder",
    "redik.models.dh",
    "redik.models.scene_library",
    "redik.solvers.analytic",
):
    _importlib.import_module(_module)
del _module

__version__ = "0.1.0"

__all__ = [
    "AccelerationLimit",
    "BackendError",
    "BallJointLimit",
    "BatchResult",
    "CartesianPath",
    "CollisionAvoidanceLimit",
    "DampingTask",
    "FrameTask",
    "IKResult",
    "InfeasibleProblem",
    "InvalidConfiguration",
    "InvalidInput",
    "InvalidPose",
    "InvalidRotation",
    "JointLimitAvoidanceTask",
    "JointTrajectory",
    "ManipulabilityTask",
    "ModelError",
    "ModelWarning",
    "NearRotationWarning",
    "OrientationTask",
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
    "Status",
    "TargetNotSet",
    "TrackingWarning",
    "UnknownFrame",
    "VelocityLimit",
    "apps",
    "core",
    "criteria",
    "explore_self_motion",
    "follow_path",
    "kinematics",
    "lie",
    "limits",
    "list_scenes",
    "load",
    "models",
    "nullspace_velocity",
    "qp",
    "solve_all",
    "solve_batch",
    "solve_equations",
    "solve_pose",
    "solvers",
    "tasks",
]

_MOVED = {
    # name on redik in the previous release: (module, attribute there or None for the module)
    "newton": ("redik.solvers.iterative", "newton_raphson"),
    "gradient": ("redik.solvers.iterative", "gradient_descent"),
    "hybrid": ("redik.solvers.iterative", "gradient_then_newton"),
    "finite_difference_jacobian": ("redik.solvers.iterative", "finite_difference_jacobian"),
    "Frame": ("redik.kinematics.robot", "Frame"),
    "PosePath": ("redik.apps.trajectory", "PosePath"),
    "CircularPath": ("redik.apps.trajectory", "CircularPath"),
    "MinkLimit": ("redik.limits", "MinkLimit"),
    "available_backends": ("redik.qp", "available_backends"),
    "make_backend": ("redik.qp", "make_backend"),
    "scene_path": ("redik.models", "scene_path"),
    "dh_to_mjcf": ("redik.models.builder", "dh_to_mjcf"),
    "read_dh": ("redik.models.builder", "read_dh"),
    "read_screws": ("redik.models.builder", "read_screws"),
    "screws_to_mjcf": ("redik.models.builder", "screws_to_mjcf"),
    "analytic": ("redik.solvers.analytic", None),
    "batch": ("redik.solvers.batch", None),
    "redundancy": ("redik.solvers.redundancy", None),
    "dh": ("redik.models.dh", None),
    "loading": ("redik.models.loading", None),
    "model_builder": ("redik.models.builder", None),
    "scene_library": ("redik.models.scene_library", None),
    "plot": ("redik.apps.plot", None),
    "trajectory": ("redik.apps.trajectory", None),
    "workspace": ("redik.apps.workspace", None),
}
"""Names the previous release had on ``redik``, kept for one release: each still works, with
a :class:`DeprecationWarning` naming its home."""


_METHODS = ("newton", "gradient", "hybrid")


def __getattr__(name: str) -> object:
    if name == "STATUSES":
        _warnings.warn(
            "redik.STATUSES is deprecated: use redik.Status (an enum of the same strings)",
            DeprecationWarning,
            stacklevel=2,
        )
        return tuple(status.value for status in Status)
    if name in _MOVED:
        module, attribute = _MOVED[name]
        home = module if attribute is None else f"{module}.{attribute}"
        hint = f" or redik.solve_equations(..., method={name!r})" if name in _METHODS else ""
        _warnings.warn(
            f"redik.{name} is deprecated and leaves redik's namespace in the next release: "
            f"use {home}{hint}",
            DeprecationWarning,
            stacklevel=2,
        )
        value = _importlib.import_module(module)
        return value if attribute is None else getattr(value, attribute)
    raise AttributeError(f"module 'redik' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
