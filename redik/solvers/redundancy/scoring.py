r"""Scoring objects for the secondary criteria.

What makes one point of a self-motion manifold better than another.

The math (values and gradients) is in :mod:`redik.criteria`; this module wraps it into
scoring objects over a robot's samples.

A criterion has a ``value`` at a configuration, a sense (``maximize``), and an ``ascent``
direction ``q̇₀`` that improves it locally — the velocity fed to the null space in
:func:`redik.solvers.redundancy.nullspace_velocity` and
:func:`redik.solvers.redundancy.gradient_projection_ik`.
:func:`evaluate_criteria` scores every sample of a :class:`redik.solvers.redundancy.SelfMotion`.

Each method receives the ``"world"`` Jacobian ``J`` at ``q`` (see :mod:`redik.core.conventions`)
because the caller has just computed it.
"""

from __future__ import annotations

import abc
import dataclasses
from typing import TYPE_CHECKING

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.criteria import (
    joint_limit_margin,
    joint_limit_margin_gradient,
    manipulability,
    manipulability_gradient,
    posture_distance,
    posture_gradient,
)
from redik.kinematics.batched import jacobian
from redik.kinematics.chain import Chain

if TYPE_CHECKING:
    from redik.kinematics.robot import Frame, Robot


class Criterion(abc.ABC):
    """A scalar score of a configuration, with a direction that improves it.

    Attributes:
        name: The key under which samples are scored (``SelfMotion.criteria[name]``).
        maximize: True when larger values are better.
    """

    name: str
    maximize: bool

    @abc.abstractmethod
    def value(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> float:
        """The criterion at ``q`` (``J``: world Jacobian at ``q``)."""

    @abc.abstractmethod
    def ascent(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> np.ndarray:
        """A joint velocity ``q̇₀`` along which the criterion improves (to first order)."""

    def values(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> np.ndarray:
        """:meth:`value` at every row of ``q`` (N × n; ``J``: N × 6 × n).

        Subclasses may vectorise it; this default calls :meth:`value` row by row.
        """
        return np.array([self.value(robot, x, Jx) for x, Jx in zip(q, J, strict=True)])


@dataclasses.dataclass(frozen=True)
class JointLimitMargin(Criterion):
    """Distance to the nearest joint limit (rad or m), to maximise.

    The ascent is the gradient of a soft minimum of the limit distances
    (:func:`redik.criteria.joint_limit_margin_gradient`).
    """

    name: str = "joint_limit_margin"
    maximize: bool = True
    temperature: float = 0.05

    def value(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> float:
        """:func:`redik.criteria.joint_limit_margin` at ``q``."""
        return float(joint_limit_margin(q, robot.lower, robot.upper))

    def values(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> np.ndarray:
        """:func:`redik.criteria.joint_limit_margin` at every row of ``q``."""
        return np.asarray(joint_limit_margin(q, robot.lower, robot.upper))

    def ascent(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> np.ndarray:
        """:func:`redik.criteria.joint_limit_margin_gradient` at ``q``."""
        return joint_limit_margin_gradient(q, robot.lower, robot.upper, self.temperature)


@dataclasses.dataclass(frozen=True)
class Manipulability(Criterion):
    """Yoshikawa's ``√det(JJᵀ)``, to maximise; the ascent is its analytic gradient."""

    name: str = "manipulability"
    maximize: bool = True

    def value(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> float:
        """:func:`redik.criteria.manipulability` of ``J``."""
        return float(manipulability(J))

    def values(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> np.ndarray:
        """:func:`redik.criteria.manipulability` of every Jacobian of ``J``."""
        return np.asarray(manipulability(J))

    def ascent(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> np.ndarray:
        """:func:`redik.criteria.manipulability_gradient` of ``J``."""
        return manipulability_gradient(J)


@dataclasses.dataclass(frozen=True, eq=False)
class PostureDistance(Criterion):
    """``‖q − q_nominal‖`` (periodic hinges modulo 2π), to minimise; ascent ``−(q − q_nom)``."""

    nominal: np.ndarray
    name: str = "posture_distance"
    maximize: bool = False

    def value(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> float:
        """:func:`redik.criteria.posture_distance` of ``q``."""
        return float(posture_distance(q, self.nominal, robot.periodic))

    def values(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> np.ndarray:
        """:func:`redik.criteria.posture_distance` of every row of ``q``."""
        return np.asarray(posture_distance(q, self.nominal, robot.periodic))

    def ascent(self, robot: Robot, q: np.ndarray, J: np.ndarray) -> np.ndarray:
        """:func:`redik.criteria.posture_gradient` at ``q``."""
        return posture_gradient(q, self.nominal, robot.periodic)


def default_criteria(robot: Robot, nominal: np.ndarray | None = None) -> tuple[Criterion, ...]:
    """Joint-limit margin, manipulability and distance to ``nominal`` (default ``robot.home``)."""
    nominal = robot.home if nominal is None else robot.check_q(nominal, "nominal")
    return (JointLimitMargin(), Manipulability(), PostureDistance(np.array(nominal)))


def criterion_by_name(robot: Robot, name: str, nominal: np.ndarray | None = None) -> Criterion:
    """One of :func:`default_criteria` by its name."""
    for criterion in default_criteria(robot, nominal):
        if criterion.name == name:
            return criterion
    names = [c.name for c in default_criteria(robot, nominal)]
    raise InvalidInput(f"unknown criterion {name!r}; expected one of {names}")


def evaluate_criteria(
    robot: Robot,
    samples: np.ndarray,
    criteria: tuple[Criterion, ...],
    frame: Frame,
) -> dict[str, np.ndarray]:
    """Every criterion at every row of ``samples`` (N × n): a dict of length-N arrays.

    The world Jacobians come from :mod:`redik.solvers.batch`'s vectorised kinematics when ``frame``
    is the end-effector, else from MuJoCo one sample at a time.
    """
    samples = np.asarray(samples, dtype=float).reshape(-1, robot.dof)
    if frame == robot.ee and len(samples):
        J = jacobian(Chain.from_robot(robot), samples, reference="world")
    else:
        J = np.empty((len(samples), 6, robot.dof))
        T = np.eye(4)
        for k, q in enumerate(samples):
            robot.state.kinematics(q, frame, T, J[k])
    return {c.name: np.asarray(c.values(robot, samples, J), dtype=float) for c in criteria}
