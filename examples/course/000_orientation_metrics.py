"""Notes 000 (Ch7 Inverse Kinematics), "Position and Orientation Error for Minimum-Coordinate
Representation": the distance metrics.

e_p = ‖p1 − p2‖; e_R by (1) unit quaternions: the geodesic distance 2 arccos(|q1·q2|) ∈ [0, π]
and the chordal distance min(‖q1 − q2‖, ‖q1 + q2‖) ∈ [0, √2]; (2) exponential coordinates,
‖r1 − r2‖; (3) Euler angles, ‖φ1 − φ2‖ (small distances only); and the preferred
arccos((tr R_rel − 1)/2) = ‖log(R_rel)^∨‖ with R_rel = R1ᵀ R2. The notes give no numbers: the
two poses are chosen here, and each metric is evaluated by the notes' formula and by
``redik.lie``. ‖r1 − r2‖ is not the rotation angle between R1 and R2 (equal only when the two
axes coincide), which the last line shows.

Run: python examples/course/000_orientation_metrics.py
"""

import math

import numpy as np

from redik import lie

R1, R2 = lie.so3_exp(np.array([0.2, -0.4, 0.3])), lie.so3_exp(np.array([0.5, -0.1, 0.6]))
T1, T2 = lie.make_pose(R1, [0.1, 0.2, 0.3]), lie.make_pose(R2, [0.4, -0.2, 0.3])
q1, q2 = lie.quat_from_matrix(R1), lie.quat_from_matrix(R2)
r1, r2 = lie.so3_log(R1), lie.so3_log(R2)
phi1, phi2 = lie.euler_angles(R1, "zyx"), lie.euler_angles(R2, "zyx")

ROWS = [  # metric, the notes' formula, redik
    ("e_p", np.linalg.norm(T1[:3, 3] - T2[:3, 3]), lie.position_distance(T1, T2)),
    ("geodesic", 2 * math.acos(abs(q1 @ q2)), lie.quaternion_geodesic_distance(q1, q2)),
    ("chordal", min(np.linalg.norm(q1 - q2), np.linalg.norm(q1 + q2)),
     lie.quaternion_chordal_distance(q1, q2)),
    ("‖r1 − r2‖", np.linalg.norm(r1 - r2), lie.exp_coordinate_distance(R1, R2)),
    ("‖φ1 − φ2‖ ZYX", np.linalg.norm(phi1 - phi2),
     np.linalg.norm(lie.euler_difference(R1, R2, "zyx"))),
    ("trace", math.acos((np.trace(R1.T @ R2) - 1) / 2), lie.rotation_angle_trace(R1, R2)),
    ("‖log R_rel‖", np.linalg.norm(lie.so3_log(R1.T @ R2)), lie.rotation_angle(R1, R2)),
]  # fmt: skip

print("000 pose-error metrics   the notes' formula           redik   redik − notes")
for name, notes, ours in ROWS:
    print(f"  {name:14s} {notes:18.12f} {ours:15.12f} {ours - notes:+15.1e}")
print(
    f"‖r1 − r2‖ = {lie.exp_coordinate_distance(R1, R2):.4f} is not the angle of R1ᵀR2, "
    f"{lie.rotation_angle(R1, R2):.4f}; the body error twist log(T1⁻¹T2) "
    f"(lie.body_error_twist) has that angle: {np.linalg.norm(lie.body_error_twist(T1, T2)[3:]):.4f}"
)
