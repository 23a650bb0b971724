"""Input validation for the closed-form solvers: done once at the boundary, never in kernels.

Each check returns the value as a float array of the expected shape or raises an
:mod:`redik.core.exceptions` error whose message names the argument, what it got and what was
expected.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from redik.core.exceptions import InvalidInput, InvalidPose
from redik.core.rotation_policy import ROTATION_TOLERANCE, as_pose, as_rotation, check_rotations
from redik.core.validate import MAX_COORDINATE, real_array
from redik.kinematics.compiled import valid_target


def finite_array(value: object, name: str, shape: tuple[int | None, ...]) -> np.ndarray:
    """A finite float array of a given shape.

    ``value`` as a finite float array of ``shape`` (``None`` matches any length), entries
    within ``±``:data:`~redik.core.validate.MAX_COORDINATE` (larger ones overflow the
    kernels' squares).
    """
    array = real_array(value, name)
    if array.ndim != len(shape) or any(
        want is not None and got != want for got, want in zip(array.shape, shape, strict=True)
    ):
        raise InvalidInput(f"{name} must have shape {_shape(shape)}, got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InvalidInput(f"{name} must be finite, got {np.array2string(array, threshold=20)}")
    if np.abs(array).max(initial=0.0) > MAX_COORDINATE:
        raise InvalidInput(
            f"{name} must be within ±{MAX_COORDINATE:g} (MuJoCo's mjMAXVAL), "
            f"got {np.array2string(array, threshold=20)}"
        )
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


def scalar(value: Any, name: str) -> float:
    """A finite real number.

    A finite real number within ``±``:data:`~redik.core.validate.MAX_COORDINATE` (a signed
    DH offset, a coordinate, an angle).
    """
    try:
        if type(value) is not float and type(value) is not int:  # the fast path: no numpy
            if isinstance(value, bool | str | bytes | complex) or np.ndim(value) != 0:
                raise TypeError
        number = float(value)
    except (TypeError, ValueError, OverflowError):  # a ragged list, an int beyond float
        raise InvalidInput(f"{name} must be a real number, got {value!r}") from None
    if not (math.isfinite(number) and abs(number) <= MAX_COORDINATE):
        raise InvalidInput(f"{name} must be finite and within ±{MAX_COORDINATE:g}, got {number!r}")
    return number


def rotation(value: object, name: str = "R", *, strict: bool = False) -> np.ndarray:
    """A 3×3 rotation matrix.

    A 3×3 rotation matrix, under :mod:`~redik.core.rotation_policy` (a near-rotation is
    projected onto SO(3) with a warning unless ``strict``).
    """
    return as_rotation(value, name, strict=strict)


def pose(value: object, name: str = "T", *, strict: bool = False) -> np.ndarray:
    """A 4×4 rigid transform ``[[R, p], [0, 0, 0, 1]]``, under :mod:`~redik.core.rotation_policy`.

    A C-contiguous float64 array that :func:`redik.kinematics.compiled.valid_target` accepts
    as it is (as_pose's own rule for "use as it is", strict or not) is returned at once,
    without as_pose's Python checks; anything else goes through
    :func:`redik.core.rotation_policy.as_pose` (errors, projection of a near-rotation).
    """
    if (
        value.__class__ is np.ndarray
        and value.dtype == np.float64
        and value.shape == (4, 4)
        and value.flags.c_contiguous
        and valid_target(value, ROTATION_TOLERANCE)
    ):
        return value
    return as_pose(value, name, strict=strict)


def poses(value: object, name: str = "T", *, strict: bool = False) -> np.ndarray:
    """A stack of rigid transforms.

    A (B, 4, 4) stack of rigid transforms, under :mod:`~redik.core.rotation_policy`
    (near-rotations projected, one warning for the batch, unless ``strict``); the first bad one is
    named.
    """
    T = real_array(value, name, InvalidPose)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise InvalidPose(f"{name} must have shape (B, 4, 4) (rigid transforms), got {T.shape}")
    with np.errstate(invalid="ignore"):
        bad = ~np.isfinite(T).all(axis=(1, 2))
        bad |= np.abs(T[:, 3] - (0.0, 0.0, 0.0, 1.0)).max(axis=1) > ROTATION_TOLERANCE
        bad |= np.abs(T[:, :3, 3]).max(axis=1) > MAX_COORDINATE
    _refuse_first(T, bad, name, strict)
    block = T[:, :3, :3]
    R, accepted = check_rotations(block, name, strict=strict)
    _refuse_first(T, ~accepted, name, strict)
    if R is not block:
        T = T.copy()
        T[:, :3, :3] = R
    return T


def _refuse_first(T: np.ndarray, bad: np.ndarray, name: str, strict: bool) -> None:
    """Raise :func:`~redik.core.rotation_policy.as_pose`'s error for the first marked pose."""
    if bad.any():
        index = int(np.argmax(bad))
        as_pose(T[index], f"{name}[{index}]", strict=strict)
        raise AssertionError(f"{name}[{index}] refused by the stack check, not by as_pose")


def limits(
    value: tuple[object, object] | None, n_joints: int
) -> tuple[np.ndarray, np.ndarray] | None:
    """``(lower, upper)`` joint limits, each (n,), ``lower ≤ upper``; ±inf allowed."""
    if value is None:
        return None
    if len(value) != 2:
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
    if bounds is None:  # each bound alone is well formed, yet not the pair
        raise InvalidInput(f"limits must be two arrays of {n_joints} numbers, got {value!r}")
    lower, upper = bounds
    if (lower > upper).any():
        joints = np.flatnonzero(lower > upper).tolist()
        raise InvalidInput(f"limits lower > upper for joints {joints}: {lower} > {upper}")
    return lower, upper


def _shape(shape: tuple[int | None, ...]) -> str:
    return "(" + ", ".join("B" if n is None else str(n) for n in shape) + ")"


def resolve_limits(
    value: object, robot: tuple[np.ndarray, np.ndarray], n_joints: int
) -> tuple[np.ndarray, np.ndarray]:
    """The ``limits=`` of a solver bound to a robot, as ``(lower, upper)``.

    Args:
        value: ``"robot"`` (the robot's limits), None (no limits) or ``(lower, upper)``.
        robot: The robot's limits.
        n_joints: The number of joints.

    Raises:
        InvalidInput: Any other string, or limits that :func:`limits` refuses.
    """
    if isinstance(value, str):
        if value != "robot":
            raise InvalidInput(f"limits must be 'robot', None or (lower, upper), got {value!r}")
        return robot
    if value is None:
        return np.full(n_joints, -np.inf), np.full(n_joints, np.inf)
    checked = limits(value, n_joints)  # type: ignore[arg-type]
    assert checked is not None
    return checked
