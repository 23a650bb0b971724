"""redik — optimisation-based, redundancy-resolving inverse kinematics on MuJoCo.

The names on ``redik`` itself are the entry points most code needs — one way to solve each
kind of problem, the tasks and limits they take, the results they return and the errors
they raise — listed with what each solves in the guides' *Public API* section
(``docs/guides/index.md``; ``tests/test_docs.py`` holds ``__all__`` to it). Everything else
lives in its layer's package (:mod:`redik.lie`, :mod:`redik.models`, :mod:`redik.kinematics`,
:mod:`redik.tasks`, :mod:`redik.limits`, :mod:`redik.qp`, :mod:`redik.solvers`,
:mod:`redik.apps`…).

Conventions (frames, twist order, units) are in :mod:`redik.core.conventions`.

``import redik`` loads the layers up to the kinematics (errors, conventions, group math, models,
:class:`Robot`); the task stack, the solvers and the applications are imported on first use of
one of their names (``redik.solve_pose``, ``redik.FrameTask``, ``redik.solvers.analytic``…), so a
script pays only for what it uses (:mod:`redik.core.lazy`).
"""

import importlib as _importlib
from typing import TYPE_CHECKING as _TYPE_CHECKING
from typing import Any as _Any

from redik import core, kinematics, lie, models
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
    TaskError,
    TrackingWarning,
    UnknownFrame,
)
from redik.core.lazy import lazy_submodules as _lazy_submodules
from redik.core.result import IKResult, Status
from redik.kinematics.robot import Robot, load
from redik.models.scenes import list_scenes

_ENTRY_POINTS = {
    "redik.apps.trajectory": ("CartesianPath", "JointTrajectory", "follow_path"),
    "redik.limits": (
        "AccelerationLimit",
        "BallJointLimit",
        "CollisionAvoidanceLimit",
        "ConfigurationLimit",
        "VelocityLimit",
    ),
    "redik.qp.problem": ("Problem",),
    "redik.solvers.batch": ("BatchResult", "solve_batch"),
    "redik.solvers.iterative": ("solve_equations",),
    "redik.solvers.pose": ("solve_all", "solve_pose"),
    "redik.solvers.redundancy": ("SelfMotion", "explore_self_motion", "nullspace_velocity"),
    "redik.solvers.task_stack": ("QPResult", "SolveOptions", "solve_problem"),
    "redik.tasks": (
        "DampingTask",
        "EqualityConstraintTask",
        "FrameTask",
        "JointLimitAvoidanceTask",
        "ManipulabilityTask",
        "OrientationTask",
        "PositionTask",
        "PostureTask",
        "RelativeFrameTask",
    ),
}
"""The public names of the layers above the kinematics, by the module each is imported from
on first use."""

if _TYPE_CHECKING:  # the same names, for type checkers and editors, which run no __getattr__
    from redik import apps, criteria, limits, qp, solvers, tasks
    from redik.apps.trajectory import CartesianPath, JointTrajectory, follow_path
    from redik.limits import (
        AccelerationLimit,
        BallJointLimit,
        CollisionAvoidanceLimit,
        ConfigurationLimit,
        VelocityLimit,
    )
    from redik.qp.problem import Problem
    from redik.solvers.batch import BatchResult, solve_batch
    from redik.solvers.iterative import solve_equations
    from redik.solvers.pose import solve_all, solve_pose
    from redik.solvers.redundancy import SelfMotion, explore_self_motion, nullspace_velocity
    from redik.solvers.task_stack import QPResult, SolveOptions, solve_problem
    from redik.tasks import (
        DampingTask,
        EqualityConstraintTask,
        FrameTask,
        JointLimitAvoidanceTask,
        ManipulabilityTask,
        OrientationTask,
        PositionTask,
        PostureTask,
        RelativeFrameTask,
    )

_MODULE_OF = {name: module for module, names in _ENTRY_POINTS.items() for name in names}
_subpackage = _lazy_submodules(__name__)


def __getattr__(name: str) -> _Any:
    """Import a public name's module, or a subpackage (``redik.solvers``), on first use."""
    module = _MODULE_OF.get(name)
    value = _subpackage(name) if module is None else getattr(_importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})


__version__ = "0.1.0"

__all__ = [
    "AccelerationLimit",
    "BackendError",
    "BallJointLimit",
    "BatchResult",
    "CartesianPath",
    "CollisionAvoidanceLimit",
    "ConfigurationLimit",
    "DampingTask",
    "EqualityConstraintTask",
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
    "PositionTask",
    "PostureTask",
    "Problem",
    "QPResult",
    "RedikError",
    "RedikWarning",
    "RelativeFrameTask",
    "Robot",
    "SelfMotion",
    "SolveOptions",
    "Status",
    "TargetNotSet",
    "TaskError",
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
    "solve_problem",
    "solvers",
    "tasks",
]
