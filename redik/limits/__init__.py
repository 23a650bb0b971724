"""Limits: hard inequalities on the joint step. The contract is in :mod:`redik.limits.limit`."""

from .ball_joint_limit import BallJointLimit
from .collision_avoidance_limit import CollisionAvoidanceLimit
from .limit import BoxLimit, InequalityLimit, Limit
from .mink_limit import MinkLimit
from .position_limit import PositionLimit
from .velocity_limit import VelocityLimit

__all__ = [
    "BallJointLimit",
    "BoxLimit",
    "CollisionAvoidanceLimit",
    "InequalityLimit",
    "Limit",
    "MinkLimit",
    "PositionLimit",
    "VelocityLimit",
]
