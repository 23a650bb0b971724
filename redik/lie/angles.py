"""Angles: wrapping to a turn, periodic joints, and Euler angles of a rotation.

Periodic joints and the wrap of their differences are defined in :mod:`redik.core.conventions`
(Joint vector). Euler angles are intrinsic: ``"xyz"`` means ``R = R_x(α) R_y(β) R_z(γ)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import overload

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput
from redik.core.validate import real_array

_TWO_PI = 2.0 * math.pi


@overload
def wrap_angle(angle: float) -> float: ...
@overload
def wrap_angle(angle: NDArray[np.float64]) -> NDArray[np.float64]: ...
def wrap_angle(angle: NDArray[np.float64] | float) -> NDArray[np.float64] | float:
    """Wrap angles to (−π, π]: ``a − 2πk`` for the integer ``k`` that lands there.

    Exact in floating point, with ``π`` and ``2π`` the doubles ``math.pi`` and
    ``2 * math.pi``: ``fmod`` is exact, and so is the final shift by ``±2π`` (Sterbenz's lemma,
    the remainder being within a factor 2 of ``2π``). So ``±π`` and every odd multiple of
    ``π`` give ``π``, ``wrap(−a) = −wrap(a)`` away from ``π``, a tiny angle is returned
    unchanged, and a large one loses nothing to an intermediate rounding (the textbook
    ``π − ((π − a) mod 2π)`` rounds ``π − a`` first: at ``a = 1e300`` it is off by π).
    The double ``2π`` differs from the real one by 2.4e-16, so for large ``|a|`` the result
    differs from the real-number remainder by ``k · 2.4e-16 < ulp(a) / 2``: less than the
    rounding of the input itself.

    Args:
        angle: An angle (rad) or an array of them.

    Returns:
        The wrapped angles, elementwise; a float for a scalar. NaN and ±inf give NaN.

    Raises:
        InvalidInput: ``angle`` does not hold real numbers.
    """
    if isinstance(angle, float | int) and not isinstance(angle, bool):
        r = math.fmod(angle, _TWO_PI) if math.isfinite(angle) else math.nan
        return r - _TWO_PI if r > math.pi else (r + _TWO_PI if r <= -math.pi else r)
    a = (
        angle
        if type(angle) is np.ndarray and angle.dtype == np.float64
        else real_array(angle, "angle")
    )
    with np.errstate(invalid="ignore"):
        remainder = np.fmod(a, _TWO_PI)
        # k·2π with k ∈ {−1, 0, 1} is exact, and so is r − k·2π.
        wrapped = remainder - _TWO_PI * (
            (remainder > math.pi).astype(float) - (remainder <= -math.pi)
        )
    return float(wrapped) if wrapped.ndim == 0 else wrapped


def wrap_into_range(
    angle: NDArray[np.float64] | float, lower: NDArray[np.float64] | float
) -> NDArray[np.float64] | float:
    """Move angles by whole turns into ``[lower, lower + 2π)``.

    ``lower + ((angle − lower) mod 2π)``: the representative a periodic joint
    (:func:`periodic_coordinates`) takes when a step carries it out of its range; the
    compiled DLS kernel writes the same expression inline. :func:`wrap_angle` is the
    symmetric case, into (−π, π].

    Args:
        angle: Angles (rad).
        lower: The lower ends of the ranges, broadcast against ``angle``.

    Returns:
        The moved angles, elementwise.
    """
    return lower + np.mod(np.subtract(angle, lower), _TWO_PI)


def periodic_coordinates(
    revolute: NDArray[np.bool_], lower: NDArray[np.float64], upper: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """Mark the periodic coordinates: rotations whose range spans a full turn.

    ``upper − lower ≥ 2π`` (an unlimited hinge included). Each angle of such a joint has an
    in-range representative, so redik takes it modulo 2π: solutions and samples that differ
    by whole turns are one, their differences are wrapped by :func:`wrap_angle`, and a step
    that leaves the range is wrapped back into it rather than stopped at the limit
    (:mod:`redik.core.conventions`, Joint vector). The one definition, behind
    ``Robot.periodic`` and the compiled kernel's mask
    (:meth:`redik.kinematics.chain.Chain.kernel_arrays`).

    Args:
        revolute: Which coordinates are angles (bool, n).
        lower: Lower limits (n,).
        upper: Upper limits (n,).

    Returns:
        The mask of periodic coordinates (bool, n).
    """
    return np.asarray(revolute, dtype=bool) & (np.subtract(upper, lower) >= 2.0 * np.pi)


def _clipped_asin(x: float) -> float:
    return math.asin(max(-1.0, min(1.0, x)))


def _xyz(R: NDArray[np.float64]) -> tuple[float, float, float]:
    return math.atan2(-R[1, 2], R[2, 2]), _clipped_asin(R[0, 2]), math.atan2(-R[0, 1], R[0, 0])


def _zyx(R: NDArray[np.float64]) -> tuple[float, float, float]:
    return math.atan2(R[1, 0], R[0, 0]), _clipped_asin(-R[2, 0]), math.atan2(R[2, 1], R[2, 2])


def _zyz(R: NDArray[np.float64]) -> tuple[float, float, float]:
    beta = math.atan2(math.hypot(R[0, 2], R[1, 2]), R[2, 2])
    return math.atan2(R[1, 2], R[0, 2]), beta, math.atan2(R[2, 1], -R[2, 0])


def _zxz(R: NDArray[np.float64]) -> tuple[float, float, float]:
    beta = math.atan2(math.hypot(R[0, 2], R[1, 2]), R[2, 2])
    return math.atan2(R[0, 2], -R[1, 2]), beta, math.atan2(R[2, 0], R[2, 1])


_EULER: dict[str, Callable[[NDArray[np.float64]], tuple[float, float, float]]] = {
    "xyz": _xyz,
    "zyx": _zyx,
    "zyz": _zyz,
    "zxz": _zxz,
}


def euler_angles(R: NDArray[np.float64], convention: str = "xyz") -> NDArray[np.float64]:
    r"""Intrinsic Euler angles ``(α, β, γ)`` of a rotation.

    ======== ============================== ==================== ===================
    ``xyz``  ``R = R_x(α) R_y(β) R_z(γ)``   roll-pitch-yaw       singular at β = ±π/2
    ``zyx``  ``R = R_z(α) R_y(β) R_x(γ)``                        singular at β = ±π/2
    ``zyz``  ``R = R_z(α) R_y(β) R_z(γ)``   a spherical wrist    singular at β = 0, π
    ``zxz``  ``R = R_z(α) R_x(β) R_z(γ)``   a spherical wrist    singular at β = 0, π
    ======== ============================== ==================== ===================

    The middle angle is in ``[−π/2, π/2]`` (``xyz``, ``zyx``) or ``[0, π]`` (``zyz``,
    ``zxz``); the other two in (−π, π] (Siciliano et al., *Robotics: Modelling, Planning and
    Control*, 2009, §2.4). Equal to scipy's ``Rotation.from_matrix(R).as_euler("XYZ")`` (and
    ``"ZYX"``, ``"ZYZ"``, ``"ZXZ"``) away from the singularities.

    Args:
        R: A rotation matrix (3, 3).
        convention: One of the four above (case-insensitive).

    Returns:
        ``(α, β, γ)`` (rad).

    Raises:
        InvalidInput: An unknown ``convention``.
    """
    angles = _EULER.get(str(convention).lower())
    if angles is None:
        raise InvalidInput(f"Euler convention must be one of {list(_EULER)}, got {convention!r}")
    return np.array(angles(R))
