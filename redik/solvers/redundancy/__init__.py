"""Redundancy resolution: null-space projection and the self-motion manifold of a pose.

* :mod:`.nullspace` — ``q̇ = J⁺ẋ + (I − J⁺J) q̇₀``, the pseudo-inverse, projector and basis.
* :mod:`.corrector` — Newton projection of configurations onto a pose (IKinBody).
* :mod:`.gradient_projection` — :func:`gradient_projection_ik` climbs a criterion while
  holding a pose.
* :mod:`.scoring` — joint-limit margin, manipulability, distance to a nominal posture as
  scoring objects; their math (re-exported here) is :mod:`redik.criteria`.
* :mod:`.selfmotion` — :func:`explore_self_motion` samples every configuration reaching a
  pose (curves for 7R arms, surfaces for 8R arms, points for 6R arms) into a
  :class:`SelfMotion`.
* :mod:`redik.apps.selfmotion_plot` — the manifold in joint space as matplotlib figures.
"""

from redik.criteria import (
    jacobian_derivatives,
    joint_limit_distance,
    joint_limit_distance_gradient,
    joint_limit_margin,
    joint_limit_margin_gradient,
    manipulability,
    manipulability_gradient,
    posture_gradient,
)
from redik.solvers.redundancy.gradient_projection import gradient_projection_ik
from redik.solvers.redundancy.nullspace import (
    nullspace_basis,
    nullspace_projector,
    nullspace_velocity,
    pseudo_inverse,
)
from redik.solvers.redundancy.scoring import (
    Criterion,
    JointLimitMargin,
    Manipulability,
    PostureDistance,
    criterion_by_name,
    default_criteria,
    evaluate_criteria,
)
from redik.solvers.redundancy.selfmotion import SelfMotion, explore_self_motion

__all__ = [
    "Criterion",
    "JointLimitMargin",
    "Manipulability",
    "PostureDistance",
    "SelfMotion",
    "criterion_by_name",
    "default_criteria",
    "evaluate_criteria",
    "explore_self_motion",
    "gradient_projection_ik",
    "jacobian_derivatives",
    "joint_limit_distance",
    "joint_limit_distance_gradient",
    "joint_limit_margin",
    "joint_limit_margin_gradient",
    "manipulability",
    "manipulability_gradient",
    "nullspace_basis",
    "nullspace_projector",
    "nullspace_velocity",
    "posture_gradient",
    "pseudo_inverse",
]
