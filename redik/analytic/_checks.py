"""Input validation for the closed-form solvers: done once at the boundary, never in kernels.

Each check returns the value as a float array of the expected shape or raises an
:mod:`redik.exceptions` error whose message names the argument, what it got and what was
expected.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from redik.analytic._numeric import SCALAR, Numeric, pose_entries
from redik.exceptions import InvalidInput, InvalidPose, InvalidRotation

#: How far ``RᵀR`` may be from the identity (max abs entry) for ``R`` to count as a rotation.
ORTHONORMAL_TOL = 1e-8


def finite_array(value: object, name: str, shape: tuple[int | None, ...]) -> np.ndarray:
    """``value`` as a finite float array of ``shape`` (``None`` matches any length)."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as error:
        raise InvalidInput(f"{name} must be numeric with shape {_shape(shape)}: {error}") from None
    if array.ndim != len(shape) or any(
        want is not None and got != want for got, want in zip(array.shape, shape, strict=True)
    ):
        raise InvalidInput(f"{name} must have shape {_shape(shape)}, got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InvalidInput(f"{name} must be finite, got {np.array2string(array, threshold=20)}")
    return array


def length(value: object, name: str, *, allow_zero: bool = False) -> float:
    """A link length: finite and positive (or non-negative with ``allow_zero``), in metres."""
    number = scalar(value, name)
    if number < 0.0 or (number == 0.0 and not allow_zero):
        expected = "non-negative" if allow_zero else "positive"
        raise InvalidInput(f"{name} must be a {expected} length in metres, got {number!r}")
    return number


def nonzero(value: object, name: str) -> float:
    """A signed DH parameter that the solver divides by."""
    number = scalar(value, name)
    if number == 0.0:
        raise InvalidInput(f"{name} must be non-zero for this arm family, got 0.0")
    return number


def scalar(value: object, name: str) -> float:
    """A finite real number (a signed DH offset, a coordinate, an angle)."""
    if isinstance(value, float | int) and not isinstance(value, bool):
        if not math.isfinite(value):
            raise InvalidInput(f"{name} must be finite, got {value!r}")
        return float(value)
    if isinstance(value, bool) or np.ndim(value) != 0:
        raise InvalidInput(f"{name} must be a real number, got {value!r}")
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InvalidInput(f"{name} must be a real number, got {value!r}") from None
    if not np.isfinite(number):
        raise InvalidInput(f"{name} must be finite, got {number!r}")
    return number


def rotation(value: object, name: str = "R") -> np.ndarray:
    """A 3×3 rotation matrix (orthonormal, det = +1)."""
    R = finite_array(value, name, (3, 3))
    _check_rotations(R.tolist(), SCALAR, name, InvalidRotation)
    return R


def pose(value: object, name: str = "T") -> np.ndarray:
    """A 4×4 rigid transform ``[[R, p], [0, 0, 0, 1]]``."""
    return poses(value, name, batch=False)


def poses(value: object, name: str = "T", *, batch: bool = True) -> np.ndarray:
    """A (B, 4, 4) stack of rigid transforms (or one 4×4 when ``batch`` is False)."""
    shape: tuple[int | None, ...] = (None, 4, 4) if batch else (4, 4)
    T = finite_array(value, name, shape)
    M, num = pose_entries(T)
    bottom = num.maximum(
        num.maximum(abs(M[3][0]), abs(M[3][1])), num.maximum(abs(M[3][2]), abs(M[3][3] - 1.0))
    )
    if num.any(bottom > ORTHONORMAL_TOL):
        index = int(np.argmax(bottom))
        where = f"{name}[{index}]" if batch else name
        raise InvalidPose(
            f"{where} must be a rigid transform with bottom row [0, 0, 0, 1], "
            f"got {np.array2string((T if batch else T[None])[index, 3])}"
        )
    _check_rotations(M, num, name, InvalidPose, batch=batch)
    return T


def limits(
    value: tuple[object, object] | None, n_joints: int
) -> tuple[np.ndarray, np.ndarray] | None:
    """``(lower, upper)`` joint limits, each (n,), ``lower ≤ upper``; ±inf allowed."""
    if value is None:
        return None
    if len(value) != 2:  # type: ignore[arg-type]
        raise InvalidInput(f"limits must be a pair (lower, upper), got {value!r}")
    try:
        bounds = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        bounds = None
    # One array and one check for well-formed limits; the per-bound loop names what is wrong.
    if bounds is None or bounds.shape != (2, n_joints) or np.isnan(bounds).any():
        for name, bound in zip(("lower", "upper"), value, strict=True):
            array = np.asarray(bound, dtype=float)
            if array.shape != (n_joints,) or np.any(np.isnan(array)):
                raise InvalidInput(
                    f"limits {name} must be {n_joints} numbers (±inf allowed, no NaN), "
                    f"got {bound!r}"
                )
    lower, upper = bounds
    if (lower > upper).any():
        joints = np.flatnonzero(lower > upper).tolist()
        raise InvalidInput(f"limits lower > upper for joints {joints}: {lower} > {upper}")
    return lower, upper


def _check_rotations(
    M: Any, num: Numeric, name: str, error: type[InvalidInput], *, batch: bool = False
) -> None:
    """Check that the 3×3 blocks ``M[i][j]`` (i, j < 3; :mod:`._numeric` entries) are
    rotations: ``RᵀR = I`` within :data:`ORTHONORMAL_TOL` and ``det R > 0``."""
    columns = [[M[i][j] for i in range(3)] for j in range(3)]
    deviation = 0.0
    for j in range(3):
        for k in range(j, 3):
            (a0, a1, a2), (b0, b1, b2) = columns[j], columns[k]
            dot = a0 * b0 + a1 * b1 + a2 * b2
            deviation = num.maximum(deviation, abs(dot - (1.0 if j == k else 0.0)))
    (a0, a1, a2), (b0, b1, b2), c = columns
    determinant = (
        (a1 * b2 - a2 * b1) * c[0] + (a2 * b0 - a0 * b2) * c[1] + (a0 * b1 - a1 * b0) * c[2]
    )
    bad = (deviation > ORTHONORMAL_TOL) | (determinant < 0.0)
    if num.any(bad):
        index = int(np.argmax(bad))
        where = f"{name}[{index}]" if batch else name
        what = "rotation block of " if error is InvalidPose else ""
        raise error(
            f"the {what}{where} must be a rotation (orthonormal, det +1): RᵀR deviates from I "
            f"by {np.ravel(deviation)[index]:.2e} (tolerance {ORTHONORMAL_TOL:g}), "
            f"det = {np.ravel(determinant)[index]:.6g}"
        )


def _shape(shape: tuple[int | None, ...]) -> str:
    return "(" + ", ".join("B" if n is None else str(n) for n in shape) + ")"
