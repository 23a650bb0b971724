"""redik — optimisation-based, redundancy-resolving inverse kinematics on MuJoCo.

The names on ``redik`` itself are the entry points most code needs — one way to solve each
kind of problem, the tasks and limits they take, the results they return and the errors
they raise — listed with what each solves in the guides' *Public API* section
(``docs/guides/index.md``; ``tests/test_docs.py`` holds ``__all__`` to it). Everything else
lives in its layer's package (:mod:`redik.lie`, :mod:`redik.models`, :mod:`redik.kinematics`,
:mod:`redik.tasks`, :mod:`redik.limits`, :mod:`redik.qp`, :mod:`redik.solvers`,
:mod:`redik.apps`…).

Conventions (frames, twist order, units) are in :mod:`redik.core.conventions`.
"""

import importlib as _importlib

from redik import (
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
    TaskError,
    TrackingWarning,
    UnknownFrame,
)
from redik.core.result import IKResult, Status
from redik.kinematics.robot import Robot, load
from redik.limits import (
    AccelerationLimit,
    BallJointLimit,
    CollisionAvoidanceLimit,
    ConfigurationLimit,
    VelocityLimit,
)
from redik.models.scenes import list_scenes
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

# Loaded with redik so that ``redik.solvers.analytic.ur(...)`` or
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
