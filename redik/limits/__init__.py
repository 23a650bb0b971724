"""Limits: hard inequalities on the joint step. The contract is in :mod:`redik.limits.limit`."""

from redik.limits.acceleration_limit import AccelerationLimit
from redik.limits.ball_joint_limit import BallJointLimit
from redik.limits.collision_avoidance_limit import CollisionAvoidanceLimit
from redik.limits.configuration_limit import ConfigurationLimit
from redik.limits.limit import BoxLimit, InequalityLimit, Limit
from redik.limits.mink_limit import MinkLimit
from redik.limits.velocity_limit import VelocityLimit

__all__ = [
    "AccelerationLimit",
    "BallJointLimit",
    "BoxLimit",
    "CollisionAvoidanceLimit",
    "ConfigurationLimit",
    "InequalityLimit",
    "Limit",
    "MinkLimit",
    "VelocityLimit",
]
