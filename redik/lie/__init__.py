"""Group math: rotations SO(3), rigid transforms SE(3), angles, and pose-error metrics.

* :mod:`~redik.lie.so3` — skew matrices, exp and log (one rotation, or a batch), quaternion
  conversions, the inverse left Jacobian, SLERP;
* :mod:`~redik.lie.se3` — poses, inverse, adjoint, Jacobian references, exp and log, the
  inverse left Jacobian, pose interpolation;
* :mod:`~redik.lie.angles` — wrapping angles, periodic joints, Euler angles;
* :mod:`~redik.lie.metrics` — the errors a solver reports and the course's orientation metrics.

Twist order ``(v, ω)``, scalar-first quaternions and ``T_ab`` are those of
:mod:`redik.core.conventions`. The maps take validated float input unchecked, like MuJoCo's
``mju_*``; checks of rotations and poses at the boundary are :mod:`redik.core.rotation_policy`.
Every other module calls these functions; the compiled kernels call the compiled ones
(:func:`~redik.lie.so3.apply_inverse_v`, :func:`~redik.lie.se3.se3_left_jacobian_inverse_entries`)
or twins tested equal to them (docs/architecture.md).
"""

from redik.lie.angles import euler_angles, periodic_coordinates, wrap_angle, wrap_into_range
from redik.lie.metrics import (
    body_error_twist,
    euler_difference,
    exp_coordinate_distance,
    pose_errors,
    position_distance,
    quaternion_chordal_distance,
    quaternion_geodesic_distance,
    rotation_angle,
    rotation_angle_trace,
)
from redik.lie.se3 import (
    adjoint,
    interpolate_pose,
    inverse,
    make_pose,
    se3_exp,
    se3_left_jacobian_inverse,
    se3_left_jacobian_inverse_entries,
    se3_log,
    world_jacobian_to,
)
from redik.lie.so3 import (
    apply_inverse_v,
    matrix_from_quat,
    quat_from_matrix,
    rotation_log,
    skew,
    slerp,
    so3_exp,
    so3_left_jacobian_inverse,
    so3_log,
)

__all__ = [
    "adjoint",
    "apply_inverse_v",
    "body_error_twist",
    "euler_angles",
    "euler_difference",
    "exp_coordinate_distance",
    "interpolate_pose",
    "inverse",
    "make_pose",
    "matrix_from_quat",
    "periodic_coordinates",
    "pose_errors",
    "position_distance",
    "quat_from_matrix",
    "quaternion_chordal_distance",
    "quaternion_geodesic_distance",
    "rotation_angle",
    "rotation_angle_trace",
    "rotation_log",
    "se3_exp",
    "se3_left_jacobian_inverse",
    "se3_left_jacobian_inverse_entries",
    "se3_log",
    "skew",
    "slerp",
    "so3_exp",
    "so3_left_jacobian_inverse",
    "so3_log",
    "world_jacobian_to",
    "wrap_angle",
    "wrap_into_range",
]
