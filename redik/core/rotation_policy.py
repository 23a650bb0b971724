r"""How close to a rotation a matrix must be to be used as one: the one tolerance policy.

Every entry point that takes a rotation or a pose applies it (:func:`as_rotation`,
:func:`as_pose`, :func:`check_rotations`, and through them ``solve_pose``, the tasks'
``set_target``, the closed-form solvers and ``solve_batch``). For a matrix ``M`` with
``d = max|MᵀM − I|``:

* ``d ≤`` :data:`ROTATION_TOLERANCE` and ``|det M − 1| ≤`` :data:`ROTATION_TOLERANCE`: used as
  it is;
* ``d ≤`` :data:`NEAR_ROTATION_TOLERANCE` and ``det M > 0``: replaced by
  :func:`closest_rotation` (the SVD projection onto SO(3)) with a
  :class:`~redik.core.exceptions.NearRotationWarning` (a rotation typed with three or more
  decimals); with ``strict=True`` it is refused instead;
* anything else (NaN or inf, a reflection, a scaled or sheared matrix): refused with
  :class:`~redik.core.exceptions.InvalidRotation` or :class:`~redik.core.exceptions.InvalidPose`.

The bottom row of a pose must be ``[0, 0, 0, 1]`` within :data:`ROTATION_TOLERANCE` in both
modes, and its translation within ``±``:data:`~redik.core.validate.MAX_COORDINATE`. A unit
quaternion (:func:`as_quaternion`) must have norm 1 within :data:`ROTATION_TOLERANCE`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import (
    InvalidInput,
    InvalidPose,
    InvalidRotation,
    NearRotationWarning,
    warn,
)
from redik.core.validate import MAX_COORDINATE, as_vector, real_array

ROTATION_TOLERANCE = 1e-6
"""Largest ``max|RᵀR − I|`` and ``|det R − 1|`` of a matrix used as a rotation as it is: what
floating-point products of rotations and MuJoCo's ``xmat`` stay well within. The only
tolerance of ``strict=True``."""

NEAR_ROTATION_TOLERANCE = 2e-3
"""Largest ``max|RᵀR − I|`` of a matrix (with ``det R > 0``) accepted by the pose entry points
after projection onto SO(3), with a :class:`~redik.core.exceptions.NearRotationWarning`: any
rotation typed from a book with three or more decimals. Rounding each entry by ``|ε| ≤ 5e-4``
moves an entry of ``RᵀR`` by at most ``2 ‖column‖ ‖ε‖ ≤ 2√3 · 5e-4 ≈ 1.7e-3`` (Modern
Robotics' IKinBody quiz target has 5.4e-5; four decimals give at most 1.7e-4), while two
decimals give up to 1.7e-2 and are refused. A reflection is refused whatever its defect."""


def _defect_and_det(rows: Any, largest: Callable[[tuple[Any, ...]], Any]) -> tuple[Any, Any]:
    """``(max|RᵀR − I|, det R)`` from the rows of ``R``.

    Python floats for one matrix (numpy calls on 3 × 3 arrays would cost more than the check
    is worth at a boundary), or arrays over a stack; ``largest`` is ``max`` or its numpy
    reduction.
    """
    (a, b, c), (d, e, f), (g, h, i) = rows
    defect = largest(
        (
            abs(a * a + d * d + g * g - 1.0),
            abs(b * b + e * e + h * h - 1.0),
            abs(c * c + f * f + i * i - 1.0),
            abs(a * b + d * e + g * h),
            abs(a * c + d * f + g * i),
            abs(b * c + e * f + h * i),
        )
    )
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return defect, det


def _verdict(defect: Any, det: Any) -> tuple[Any, Any]:
    """The policy on floats or arrays alike: ``(exact, accepted)``.

    A matrix accepted but not exact is projected (``exact`` implies ``accepted``).
    """
    exact = (defect <= ROTATION_TOLERANCE) & (abs(det - 1.0) <= ROTATION_TOLERANCE)
    return exact, (defect <= NEAR_ROTATION_TOLERANCE) & (det > 0.0)


def _matrix_stack(R: object, name: str) -> NDArray[np.float64]:
    """``R`` as a float (..., 3, 3) array, or :class:`InvalidRotation` naming its shape."""
    R = real_array(R, name, InvalidRotation)
    if R.ndim < 2 or R.shape[-2:] != (3, 3):
        raise InvalidRotation(f"{name} must have shape (..., 3, 3), got {R.shape}")
    return R


def rotation_defect(R: object) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Measure how far each matrix of a stack is from SO(3), as the policy does.

    Args:
        R: A (..., 3, 3) stack of matrices.

    Returns:
        ``(max|RᵀR − I|, det R)``, each of shape (...).

    Raises:
        InvalidRotation: ``R`` is not a real (..., 3, 3) array.
    """
    R = _matrix_stack(R, "R")
    with np.errstate(invalid="ignore", over="ignore"):
        defect, det = _defect_and_det(np.moveaxis(R, (-2, -1), (0, 1)), np.maximum.reduce)
    return np.asarray(defect), np.asarray(det)


def closest_rotation(R: object) -> NDArray[np.float64]:
    r"""Project onto SO(3): the rotation nearest to ``R`` in the Frobenius norm.

    With the SVD ``R = U Σ Vᵀ``, :math:`\arg\min_{Q ∈ SO(3)} ‖Q − R‖_F = U\,
    \mathrm{diag}(1, 1, \det(U V^\top))\,V^\top` (the orthogonal Procrustes problem;
    Higham, *Matrix nearness problems*, 1989, §3; Umeyama, IEEE TPAMI 13(4), 1991, for the
    determinant sign). For ``det R > 0`` it is the orthogonal polar factor ``R (RᵀR)^{-1/2}``.
    scipy's ``Rotation.from_matrix(R).as_matrix()`` gives the same matrices.

    Args:
        R: One (3, 3) matrix or a (..., 3, 3) stack.

    Returns:
        The projected matrices, of the shape of ``R``.

    Raises:
        InvalidRotation: ``R`` is not a real (..., 3, 3) array, or is not finite.
    """
    R = _matrix_stack(R, "R")
    if not np.isfinite(R).all():
        raise InvalidRotation(f"R must be finite to be projected onto SO(3), got {R.tolist()}")
    U, _, Vt = np.linalg.svd(R)
    U[..., :, 2] *= np.where(np.linalg.det(U @ Vt) < 0.0, -1.0, 1.0)[..., None]
    closest: NDArray[np.float64] = U @ Vt
    return closest


def _refusal(name: str, defect: float, det: float, strict: bool) -> str:
    accepted = (
        f"strict=True accepts max|RᵀR − I| and |det − 1| up to {ROTATION_TOLERANCE:g}"
        if strict
        else f"accepted: max|RᵀR − I| ≤ {NEAR_ROTATION_TOLERANCE:g} with det > 0, projected "
        "onto the closest rotation"
    )
    return (
        f"{name} is not a rotation matrix: max|RᵀR − I| = {defect:.3g}, det = {det:.6g} "
        f"(expected orthonormal with det +1; {accepted})"
    )


def _checked_rotation_block(
    R: NDArray[np.float64], name: str, strict: bool, error: type[InvalidInput]
) -> NDArray[np.float64] | None:
    """None when ``R`` is a rotation as it is, else its projection (with a warning).

    Raises ``error`` when the policy refuses ``R``.
    """
    defect, det = _defect_and_det(R.tolist(), max)
    if not (math.isfinite(defect) and math.isfinite(det)):
        if not np.isfinite(R).all():
            raise error(f"{name} must be finite, holds NaN or inf: {R.tolist()}")
        raise error(_refusal(name, defect, det, strict))  # entries so large RᵀR overflows
    exact, accepted = _verdict(defect, det)
    if exact:
        return None
    if strict or not accepted:
        raise error(_refusal(name, defect, det, strict))
    projected = closest_rotation(R)
    warn(
        f"{name} is not exactly a rotation (max|RᵀR − I| = {defect:.2g}); using the closest "
        f"rotation, which moves its entries by up to {np.abs(projected - R).max():.2g}. "
        "Pass strict=True to refuse such input.",
        NearRotationWarning,
    )
    return projected


def check_rotations(
    R: object, name: str = "R", *, strict: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Apply the policy to a stack of matrices, without raising on a refused one.

    Args:
        R: A (B, 3, 3) stack.
        name: Its name, for the messages.
        strict: Refuse near-rotations instead of projecting them.

    Returns:
        ``(R_used, accepted)``: ``R_used`` is ``R`` itself when nothing is projected, else a
        copy with the near-rotations projected (one warning for all of them); ``accepted`` (B,)
        is False for the refused matrices (left unchanged).

    Raises:
        InvalidRotation: ``R`` is not a real (B, 3, 3) array.
    """
    stack = _matrix_stack(R, name)
    if stack.ndim != 3:
        raise InvalidRotation(f"{name} must have shape (B, 3, 3), got {stack.shape}")
    defect, det = rotation_defect(stack)
    with np.errstate(invalid="ignore"):
        exact, accepted = _verdict(defect, det)
    near = accepted & ~exact
    if strict or not near.any():
        return stack, exact
    stack = stack.copy()
    stack[near] = closest_rotation(stack[near])
    warn(
        f"{int(near.sum())} of the {len(stack)} matrices {name} are not exactly rotations "
        f"(max|RᵀR − I| up to {defect[near].max():.2g}); the closest rotations are used. "
        "Pass strict=True to refuse such input.",
        NearRotationWarning,
    )
    return stack, accepted


def as_rotation(R: object, name: str = "R", *, strict: bool = False) -> NDArray[np.float64]:
    """Check a rotation matrix under the policy.

    Args:
        R: The argument as given.
        name: Its name, for the messages.
        strict: Refuse a near-rotation instead of projecting it.

    Returns:
        ``R`` as a float (3, 3) array; a near-rotation projected onto SO(3) (with a
        :class:`~redik.core.exceptions.NearRotationWarning`).

    Raises:
        InvalidRotation: Wrong shape or dtype, non-finite entries, or not a rotation.
    """
    R = real_array(R, name, InvalidRotation)
    if R.shape != (3, 3):
        raise InvalidRotation(f"{name} must have shape (3, 3) (a rotation), got shape {R.shape}")
    projected = _checked_rotation_block(R, name, strict, InvalidRotation)
    return R if projected is None else projected


def as_pose(T: object, name: str = "T", *, strict: bool = False) -> NDArray[np.float64]:
    """Check a rigid transform under the policy.

    Args:
        T: The argument as given.
        name: Its name, for the messages.
        strict: Refuse a near-rotation block instead of projecting it.

    Returns:
        ``T`` as a float (4, 4) array; a near-rotation block projected onto SO(3) in a copy
        (with a :class:`~redik.core.exceptions.NearRotationWarning`).

    Raises:
        InvalidPose: Wrong shape or dtype, non-finite entries, a bottom row other than
            ``[0, 0, 0, 1]``, a translation beyond ``±``:data:`~redik.core.validate.MAX_COORDINATE`,
            or a rotation block that is not a rotation.
    """
    pose = real_array(T, name, InvalidPose)
    if pose.shape != (4, 4):
        raise InvalidPose(
            f"{name} must have shape (4, 4) (a rigid transform), got shape {pose.shape}"
        )
    rows = pose.tolist()
    if not math.isfinite(sum(rows[0]) + sum(rows[1]) + sum(rows[2]) + sum(rows[3])):
        raise InvalidPose(f"{name} must be finite, holds NaN or inf: {rows}")
    x, y, z, w = rows[3]
    if max(abs(x), abs(y), abs(z), abs(w - 1.0)) > ROTATION_TOLERANCE:
        raise InvalidPose(f"{name} must have the bottom row [0, 0, 0, 1], got {rows[3]}")
    if max(abs(rows[0][3]), abs(rows[1][3]), abs(rows[2][3])) > MAX_COORDINATE:
        raise InvalidPose(
            f"{name} has a translation beyond ±{MAX_COORDINATE:g} m (MuJoCo's mjMAXVAL): "
            f"{[rows[0][3], rows[1][3], rows[2][3]]}"
        )
    projected = _checked_rotation_block(pose[:3, :3], f"{name}[:3, :3]", strict, InvalidPose)
    if projected is None:
        return pose
    pose = pose.copy()
    pose[:3, :3] = projected
    return pose


def as_quaternion(
    quat: object, name: str = "quat", tol: float = ROTATION_TOLERANCE
) -> NDArray[np.float64]:
    """Check a unit quaternion ``(w, x, y, z)`` (:mod:`redik.core.conventions`).

    Args:
        quat: The argument as given.
        name: Its name, for the messages.
        tol: Largest ``|‖quat‖ − 1|`` accepted.

    Returns:
        ``quat`` as a float array of shape (4,), not renormalised.

    Raises:
        InvalidInput: Not a finite 4-vector of norm 1 within ``tol``.
    """
    vector = as_vector(quat, 4, name)
    norm = float(np.linalg.norm(vector))
    if abs(norm - 1.0) > tol:
        raise InvalidInput(f"{name} must be a unit quaternion (w, x, y, z), got norm {norm:.6g}")
    return vector
