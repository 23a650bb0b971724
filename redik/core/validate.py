"""Checks of arguments at the public boundary: scalar options, paths and real arrays.

Each check returns the value in a plain form (a Python number, a :class:`~pathlib.Path`, a
float array) or raises :class:`~redik.core.exceptions.InvalidInput` (or the subclass it is
given) naming the argument, so that a string, ``None``, a bool, a complex number or NaN where a
number belongs never reaches numpy or MuJoCo as a raw ``TypeError``. Checks happen once, where a
value enters redik; the maps and kernels behind them take validated input unchecked, as
MuJoCo's ``mju_*`` functions do. Rotations and poses have their own policy,
:mod:`redik.core.rotation_policy`.
"""

from __future__ import annotations

import math
import os
from numbers import Real
from pathlib import Path
from typing import Literal, overload

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput

MAX_COORDINATE = mujoco.mjMAXVAL
"""Largest magnitude (1e10) of a translation coordinate (m) or a joint value accepted at the
boundary: MuJoCo's ``mjMAXVAL``, beyond which it calls a state diverged. Squares of much
larger values overflow in the pose-error and QP arithmetic long before they mean anything."""


def _real(value: object) -> float | None:
    """``value`` as a float if it is a real number (a bool is none), else ``None``."""
    if isinstance(value, bool) or not isinstance(value, Real):
        return None
    return float(value)


def positive(value: object, name: str, *, allow_inf: bool = False, unit: str = "") -> float:
    """Check a strictly positive number.

    Args:
        value: The argument as given.
        name: Its name, for the message.
        allow_inf: Accept ``inf`` (an unbounded rate or budget).
        unit: The unit named in the message, if any.

    Returns:
        ``value`` as a float ``> 0``, finite unless ``allow_inf``.

    Raises:
        InvalidInput: ``value`` is not a real number ``> 0`` (a bool counts as none).
    """
    number = _real(value)
    if number is None or not number > 0 or not (allow_inf or math.isfinite(number)):
        finite = "" if allow_inf else "finite "
        units = f" ({unit})" if unit else ""
        raise InvalidInput(f"{name} must be a {finite}positive number{units}, got {value!r}")
    return number


def non_negative(value: object, name: str) -> float:
    """Check a finite number ``≥ 0``.

    Args:
        value: The argument as given.
        name: Its name, for the message.

    Returns:
        ``value`` as a float.

    Raises:
        InvalidInput: ``value`` is not a finite real number ``≥ 0``.
    """
    number = _real(value)
    if number is None or not number >= 0 or not math.isfinite(number):
        raise InvalidInput(f"{name} must be a finite number ≥ 0, got {value!r}")
    return number


def fraction(value: object, name: str) -> float:
    """Check a share strictly between 0 and 1.

    Such as the fraction by which ``‖e‖²`` must fall to count as progress: 0 would ask
    nothing, 1 an exact zero.

    Args:
        value: The argument as given.
        name: Its name, for the message.

    Returns:
        ``value`` as a float in ``(0, 1)``.

    Raises:
        InvalidInput: ``value`` is not a real number in ``(0, 1)``.
    """
    number = _real(value)
    if number is None or not 0.0 < number < 1.0:
        raise InvalidInput(f"{name} must be a number in (0, 1), got {value!r}")
    return number


@overload
def integer(
    value: object, name: str, minimum: int = 0, *, allow_none: Literal[False] = False
) -> int: ...
@overload
def integer(value: object, name: str, minimum: int = 0, *, allow_none: bool) -> int | None: ...
def integer(value: object, name: str, minimum: int = 0, *, allow_none: bool = False) -> int | None:
    """Check a whole number: a count of iterations, restarts, samples or workers, a chunk size.

    Args:
        value: The argument as given: an ``int`` or numpy integer. A bool, a float (even
            ``3.0``) or a string is refused.
        name: Its name, for the message.
        minimum: The smallest value accepted.
        allow_none: Accept None (returned as it is).

    Returns:
        ``value`` as a Python ``int ≥ minimum``, or None.

    Raises:
        InvalidInput: ``value`` is not such an integer.
    """
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        none = " (or None)" if allow_none else ""
        raise InvalidInput(f"{name} must be an integer ≥ {minimum}{none}, got {value!r}")
    return int(value)


def seed(value: object, name: str = "seed") -> int | None:
    """Check a seed of random choices, ``int | None``.

    An integer ``≥ 0`` gives reproducible choices, None fresh entropy; the callee makes its own
    ``np.random.default_rng(seed)`` or ``np.random.SeedSequence(seed)`` from it.

    Args:
        value: The argument as given. A bool is refused as by :func:`integer` (``seed=True``
            is no seed 1), and so are floats, strings, negative integers and numpy
            ``Generator``/``SeedSequence`` objects (the message says to pass an int).
        name: Its name, for the message.

    Returns:
        ``value`` as an ``int``, or None.

    Raises:
        InvalidInput: ``value`` is not None or an integer ``≥ 0``.
    """
    if value is None:
        return None
    if not isinstance(value, bool) and isinstance(value, (int, np.integer)) and value >= 0:
        return int(value)
    if isinstance(value, np.random.Generator | np.random.SeedSequence | np.random.BitGenerator):
        raise InvalidInput(
            f"{name} must be None or an integer ≥ 0, got a numpy {type(value).__name__}: pass "
            "an int (e.g. int(rng.integers(2**63)) to derive one from a generator)"
        )
    raise InvalidInput(f"{name} must be None or an integer ≥ 0, got {value!r}")


def flag(value: object, name: str) -> bool:
    """Check a switch.

    Args:
        value: The argument as given; a truthy string such as ``"no"`` is refused, not obeyed.
        name: Its name, for the message.

    Returns:
        ``value``, a bool.

    Raises:
        InvalidInput: ``value`` is not a bool.
    """
    if not isinstance(value, bool):
        raise InvalidInput(f"{name} must be True or False, got {value!r}")
    return value


def path(value: object, name: str) -> Path:
    """Check a file-system path.

    Args:
        value: The argument as given: a ``str`` or path-like object.
        name: Its name, for the message.

    Returns:
        ``value`` as a :class:`~pathlib.Path`.

    Raises:
        InvalidInput: ``value`` is neither.
    """
    if not isinstance(value, (str, os.PathLike)):
        raise InvalidInput(f"{name} must be a path (str or os.PathLike), got {value!r}")
    return Path(value)


def real_array(
    value: object, name: str, error: type[InvalidInput] = InvalidInput
) -> NDArray[np.float64]:
    """Check an array of real numbers, of any shape.

    Refuses complex input (which ``np.asarray(…, dtype=float)`` would silently truncate) and
    string, object and ragged input (on which it would fail with a raw numpy error).

    Args:
        value: The argument as given.
        name: Its name, for the message.
        error: The :class:`~redik.core.exceptions.InvalidInput` subclass to raise.

    Returns:
        ``value`` as a float array (``value`` itself when it already is one).

    Raises:
        InvalidInput: ``value`` (as ``error``) does not hold real numbers.
    """
    array = value if isinstance(value, np.ndarray) else None
    if array is None:
        try:
            array = np.asarray(value)
        except (TypeError, ValueError) as exc:
            raise error(f"{name} must be an array of real numbers: {exc}") from None
    if array.dtype.kind not in "biuf":
        raise error(
            f"{name} must hold real numbers, got dtype {array.dtype} "
            f"({np.array2string(array, threshold=12)})"
        )
    return array.astype(float, copy=False)


def as_vector(
    x: object, size: int, name: str, error: type[InvalidInput] = InvalidInput
) -> NDArray[np.float64]:
    """Check a finite real vector of a given length.

    Args:
        x: The argument as given.
        size: The length it must have.
        name: Its name, for the message.
        error: The :class:`~redik.core.exceptions.InvalidInput` subclass to raise.

    Returns:
        ``x`` as a float array of shape ``(size,)``.

    Raises:
        InvalidInput: ``x`` (as ``error``) has another shape, or holds NaN or inf.
    """
    x = real_array(x, name, error)
    if x.shape != (size,):
        raise error(f"{name} must have shape ({size},), got {x.shape}")
    if not np.all(np.isfinite(x)):
        raise error(f"{name} must be finite, holds NaN or inf: {x.tolist()}")
    return x
