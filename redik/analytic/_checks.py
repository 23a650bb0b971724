"""Input validation for the closed-form solvers: done once at the boundary, never in kernels.

Each check returns the value as a float array of the expected shape or raises an
:mod:`redik.exceptions` error whose message names the argument, what it got and what was
expected.
"""

from __future__ import annotations

import numpy as np

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
    _check_rotations(R[None], name, InvalidRotation)
    return R


def pose(value: object, name: str = "T") -> np.ndarray:
    """A 4×4 rigid transform ``[[R, p], [0, 0, 0, 1]]``."""
    return poses(value, name, batch=False)


def poses(value: object, name: str = "T", *, batch: bool = True) -> np.ndarray:
    """A (B, 4, 4) stack of rigid transforms (or one 4×4 when ``batch`` is False)."""
    shape: tuple[int | None, ...] = (None, 4, 4) if batch else (4, 4)
    T = finite_array(value, name, shape)
    stack = T if batch else T[None]
    bottom = np.abs(stack[:, 3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max(axis=1)
    if np.any(bottom > ORTHONORMAL_TOL):
        index = int(np.argmax(bottom))
        where = f"{name}[{index}]" if batch else name
        raise InvalidPose(
            f"{where} must be a rigid transform with bottom row [0, 0, 0, 1], "
            f"got {np.array2string(stack[index, 3])}"
        )
    _check_rotations(stack[:, :3, :3], name, InvalidPose, batch=batch)
    return T


def limits(
    value: tuple[object, object] | None, n_joints: int
) -> tuple[np.ndarray, np.ndarray] | None:
    """``(lower, upper)`` joint limits, each (n,), ``lower ≤ upper``; ±inf allowed."""
    if value is None:
        return None
    if len(value) != 2:  # type: ignore[arg-type]
        raise InvalidInput(f"limits must be a pair (lower, upper), got {value!r}")
    bounds = []
    for name, bound in zip(("lower", "upper"), value, strict=True):
        array = np.asarray(bound, dtype=float)
        if array.shape != (n_joints,) or np.any(np.isnan(array)):
            raise InvalidInput(
                f"limits {name} must be {n_joints} numbers (±inf allowed, no NaN), got {bound!r}"
            )
        bounds.append(array)
    lower, upper = bounds
    if np.any(lower > upper):
        joints = np.flatnonzero(lower > upper).tolist()
        raise InvalidInput(f"limits lower > upper for joints {joints}: {lower} > {upper}")
    return lower, upper


def _check_rotations(
    R: np.ndarray, name: str, error: type[InvalidInput], *, batch: bool = False
) -> None:
    gram = np.einsum("bji,bjk->bik", R, R) - np.eye(3)
    deviation = np.abs(gram).max(axis=(1, 2))
    determinant = np.linalg.det(R)
    bad = (deviation > ORTHONORMAL_TOL) | (determinant < 0.0)
    if np.any(bad):
        index = int(np.argmax(bad))
        where = f"{name}[{index}]" if batch else name
        what = "rotation block of " if error is InvalidPose else ""
        raise error(
            f"the {what}{where} must be a rotation (orthonormal, det +1): RᵀR deviates from I "
            f"by {deviation[index]:.2e} (tolerance {ORTHONORMAL_TOL:g}), "
            f"det = {determinant[index]:.6g}"
        )


def _shape(shape: tuple[int | None, ...]) -> str:
    return "(" + ", ".join("B" if n is None else str(n) for n in shape) + ")"
