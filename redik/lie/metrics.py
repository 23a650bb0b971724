r"""Distances between poses and rotations: the errors a solver reports, and the course's metrics.

Every redik solver reports ``(‖p_d − p‖, ‖log(Rᵀ R_d)‖)`` (:func:`pose_errors`) and drives the
body error twist ``log(T⁻¹ T_d)`` (:func:`body_error_twist`) to zero
(:mod:`redik.core.conventions`, Pose error). The others are the orientation metrics of the
course (position distance; rotation angle by the log and by the trace; geodesic and chordal
distances of unit quaternions; the distance of exponential coordinates; the difference of Euler
angles), each equal to its formula there, with what it is and is not good for. Huynh, *Metrics
for 3D rotations: comparison and analysis*, J. Math. Imaging Vis. 35, 2009, compares them.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.lie.angles import euler_angles, wrap_angle
from redik.lie.se3 import inverse, se3_log
from redik.lie.so3 import so3_log


def position_distance(T_a: NDArray[np.float64], T_b: NDArray[np.float64]) -> float:
    """The Euclidean distance ``e_p = ‖p_b − p_a‖`` between two poses' origins.

    Args:
        T_a: A pose (4, 4).
        T_b: A pose (4, 4).

    Returns:
        The distance (m).
    """
    return float(np.linalg.norm(T_b[:3, 3] - T_a[:3, 3]))


def rotation_angle(R_a: NDArray[np.float64], R_b: NDArray[np.float64]) -> float:
    """The angle of the relative rotation, by the logarithm: ``‖log(R_aᵀ R_b)‖``.

    Accurate at every angle; this is the rotation error every redik solver reports.

    Args:
        R_a: A rotation (3, 3).
        R_b: A rotation (3, 3).

    Returns:
        The angle (rad), in ``[0, π]``.
    """
    return float(np.linalg.norm(so3_log(R_a.T @ R_b)))


def rotation_angle_trace(R_a: NDArray[np.float64], R_b: NDArray[np.float64]) -> float:
    """The angle of the relative rotation, by the trace: ``arccos((tr(R_aᵀ R_b) − 1)/2)``.

    The textbook formula. Its derivative is unbounded at 0, so it loses about half the digits
    for small angles: an error of 1e-8 rad reads as about 1e-8 ± 1e-8. Prefer
    :func:`rotation_angle` for tolerances.

    Args:
        R_a: A rotation (3, 3).
        R_b: A rotation (3, 3).

    Returns:
        The angle (rad), in ``[0, π]``.
    """
    cos_angle = 0.5 * (float(np.sum(R_a * R_b)) - 1.0)
    return math.acos(min(1.0, max(-1.0, cos_angle)))


def quaternion_geodesic_distance(q_a: NDArray[np.float64], q_b: NDArray[np.float64]) -> float:
    """The rotation angle between two unit quaternions: ``2 arccos|q_a · q_b|``.

    Computed as ``‖log(q_b⁻¹ q_a)‖`` by ``mju_subQuat``, which brings the angle into
    ``[−π, π]``: sign-invariant (``q`` and ``−q`` are the same rotation), and equal to
    :func:`rotation_angle` of the corresponding matrices.

    Args:
        q_a: A unit quaternion ``(w, x, y, z)``.
        q_b: A unit quaternion ``(w, x, y, z)``.

    Returns:
        The angle (rad), in ``[0, π]``.
    """
    rotation = np.empty(3)
    mujoco.mju_subQuat(rotation, np.asarray(q_b, dtype=float), np.asarray(q_a, dtype=float))
    return float(np.linalg.norm(rotation))


def quaternion_chordal_distance(q_a: NDArray[np.float64], q_b: NDArray[np.float64]) -> float:
    """The chordal distance ``min(‖q_a − q_b‖, ‖q_a + q_b‖) = 2 sin(θ/4)`` of unit quaternions.

    A metric on rotations that is cheap and smooth, for a relative angle θ; it is not an
    angle.

    Args:
        q_a: A unit quaternion ``(w, x, y, z)``.
        q_b: A unit quaternion ``(w, x, y, z)``.

    Returns:
        The distance, in ``[0, √2]``.
    """
    q_a = np.asarray(q_a, dtype=float)
    q_b = np.asarray(q_b, dtype=float)
    return float(min(np.linalg.norm(q_a - q_b), np.linalg.norm(q_a + q_b)))


def exp_coordinate_distance(R_a: NDArray[np.float64], R_b: NDArray[np.float64]) -> float:
    """The distance of exponential coordinates ``e_R = ‖r_a − r_b‖``, ``r = log(R)^∨``.

    Each rotation's own coordinates (``‖r‖ ≤ π``) are compared, not their relative
    rotation: this equals :func:`rotation_angle` only when the two axes coincide, and jumps
    where an angle crosses π (there ``r`` flips to ``−r``). The course's
    minimum-coordinate error (2).

    Args:
        R_a: A rotation (3, 3).
        R_b: A rotation (3, 3).

    Returns:
        ``‖log(R_a)^∨ − log(R_b)^∨‖``.
    """
    return float(np.linalg.norm(so3_log(R_a) - so3_log(R_b)))


def body_error_twist(T: NDArray[np.float64], T_target: NDArray[np.float64]) -> NDArray[np.float64]:
    """The body error twist ``ξ_b = log(T⁻¹ T_d) = (v, ω)``: the target seen from ``T``.

    The pose error of :mod:`redik.core.conventions` (``T`` the current pose, ``T_d`` the
    desired one), in ``T``'s frame; Modern Robotics §6.2 (``IKinBody``'s ``V_b``).

    Args:
        T: The current pose (4, 4).
        T_target: The desired pose ``T_d`` (4, 4).

    Returns:
        ``ξ_b`` (6,).
    """
    return se3_log(inverse(T) @ T_target)


def euler_difference(
    R_a: NDArray[np.float64], R_b: NDArray[np.float64], convention: str = "xyz"
) -> NDArray[np.float64]:
    """The difference of Euler angles ``φ_b − φ_a``, each wrapped to (−π, π].

    **Valid only for small errors away from the singularities** of the convention: Euler
    angles are not a metric, their difference depends on the convention, and near the
    singular middle angle a tiny rotation can change the first and last angles by up to π.
    Use it to read an error in familiar terms, never as a convergence test.

    Args:
        R_a: A rotation (3, 3).
        R_b: A rotation (3, 3).
        convention: As for :func:`redik.lie.angles.euler_angles`.

    Returns:
        The three differences (rad).
    """
    return wrap_angle(euler_angles(R_b, convention) - euler_angles(R_a, convention))


def pose_errors(T: NDArray[np.float64], T_target: NDArray[np.float64]) -> tuple[float, float]:
    """The position and rotation errors every redik solver reports.

    Args:
        T: The current pose (4, 4).
        T_target: The desired pose ``T_d`` (4, 4).

    Returns:
        ``(‖p_d − p‖, ‖log(Rᵀ R_d)‖)`` in metres and radians.
    """
    return position_distance(T, T_target), rotation_angle(T[:3, :3], T_target[:3, :3])
